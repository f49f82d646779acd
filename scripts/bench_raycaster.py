#!/usr/bin/python3
"""Benchmarks of the ray caster (issue 5): time against error, the warp's cost, sampling
efficiency against the device's ceiling, and VTK's CPU ray caster on the same views.

Usage (from the repository root, after building cvc and cvc_bench):
    /usr/bin/python3 scripts/bench_raycaster.py            # the full run, ~15 min
    /usr/bin/python3 scripts/bench_raycaster.py --quick    # smaller images, fewer points
Writes docs/benchmarks.md and docs/images/bench_*.png. VTK needs python3-vtk9 and xvfb
(xvfb-run); --no-vtk leaves it out. Benchmarks, not tests: CI does not run this.

Every timed point is the median of --runs renders, and the renders of all points of one table
are interleaved (round robin) so that the shared machine's load falls on all of them alike.
"""
import argparse
import json
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

from bench_images import hit_errors, image_errors, read_nrrd, read_png, spacing_of
from bench_raycaster_plots import pareto, plot_pareto, side_by_side

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CT_PATH = os.path.join(ROOT, "..", "shared", "data", "ct", "ts_example_abdomen_3mm.nrrd")


# ---------------------------------------------------------------------------------------------
# Driving cvc
# ---------------------------------------------------------------------------------------------

class Cvc:
    def __init__(self, build):
        self.cvc = os.path.join(build, "app", "cvc")
        self.bench = os.path.join(build, "bench", "cvc_bench")
        for tool in (self.cvc, self.bench):
            if not os.access(tool, os.X_OK):
                sys.exit(f"{tool} is missing: build the cvc and cvc_bench targets first")
        self.device = None

    def run(self, args, tool=None):
        command = [tool or self.cvc] + [str(a) for a in args]
        result = subprocess.run(command, capture_output=True, text=True)
        if result.returncode != 0:
            raise RuntimeError(f"{' '.join(command)} failed ({result.returncode}):\n{result.stdout}{result.stderr}")
        return result.stdout

    def render(self, volume, camera, options, out_png, hits=None, stats=False):
        args = ["render", volume, "--position", camera["position"], "--look-at", camera["look_at"],
                "--up", camera["up"], "--fov", camera["fov"], "--size", camera["size"]] + options
        if hits:
            args += ["--hits", hits]
        if stats:
            args += ["--stats"]
        out = self.run(args + ["--force", "-o", out_png])
        m = re.search(r"on (.*): ray casting ([0-9.eE+-]+) ms, total ([0-9.eE+-]+) s", out)
        if not m:
            raise RuntimeError(f"cannot read the timing of cvc render:\n{out}")
        self.device = m.group(1)
        result = {"device_ms": float(m.group(2)), "total_s": float(m.group(3))}
        m = re.search(r"fetches per ray: mean ([0-9.eE+-]+), max ([0-9.eE+-]+); ([0-9.eE+-]+) fetches per second", out)
        if m:
            result.update(fetches_per_ray=float(m.group(1)), fetches_max=float(m.group(2)),
                          fetches_per_s=float(m.group(3)))
        return result

    def view(self, volume, camera, options):
        """`cvc_bench view`: the median device time of 5 renders after a first one, the eye turned
        0.3 degrees about the focal point before each, as VTK's renders are timed; and the first."""
        side = camera["size"].split("x")[0]
        out = self.run(["view", volume, "--position", camera["position"], "--look-at", camera["look_at"],
                        "--up", camera["up"], "--fov", camera["fov"], "--size", side] + options, tool=self.bench)
        result = json.loads(out.strip().splitlines()[-1])
        return {"median_ms": result["median_ms"], "first_ms": result["first_ms"]}

    def ceiling(self, volume, size, steps, runs):
        out = self.run(["ceiling", volume, "--size", size, "--steps", steps, "--runs", runs], tool=self.bench)
        return json.loads(out[out.index("{"): out.rindex("}") + 1])

    def display(self, volume, camera, display, map_name, out_dir):
        out = self.run(["render", volume, "--display", display, "--position", camera["position"],
                        "--look-at", camera["look_at"], "--up", camera["up"], "--map", map_name,
                        "-o", out_dir, "--force"])
        m = re.search(r"([0-9.eE+-]+) s per frame \(ray casting ([0-9.eE+-]+) ms of device time per stereo frame\)", out)
        if not m:
            raise RuntimeError(f"cannot read the timing of cvc render --display:\n{out}")
        return {"frame_s": float(m.group(1)), "device_ms": float(m.group(2))}


def vec(v):
    return ",".join(f"{x:.3f}" for x in v)


# ---------------------------------------------------------------------------------------------
# Scenes
# ---------------------------------------------------------------------------------------------

def colon_scene(cvc, work, size):
    volume = os.path.join(work, "colon.nrrd")
    cvc.run(["phantom", "-o", volume, "--force"])
    truth = json.load(open(os.path.join(work, "colon.json")))
    line = np.array(truth["centreline_mm"], dtype=np.float64)
    fields, hu = read_nrrd(volume)
    spacing = np.array(spacing_of(fields))

    def clear(i):  # the camera's voxel and its neighbours within 3 voxels are lumen air
        c = np.round(line[i] / spacing).astype(int)
        box = hu[c[2] - 3:c[2] + 4, c[1] - 3:c[1] + 4, c[0] - 3:c[0] + 4]
        return box.size == 343 and bool((box < -900).all())

    # A third of the way along the centreline, or the nearest point after it whose
    # surroundings are air (folds cross the centreline).
    i = next(i for i in range(len(line) // 3, len(line) - 11) if clear(i))
    position, look_at = line[i], line[i + 10]
    forward = look_at - position
    up = np.array([0.0, 0.0, 1.0]) if abs(forward[2]) < 0.9 * np.linalg.norm(forward) else np.array([0.0, 1.0, 0.0])
    return {"name": "colon", "title": "colon phantom (256^3, 0.6 mm), inside view", "volume": volume,
            "spacing": list(spacing), "iso": -500,
            "camera": {"position": vec(position), "look_at": vec(look_at), "up": vec(up), "fov": 90,
                       "size": f"{size}x{size}"},
            "camera_note": f"centreline point {i} of {len(line)}, looking at point {i + 10}"}


def ct_scene(size):
    """An inside view of the air-filled colon of the abdominal CT: the air voxel deepest inside
    the largest air pocket that does not touch the volume's border (so not the air outside the
    patient), looking along its longest free path."""
    from scipy import ndimage
    fields, hu = read_nrrd(CT_PATH)
    spacing = spacing_of(fields)
    air = hu < -900
    labels, count = ndimage.label(air)
    border = np.unique(np.concatenate([labels[[0, -1]].ravel(), labels[:, [0, -1]].ravel(),
                                       labels[:, :, [0, -1]].ravel()]))
    sizes = ndimage.sum(air, labels, range(1, count + 1))
    inner = [c for c in np.argsort(-sizes) + 1 if c not in border]
    pocket = labels == inner[0]
    depth = ndimage.distance_transform_edt(air, sampling=spacing[::-1])
    k, j, i = np.unravel_index(np.argmax(np.where(pocket, depth, 0)), depth.shape)
    start = np.array([i, j, k], dtype=np.float64)
    best = (0.0, None)
    for theta in np.linspace(0.0, np.pi, 19):
        for phi in np.linspace(0.0, 2.0 * np.pi, 36, endpoint=False):
            d = np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])
            length = 0.0
            while True:
                q = np.round(start + d * (length + 0.5)).astype(int)
                if (q < 0).any() or (q >= hu.shape[::-1]).any() or hu[q[2], q[1], q[0]] > -900:
                    break
                length += 0.5
            if length > best[0]:
                best = (length, d)
    position = start * spacing
    look_at = (start + best[1] * 10.0) * spacing
    up = np.array([0.0, 0.0, 1.0]) if abs(best[1][2]) < 0.9 else np.array([0.0, 1.0, 0.0])
    return {"name": "ct", "title": "abdominal CT (122x101x112, 3 mm), inside the air-filled colon",
            "volume": CT_PATH, "spacing": spacing, "iso": -500,
            "camera": {"position": vec(position), "look_at": vec(look_at), "up": vec(up), "fov": 90,
                       "size": f"{size}x{size}"},
            "camera_note": (f"deepest air voxel ({i}, {j}, {k}) of the largest inner air pocket "
                            f"({int(pocket.sum())} voxels, {depth[k, j, i]:.1f} mm from tissue), looking "
                            f"along its longest free path ({best[0] * spacing[0]:.0f} mm)")}


# ---------------------------------------------------------------------------------------------
# Sweeps
# ---------------------------------------------------------------------------------------------

NOTES_MARKER = "<!-- Hand-written discussion: bench_raycaster.py keeps everything from this line on. -->"
REFERENCE = {"step": 0.1, "filter": "tricubic", "refine": 12, "skip": True, "adaptive": False}


def sweep_configs(mode, quick):
    steps = [0.25, 0.5, 1.0, 2.0] if not quick else [0.5, 1.0, 2.0]
    configs = []
    for filt in ("trilinear", "tricubic"):
        for step in (steps if filt == "trilinear" else steps[-3:]):
            configs.append({"step": step, "filter": filt, "refine": 6, "skip": True, "adaptive": False})
    for step in steps:
        configs.append({"step": step, "filter": "trilinear", "refine": 6, "skip": False, "adaptive": False})
    for step in [0.5, 1.0]:
        configs.append({"step": step, "filter": "trilinear", "refine": 6, "skip": True, "adaptive": True})
    if mode == "iso":
        for refine in ([0, 2, 12] if not quick else [0, 12]):
            configs.append({"step": 1.0, "filter": "trilinear", "refine": refine, "skip": True, "adaptive": False})
    return configs


def label_of(c, mode):
    text = f"{c['step']:g} vx {'cubic' if c['filter'] == 'tricubic' else 'lin'}"
    if not c["skip"]:
        text += " noskip"
    if c["adaptive"]:
        text += " adapt"
    if mode == "iso" and c["refine"] != 6:
        text += f" r{c['refine']}"
    return text


def options_of(c, mode, iso):
    # Normals from the gradient volume: computed once per volume, as VTK computes its gradients
    # before its first render; the same normals as from the volume's taps but for rounding.
    o = ["--mode", mode, "--step", c["step"], "--filter", c["filter"], "--gradient-volume", "on"]
    if mode == "iso":
        o += ["--iso", iso, "--refine", c["refine"]]
    else:
        o += ["--tf", "colon-wall"]
    if not c["skip"]:
        o += ["--no-skip"]
    if c["adaptive"]:
        o += ["--adaptive"]
    return o


def run_sweep(cvc, scene, mode, configs, runs, work, log):
    tag = f"{scene['name']}_{mode}"
    ref_png = os.path.join(work, f"{tag}_ref.png")
    ref_hits = os.path.join(work, f"{tag}_ref_hits.nrrd")
    log(f"[{tag}] reference (step {REFERENCE['step']} vx, tricubic, refine 12)")
    reference = cvc.render(scene["volume"], scene["camera"], options_of(REFERENCE, mode, scene["iso"]),
                           ref_png, hits=ref_hits)
    # The B-spline filter smooths (it does not interpolate the voxels), so trilinear renders
    # converge to a different image: their error is also given against a trilinear reference.
    lin_png = os.path.join(work, f"{tag}_ref_lin.png")
    lin_hits = os.path.join(work, f"{tag}_ref_lin_hits.nrrd")
    log(f"[{tag}] trilinear reference (step {REFERENCE['step']} vx, trilinear, refine 12)")
    cvc.render(scene["volume"], scene["camera"], options_of(dict(REFERENCE, filter="trilinear"), mode, scene["iso"]),
               lin_png, hits=lin_hits)
    points = [dict(c, label=label_of(c, mode), times=[], first_times=[]) for c in configs]
    for n, p in enumerate(points):  # the images and hits (renders are deterministic: once is enough)
        cvc.render(scene["volume"], scene["camera"], options_of(p, mode, scene["iso"]),
                   os.path.join(work, f"{tag}_{n}.png"), hits=os.path.join(work, f"{tag}_{n}_hits.nrrd"))
    for r in range(runs):
        log(f"[{tag}] round {r + 1}/{runs} of {len(points)} points")
        for p in points:
            timed = cvc.view(scene["volume"], scene["camera"], options_of(p, mode, scene["iso"]))
            p["times"].append(timed["median_ms"])
            p["first_times"].append(timed["first_ms"])
    for n, p in enumerate(points):
        p["png"], p["hits"] = os.path.join(work, f"{tag}_{n}.png"), os.path.join(work, f"{tag}_{n}_hits.nrrd")
        p["ms"] = statistics.median(p["times"])
        p["first_ms"] = statistics.median(p["first_times"])
        p.update(image_errors(os.path.join(work, f"{tag}_{n}.png"), ref_png))
        p.update(hit_errors(os.path.join(work, f"{tag}_{n}_hits.nrrd"), ref_hits))
        lin = image_errors(os.path.join(work, f"{tag}_{n}.png"), lin_png)
        p.update(rmse_lin=lin["rmse"], ssim_lin=lin["ssim"],
                 hit_lin_mm=hit_errors(os.path.join(work, f"{tag}_{n}_hits.nrrd"), lin_hits)["hit_mean_mm"])
    between = image_errors(lin_png, ref_png)
    return {"reference_ms": reference["device_ms"], "reference_png": ref_png, "lin_reference_png": lin_png,
            "lin_vs_cubic": between, "points": points}


# ---------------------------------------------------------------------------------------------
# VTK (scripts/bench_vtk_worker.py, in its own process under xvfb-run)
# ---------------------------------------------------------------------------------------------

def run_vtk(scene, modes, steps, runs, work, log, ours):
    if shutil.which("xvfb-run") is None:
        log("VTK: xvfb-run is missing (apt-get install xvfb); left out")
        return None
    tasks = []
    for mode in modes:
        for step in [0.1] + steps:
            tasks.append({"mode": mode, "iso": scene["iso"], "step": step, "step_mm": step * min(scene["spacing"]),
                          "runs": 1 if step == 0.1 else runs,
                          "png": os.path.join(work, f"vtk_{scene['name']}_{mode}_{step:g}.png")})
    job = {"volume": scene["volume"], "camera": scene["camera"], "threads": os.cpu_count() or 2, "tasks": tasks,
           "result": os.path.join(work, f"vtk_{scene['name']}.json")}
    job_path = os.path.join(work, f"vtk_{scene['name']}_job.json")
    json.dump(job, open(job_path, "w"))
    log(f"[vtk {scene['name']}] {len(tasks)} views")
    worker = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bench_vtk_worker.py")
    result = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "/usr/bin/python3", worker, job_path],
                            capture_output=True, text=True)
    if result.returncode != 0:
        log(f"VTK failed ({result.returncode}): {result.stderr[-2000:]}")
        return None
    done = json.load(open(job["result"]))
    out = {"version": done["vtk_version"]}
    for mode in modes:
        mode_tasks = [(t, r) for t, r in zip(tasks, done["results"]) if t["mode"] == mode]
        ref_task, ref_result = mode_tasks[0]
        points = []
        for t, r in mode_tasks[1:]:
            p = {"step": t["step"], "ms": statistics.median(r["times_ms"]), "first_s": r["first_s"], "png": t["png"]}
            own = image_errors(t["png"], ref_task["png"])
            vs = image_errors(t["png"], ours[mode]["reference_png"])
            p.update({k + "_vs_vtk": v for k, v in own.items()})
            p.update({k + "_vs_ours": v for k, v in vs.items()})
            points.append(p)
        ref_vs_ours = image_errors(ref_task["png"], ours[mode]["reference_png"])
        out[mode] = {"points": points, "reference_png": ref_task["png"],
                     "reference_ms": statistics.median(ref_result["times_ms"]), "reference_vs_ours": ref_vs_ours}
    return out


# ---------------------------------------------------------------------------------------------
# Warp cost and efficiency
# ---------------------------------------------------------------------------------------------

def warp_cost(cvc, scene, runs, work, log, quick):
    walls = [{"name": n, "width": 700 if not quick else 350, "height": 525 if not quick else 263}
             for n in ("front", "back", "left", "right")] + \
            [{"name": "floor", "width": 525 if not quick else 263, "height": 525 if not quick else 263}]
    display = os.path.join(work, "display_small.json")
    json.dump({"name": "small", "box_size_m": [2.95, 2.21, 2.95], "map": "conformal", "walls": walls},
              open(display, "w"))
    log("[warp] baking or loading the map")
    cvc.display(scene["volume"], scene["camera"], display, "conformal", os.path.join(work, "walls_warm"))
    times = {"conformal": [], "none": []}
    for r in range(runs):
        log(f"[warp] round {r + 1}/{runs}")
        order = ("conformal", "none") if r % 2 == 0 else ("none", "conformal")
        for m in order:
            times[m].append(cvc.display(scene["volume"], scene["camera"], display, m,
                                        os.path.join(work, f"walls_{m}"))["device_ms"])
    ratios = [c / n for c, n in zip(times["conformal"], times["none"])]
    return {"walls": walls, "times": times, "median_conformal": statistics.median(times["conformal"]),
            "median_none": statistics.median(times["none"]), "median_ratio": statistics.median(ratios),
            "ratios": ratios}


def efficiency(cvc, scene, runs, work, log, size):
    configs = [("iso, 0.5 vx trilinear, skipping", ["--mode", "iso", "--step", 0.5]),
               ("iso, 0.5 vx trilinear, no skipping", ["--mode", "iso", "--step", 0.5, "--no-skip"]),
               ("composite, 0.5 vx trilinear, skipping", ["--mode", "composite", "--step", 0.5]),
               ("iso, 0.5 vx tricubic, skipping", ["--mode", "iso", "--step", 0.5, "--filter", "tricubic"])]
    rows = {name: [] for name, _ in configs}
    ceilings = []
    for r in range(runs):
        log(f"[efficiency] round {r + 1}/{runs}")
        ceilings.append(cvc.ceiling(scene["volume"], size, 80, 5))
        for name, options in configs:
            # The fetches per ray from a counting render (a pipeline of its own), the time from
            # warm renders, as in the sweep.
            counted = cvc.render(scene["volume"], scene["camera"], options, os.path.join(work, "scratch.png"),
                                 stats=True)
            timed = cvc.view(scene["volume"], scene["camera"], options)
            rays = float(np.prod([int(n) for n in scene["camera"]["size"].split("x")]))
            rows[name].append({"fetches_per_ray": counted["fetches_per_ray"], "device_ms": timed["median_ms"],
                               "fetches_per_s": counted["fetches_per_ray"] * rays / (1e-3 * timed["median_ms"])})
    ceiling = statistics.median(c["samples_per_second"] for c in ceilings)
    out = {"ceiling_samples_per_s": ceiling, "ceiling_runs": ceilings, "rows": []}
    for name, _ in configs:
        rate = statistics.median(x["fetches_per_s"] for x in rows[name])
        out["rows"].append({"name": name, "fetches_per_s": rate, "fraction": rate / ceiling,
                            "fetches_per_ray": statistics.median(x["fetches_per_ray"] for x in rows[name]),
                            "ms": statistics.median(x["device_ms"] for x in rows[name])})
    return out


# ---------------------------------------------------------------------------------------------
# Report
# ---------------------------------------------------------------------------------------------

def fmt(x, digits=3):
    if isinstance(x, float) and (x != x):
        return "n/a"
    if x == float("inf"):
        return "inf"
    return f"{x:.{digits}f}"


def sweep_table(sweep, mode):
    front = {id(p) for p in pareto(sweep["points"])}
    lines = ["| setting | device ms (median) | RMSE | PSNR dB | SSIM | hit error mean / p95 mm | hit mismatch | Pareto "
             "| vs trilinear ref.: RMSE / SSIM / hit mean mm |",
             "|---|---:|---:|---:|---:|---:|---:|:-:|---:|"]
    for p in sorted(sweep["points"], key=lambda p: p["ms"]):
        lines.append(f"| {p['label']} | {p['ms']:.1f} | {p['rmse']:.4f} | {fmt(p['psnr'], 1)} | {p['ssim']:.4f} | "
                     f"{fmt(p['hit_mean_mm'], 3)} / {fmt(p['hit_p95_mm'], 3)} | {100 * p['hit_mismatch']:.2f} % | "
                     f"{'●' if id(p) in front else ''} | {p['rmse_lin']:.4f} / {p['ssim_lin']:.4f} / "
                     f"{fmt(p['hit_lin_mm'], 3)} |")
    return "\n".join(lines)


def find(points, **kw):
    for p in points:
        if all(p.get(k) == v for k, v in kw.items()):
            return p
    return None


def image_difference(p, q):
    """How two renders of the sweep differ: pixels, the largest colour difference, rays that hit in
    one and miss in the other, and the largest distance between hits of rays that hit in both."""
    if "png" not in p or "png" not in q or not os.path.exists(p["png"]) or not os.path.exists(q["png"]):
        return {"pixels": "n/a", "max_levels": "n/a", "flips": "n/a", "max_shift_mm": float("nan")}
    d = np.abs(read_png(p["png"]) - read_png(q["png"])).max(axis=2)
    _, h = read_nrrd(p["hits"])
    _, g = read_nrrd(q["hits"])
    h, g = h.reshape(-1, 4), g.reshape(-1, 4)
    both = (h[:, 3] > 0.5) & (g[:, 3] > 0.5)
    shift = np.linalg.norm(h[both, :3] - g[both, :3], axis=1)
    return {"pixels": int((d > 0).sum()), "max_levels": int(round(d.max() * 255)),
            "flips": int(((h[:, 3] > 0.5) != (g[:, 3] > 0.5)).sum()),
            "max_shift_mm": float(shift.max()) if shift.size else 0.0}


def skip_rows(results):
    lines = ["| scene, mode | step | skipping ms | no skipping ms | ratio (no skip / skip) | pixels that differ "
             "(max, 8-bit levels) | hit / miss flips | largest hit shift mm |", "|---|---:|---:|---:|---:|---:|---:|---:|"]
    ratios = {}
    for scene_name, sweeps in results.items():
        for mode, sweep in sweeps.items():
            for p in sweep["points"]:
                if not p["skip"]:
                    q = find(sweep["points"], step=p["step"], filter="trilinear", skip=True, adaptive=False, refine=6)
                    if q:
                        ratio = p["ms"] / q["ms"]
                        ratios[(scene_name, mode, p["step"])] = ratio
                        d = image_difference(q, p)
                        lines.append(f"| {scene_name}, {mode} | {p['step']:g} vx | {q['ms']:.1f} | {p['ms']:.1f} | "
                                     f"{ratio:.2f}x | {d['pixels']} ({d['max_levels']}) | {d['flips']} | "
                                     f"{d['max_shift_mm']:.2f} |")
    return "\n".join(lines), ratios


def write_report(path, meta, scenes, results, warp, eff, vtk, args):
    L = []
    add = L.append
    add("# Benchmarks of the ray caster\n")
    add("Issue 5's benchmarks: time against error, the warp's cost, sampling efficiency against the device's "
        "ceiling, and VTK's CPU ray caster on the same views. Generated by "
        f"`{meta['command']}` on {meta['date']} (commit `{meta['commit']}`); every number below is from that one "
        "run.\n")
    add("## Machine\n")
    add(f"- Device: **{meta['device']}** (Mesa lavapipe: Vulkan on the CPU), {meta['cores']} cores, "
        f"{meta['cpu']}; {meta['os']}.")
    add(f"- Load average (1 min) at the start {meta['load_start']}, at the end {meta['load_end']}: the machine is "
        "shared with other builds, so absolute times are noisy. Each timed point is the median of "
        f"{args.runs} renders, and the renders of all points of a table alternate (round robin), so ratios within a "
        "table are fairer than the absolute numbers.")
    add(f"- Whole run: {meta['elapsed_min']:.1f} min.\n")
    add("## How\n")
    add("- Regenerate with `/usr/bin/python3 scripts/bench_raycaster.py` (about 11 minutes here; `--quick` for a "
        "3-minute version at 256², `--no-vtk` without VTK, `--work DIR` to keep the images and `results.json`, "
        "`--report-only --work DIR` to rewrite this file and the plots from a kept run). It needs the `cvc` and "
        "`cvc_bench` targets built in `build/`, Debian's python3-numpy, -scipy, -matplotlib, -pil, and for VTK "
        "python3-vtk9 and xvfb.")
    add("- Times are the **device time of the ray-casting dispatch** (Vulkan timestamps); they leave out "
        "loading, upload, pipeline creation and the PNG. Each point's time is `cvc_bench view`'s: the median of "
        "5 renders after a first one, the eye turned 0.3 degrees about the focal point before each, as VTK's "
        "renders are timed (`results.json` keeps the first renders' times too). The images and hits come from "
        "`cvc render` with the same options. Shading normals (a still's default, B-spline) are read from the "
        "gradient volume (`--gradient-volume on`), computed once per volume as VTK computes its gradients "
        "before its first render.")
    add(f"- Images are {args.size}x{args.size}, vertical field of view 90 degrees. The reference image of each "
        "scene and mode: step 0.1 voxel, tricubic B-spline filter, 12 bisection steps (iso mode), skipping on "
        "(skipping does not change the image: see the table).")
    add("- Errors against the reference: RMSE and PSNR of the 8-bit RGB images scaled to [0, 1]; SSIM (Wang et al. "
        "2004, Gaussian window sigma 1.5) of the luma; and, from `--hits`, the distance between the first-hit "
        "positions of the two images where both rays hit (mean and 95th percentile, mm) plus the fraction of pixels "
        "where only one of them hits. In composite mode the hit is where opacity first reaches 0.5.")
    add("- Settings swept: step (voxels), filter (trilinear `lin`, tricubic `cubic`), empty-space skipping "
        "(`noskip` = off), adaptive step (`adapt`), and in iso mode the bisection steps (`rN`; rows without it use 6). "
        "The composite mode's early-termination threshold is not a `cvc render` option (fixed at 0.98), so it "
        "is **not swept**.")
    add("- Commands (per point): the image, `build/app/cvc render VOLUME --position P --look-at A --up U --fov 90 "
        f"--size {args.size}x{args.size} --mode iso|composite [--iso -500 --refine N | --tf colon-wall] --step S "
        "--filter F --gradient-volume on [--no-skip] [--adaptive] [--hits H.nrrd] --force -o OUT.png`; the time, "
        f"`build/bench/cvc_bench view VOLUME` with the same camera, `--size {args.size}` and the same options "
        "but for the output.\n")
    add("## Scenes\n")
    for s in scenes:
        c = s["camera"]
        add(f"- **{s['name']}**: {s['title']}. Camera at {c['position']} mm looking at {c['look_at']} mm, up "
            f"{c['up']} ({s['camera_note']}). Iso value {s['iso']} HU; composite mode uses the `colon-wall` "
            "transfer function.")
    add("")
    add("## Time against error\n")
    for s in scenes:
        if s["name"] not in results:
            continue
        add(f"### {s['title']}\n")
        add(f"![Pareto {s['name']}](images/bench_pareto_{s['name']}.png)\n")
        for mode in ("iso", "composite"):
            sw = results[s["name"]][mode]
            b = sw["lin_vs_cubic"]
            add(f"**{mode} mode** (reference: {sw['reference_ms']:.0f} ms, one render; the trilinear reference "
                f"differs from it by RMSE {b['rmse']:.4f}, SSIM {b['ssim']:.4f}, what a converged trilinear image keeps"
                ")\n")
            add(sweep_table(sw, mode))
            add("")
    table, ratios = skip_rows(results)
    add("### Empty-space skipping\n")
    add("Same settings with and without skipping (trilinear, no adaptive step), medians from the sweeps above, "
        "and how far the two images differ (skipping is meant to leave the image unchanged):\n")
    add(table)
    add("")
    if warp:
        add("## The warp's cost\n")
        add(f"The same 5 walls x 2 eyes (front, back, left, right {warp['walls'][0]['width']}x"
            f"{warp['walls'][0]['height']}, floor {warp['walls'][-1]['width']}x{warp['walls'][-1]['height']}), "
            "from the colon scene's camera, iso mode and default settings, with the conformal map "
            "(`--map conformal`, chord mode: each ray's near and far points are mapped through the cube map) and "
            f"without (`--map none`), alternating, {len(warp['ratios'])} runs each. Device time per stereo frame:\n")
        add("| map | device ms per stereo frame (median) | runs |")
        add("|---|---:|---|")
        add(f"| conformal | {warp['median_conformal']:.1f} | {', '.join(f'{t:.0f}' for t in warp['times']['conformal'])} |")
        add(f"| none | {warp['median_none']:.1f} | {', '.join(f'{t:.0f}' for t in warp['times']['none'])} |")
        add(f"\nMedian of the paired ratios (conformal / none): **{warp['median_ratio']:.3f}** "
            f"({100 * (warp['median_ratio'] - 1):+.1f} %); pairs: {', '.join(f'{r:.3f}' for r in warp['ratios'])}. "
            "Note that the warped rays do not see the same scene as the straight ones (the map bends them to "
            "other parts of the colon), so part of any difference is a different amount of work per ray, not "
            "the cost of the map fetches. And each run renders one frame, the first of its process: with the "
            "map that frame also fills the chord tables, which every later frame of a fly-through only reads. "
            "The warp's own cost (an identity cube map against no map: the same rays) is measured below, in "
            "\"The warp's own cost\" sections.\n")
    if eff:
        add("## Efficiency: fetches per second against the ceiling\n")
        add(f"`cvc_bench ceiling` (plain trilinear sampling of the same volume, {args.size}^2 rays x 80 steps) "
            f"and `cvc render --stats`, alternating, {len(eff['ceiling_runs'])} rounds, colon scene. Ceiling "
            f"(median): **{eff['ceiling_samples_per_s'] / 1e6:.0f} M samples/s** "
            "(runs: " + ", ".join(f"{c['samples_per_second'] / 1e6:.0f}" for c in eff["ceiling_runs"]) + " M/s).\n")
        add("| render | device ms | fetches per ray (mean) | fetches/s (median) | fraction of ceiling |")
        add("|---|---:|---:|---:|---:|")
        for r in eff["rows"]:
            add(f"| {r['name']} | {r['ms']:.1f} | {r['fetches_per_ray']:.1f} | {r['fetches_per_s'] / 1e6:.0f} M | "
                f"{100 * r['fraction']:.0f} % |")
        add("\nA fetch is one trilinear volume texture read (a tricubic sample is 8, a gradient 6 samples); "
            "brick-occupancy, transfer-function and cube-map reads are not counted.\n")
    if vtk:
        add("## Against VTK\n")
        add(f"VTK {next(iter(vtk.values()))['version']} (Debian python3-vtk9), `vtkFixedPointVolumeRayCastMapper` "
            f"(CPU, {os.cpu_count()} threads), offscreen under `xvfb-run`, on the same volume (int16 "
            "vtkImageData with our spacing and origin 0, so VTK's world coordinates are our volume millimetres), "
            "the same camera (position, focal point, view up, view angle 90 degrees = our vertical field of view), "
            "the same image size and the same sample distance (step x smallest spacing, in mm; automatic "
            "adjustment off, image sample distance 1). Composite mode uses our `colon-wall` transfer function "
            "(opacity unit distance 1 mm, as ours); the fixed-point mapper has no iso-surface mode, so iso "
            "mode is imitated by an opacity ramp from 0 to 1 within 30 HU of the iso value. Shading: VTK's "
            "Phong with its headlight (ambient 0.1, diffuse 0.9, specular 0.2, power 20) against our "
            "Cook-Torrance, so the images differ in shading even at a tiny step; VTK's output gets our 2.2 "
            "gamma after the timed renders. VTK's time is the wall time of `Render()` (median of "
            f"{args.runs}, after one untimed render that builds its gradient and space-leaping tables); ours is "
            "the device time of the dispatch.\n")
        add("Error is given twice: against **our** reference (the cross-renderer difference, dominated by the "
            "shading and classification differences) and against **VTK's own** reference at 0.1 voxel "
            "(how far VTK is from converged, comparable with our error against our reference).\n")
        for s in scenes:
            if s["name"] not in vtk:
                continue
            v = vtk[s["name"]]
            add(f"### {s['title']}\n")
            add(f"![VTK side by side {s['name']}](images/bench_vtk_{s['name']}.png)\n")
            add("| mode | step | ours ms | ours RMSE / SSIM (vs our ref.) | VTK ms | VTK first render s | "
                "VTK RMSE / SSIM vs VTK ref. | VTK RMSE / SSIM vs our ref. | time VTK / ours |")
            add("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
            for mode in ("iso", "composite"):
                if mode not in v:
                    continue
                for p in v[mode]["points"]:
                    o = find(results[s["name"]][mode]["points"], step=p["step"], filter="trilinear", skip=True,
                             adaptive=False, refine=6)
                    if not o:
                        continue
                    add(f"| {mode} | {p['step']:g} vx | {o['ms']:.1f} | {o['rmse']:.4f} / {o['ssim']:.3f} | "
                        f"{p['ms']:.0f} | {p['first_s']:.1f} | {p['rmse_vs_vtk']:.4f} / {p['ssim_vs_vtk']:.3f} | "
                        f"{p['rmse_vs_ours']:.4f} / {p['ssim_vs_ours']:.3f} | {p['ms'] / o['ms']:.1f}x |")
                r = v[mode]["reference_vs_ours"]
                add(f"| {mode} | VTK 0.1 vx ref. vs our ref. | | | {v[mode]['reference_ms']:.0f} | | | "
                    f"{r['rmse']:.4f} / {r['ssim']:.3f} | |")
            add("")
    if vtk:
        add("### At equal error\n")
        add("Each renderer's error against its own converged image (VTK against VTK at 0.1 voxel; our trilinear "
            "settings against our trilinear 0.1-voxel image, our tricubic ones against the tricubic reference), "
            "and for each VTK point our fastest setting with no larger error:\n")
        add("| scene, mode | VTK step | VTK ms | VTK RMSE (own) | our setting | our ms | our RMSE (own) | ours / VTK time |")
        add("|---|---:|---:|---:|---|---:|---:|---:|")
        for scene_name, mode, p, q in equal_error_rows(results, vtk):
            if q:
                add(f"| {scene_name}, {mode} | {p['step']:g} vx | {p['ms']:.0f} | {p['rmse_vs_vtk']:.4f} | {q['label']} | "
                    f"{q['ms']:.0f} | {own_error(q):.4f} | {q['ms'] / p['ms']:.1f}x |")
            else:
                add(f"| {scene_name}, {mode} | {p['step']:g} vx | {p['ms']:.0f} | {p['rmse_vs_vtk']:.4f} | none as good | | | |")
        add("")
    add("## Conclusions against the targets\n")
    add(meta.get("conclusions", "(see the numbers above)"))
    add("")
    # A hand-written discussion below the marker survives regeneration.
    kept = ""
    if os.path.exists(path):
        text = open(path).read()
        if NOTES_MARKER in text:
            kept = text[text.index(NOTES_MARKER):]
    open(path, "w").write("\n".join(L) + ("\n" + kept if kept else ""))


def verdict_of(passed, total):
    return "met" if passed == total else ("not met" if passed == 0 else f"met in {passed} of {total} cases")


def own_error(p):
    """A point's distance from its own filter's converged image: trilinear points against the
    trilinear reference, tricubic ones against the tricubic reference (as VTK's against VTK's)."""
    return p["rmse_lin"] if p["filter"] == "trilinear" else p["rmse"]


def equal_error_rows(results, vtk):
    """For each VTK point: our fastest setting whose own error is at most VTK's own error."""
    rows = []
    for scene_name, v in vtk.items():
        for mode in ("iso", "composite"):
            if mode not in v:
                continue
            for p in v[mode]["points"]:
                good = [q for q in results[scene_name][mode]["points"] if own_error(q) <= p["rmse_vs_vtk"]]
                best = min(good, key=lambda q: q["ms"]) if good else None
                rows.append((scene_name, mode, p, best))
    return rows


def conclusions(results, warp, eff, vtk, ratios):
    out = []
    if warp:
        pct = 100 * (warp["median_ratio"] - 1)
        out.append(f"- **First display frame through the map, against none: {pct:+.1f} %** (median of paired "
                   f"ratios; the pairs range {100 * (min(warp['ratios']) - 1):+.1f} to "
                   f"{100 * (max(warp['ratios']) - 1):+.1f} %): a different scene, and the chord tables filled in "
                   "the timed frame. The warp's own cost on later frames is measured below.")
    inside = [(k, r) for k, r in ratios.items() if k[2] == 0.5]
    if inside:
        parts = ", ".join(f"{k[0]} {k[1]} {r:.2f}x" for k, r in inside)
        out.append(f"- **Skipping halves the inside-colon time: "
                   f"{verdict_of(sum(r >= 2.0 for _, r in inside), len(inside))}**. At 0.5 voxel, "
                   f"no-skip / skip time: {parts} (>= 2.00x means halved).")
    if eff:
        parts = ", ".join(f"{r['name']}: {100 * r['fraction']:.0f} %" for r in eff["rows"])
        out.append(f"- **Efficiency**: fetches per second as a fraction of the plain-trilinear ceiling "
                   f"({eff['ceiling_samples_per_s'] / 1e6:.0f} M/s): {parts}.")
    if vtk:
        parts = []
        for scene_name, v in vtk.items():
            for mode in ("iso", "composite"):
                if mode not in v:
                    continue
                for p in v[mode]["points"]:
                    o = find(results[scene_name][mode]["points"], step=p["step"], filter="trilinear", skip=True,
                             adaptive=False, refine=6)
                    if o:
                        parts.append((scene_name, mode, p["step"], p["ms"] / o["ms"], own_error(o), p["rmse_vs_vtk"]))
        eq = [r for r in equal_error_rows(results, vtk) if r[3]]
        if eq:
            wins = sum(1 for r in eq if r[3]["ms"] < r[2]["ms"])
            spread = [r[3]["ms"] / r[2]["ms"] for r in eq]
            out.append(f"- **Faster than VTK's CPU ray caster at equal error: "
                       f"{'met' if wins == len(eq) else 'not met'}**. Matching each VTK point with our fastest "
                       f"setting of no larger error (each renderer against its own converged image), ours was "
                       f"faster in {wins} of {len(eq)} cases; our time / VTK's time ranged "
                       f"{min(spread):.1f}x to {max(spread):.1f}x (median {statistics.median(spread):.1f}x). "
                       "See the equal-error table.")
        if parts:
            faster = sum(1 for x in parts if x[3] > 1.0)
            text = "; ".join(f"{a} {b} {c:g} vx: {d:.1f}x (RMSE ours {e:.3f}, VTK {f:.3f})" for a, b, c, d, e, f in parts)
            out.append(f"- At the **same sample distance**, ours was "
                       f"faster in {faster} of {len(parts)} cases. Time VTK / ours (and each one's RMSE against its "
                       f"own reference): {text}. Equal sample distance is the nearest thing to equal error here, "
                       "since the two renderers converge to different images.")
    return "\n".join(out)


# ---------------------------------------------------------------------------------------------

def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="256x256 images, fewer points, 2 runs")
    parser.add_argument("--size", type=int, default=None, help="image side (default 512, quick 256)")
    parser.add_argument("--runs", type=int, default=None, help="renders per timed point (default 3, quick 2)")
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--docs", default=os.path.join(ROOT, "docs"))
    parser.add_argument("--work", default=None, help="keep the images here (default: a temporary folder)")
    parser.add_argument("--no-vtk", action="store_true")
    parser.add_argument("--only", default=None, help="comma list of parts: sweep,warp,efficiency,vtk")
    parser.add_argument("--report-only", action="store_true",
                        help="rewrite the report and plots from --work's results.json without rendering")
    args = parser.parse_args()
    args.size = args.size or (256 if args.quick else 512)
    args.runs = args.runs or (2 if args.quick else 3)
    parts = set((args.only or "sweep,warp,efficiency,vtk").split(","))
    if args.no_vtk:
        parts.discard("vtk")

    started = time.time()

    def log(message):
        print(f"{time.time() - started:7.1f} s  {message}", flush=True)

    work = args.work or tempfile.mkdtemp(prefix="cvc_bench_")
    os.makedirs(work, exist_ok=True)
    images = os.path.join(args.docs, "images")
    os.makedirs(images, exist_ok=True)
    cvc = Cvc(args.build)
    load_start = os.getloadavg()[0]

    scenes = [colon_scene(cvc, work, args.size), ct_scene(args.size)]
    for s in scenes:
        log(f"scene {s['name']}: {s['camera']} ({s['camera_note']})")
    if args.report_only:
        saved = json.load(open(os.path.join(work, "results.json")))
        report(args, saved["meta"], scenes, saved["results"], saved["warp"], saved["efficiency"], saved["vtk"],
               images, work, log)
        return

    results = {}
    if "sweep" in parts:
        for s in scenes:
            results[s["name"]] = {}
            for mode in ("iso", "composite"):
                results[s["name"]][mode] = run_sweep(cvc, s, mode, sweep_configs(mode, args.quick), args.runs,
                                                     work, log)
    warp = warp_cost(cvc, scenes[0], 3 if args.quick else 5, work, log, args.quick) if "warp" in parts else None
    eff = efficiency(cvc, scenes[0], args.runs, work, log, args.size) if "efficiency" in parts else None
    vtk = {}
    if "vtk" in parts and "sweep" in parts:
        for s in scenes:
            v = run_vtk(s, ["iso", "composite"], [0.5, 1.0, 2.0] if not args.quick else [0.5, 1.0], args.runs,
                        work, log, results[s["name"]])
            if v:
                vtk[s["name"]] = v

    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    cpu = "unknown CPU"
    try:
        cpu = next(l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    meta = {"command": "/usr/bin/python3 scripts/bench_raycaster.py" + (" --quick" if args.quick else "") +
                       (f" --size {args.size}" if args.size not in (256, 512) else ""),
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "commit": commit,
            "device": cvc.device or "unknown", "cores": os.cpu_count(), "cpu": cpu,
            "os": platform.platform(), "load_start": f"{load_start:.1f}", "load_end": f"{os.getloadavg()[0]:.1f}",
            "elapsed_min": (time.time() - started) / 60.0, "size": args.size, "runs": args.runs}
    json.dump({"meta": meta, "results": results, "warp": warp, "efficiency": eff, "vtk": vtk},
              open(os.path.join(work, "results.json"), "w"), indent=1)
    report(args, meta, scenes, results, warp, eff, vtk, images, work, log)


def report(args, meta, scenes, results, warp, eff, vtk, images, work, log):
    for scene_name, sweeps in results.items():
        for mode, sweep in sweeps.items():
            for n, p in enumerate(sweep["points"]):
                p.setdefault("png", os.path.join(work, f"{scene_name}_{mode}_{n}.png"))
                p.setdefault("hits", os.path.join(work, f"{scene_name}_{mode}_{n}_hits.nrrd"))
    args.size = meta.get("size", args.size)
    args.runs = meta.get("runs", args.runs)
    for s in scenes:
        if s["name"] in vtk:
            side_by_side(s, results[s["name"]], vtk[s["name"]], work, os.path.join(images, f"bench_vtk_{s['name']}.png"))
    for s in scenes:
        if s["name"] in results:
            plot_pareto(s, results[s["name"]], vtk.get(s["name"]), os.path.join(images, f"bench_pareto_{s['name']}.png"))
    _, ratios = skip_rows(results)
    meta = dict(meta, conclusions=conclusions(results, warp, eff, vtk, ratios))
    write_report(os.path.join(args.docs, "benchmarks.md"), meta, scenes, results, warp, eff, vtk, args)
    log(f"wrote {os.path.join(args.docs, 'benchmarks.md')} (raw results in {work}/results.json)")


if __name__ == "__main__":
    main()
