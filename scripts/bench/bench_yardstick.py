#!/usr/bin/python3
"""The iso target on VTK's yardstick, time and error in one run.

The target: on the yardstick's view (../shared/bench/vtk: its 512x512x451 colon phantom, inside
camera, 1024^2, iso -500 HU, 0.5-voxel step) ray casting takes at most 0.5x VTK's time, at no
larger error against each renderer's own converged image.

Usage (from the repository root, after building cvc and cvc_bench):
    /usr/bin/python3 scripts/bench/bench_yardstick.py [--rounds 5] [--out out/bench_yardstick] [--composite]

1. Time. Each round runs VTK's render.py (the median of 5 renders after a first one, the camera
   turned 0.3 degrees about the focal point before each) and then, by the same protocol,
   `cvc_bench view` for each cvc variant below. Reported: medians, and the median over rounds
   of each variant's time divided by VTK's in the same round.
2. Error. Once, after the rounds: each renderer's image at the 0.5-voxel step and its converged
   image at a 0.1-voxel step (VTK: sample distance 0.1 voxel; cvc: step 0.1 voxel, 12 bisection
   steps, the variant's own normals). Each 0.5-voxel image is compared with its own renderer's
   converged image (RMSE, PSNR, SSIM). (The two renderers' images are not compared with each
   other: they shade differently, VTK its iso-like opacity ramp with its own light and colours,
   cvc the iso surface with a headlight, Cook-Torrance and a mucosa tone.)

cvc variants: central-difference normals (6 fetches per shaded sample), the same read from the
gradient volume (a display frame's default), B-spline normals (48 fetches), the same read from
the gradient volume (8 fetches), and the B-spline's values at the voxels read from the gradient
volume (a still's default: 1 fetch).
Needs python3-vtk9, python3-numpy, python3-pil and xvfb. A benchmark, not a test.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

from bench_images import image_errors, read_png
from bench_scenes import camera_options

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
VTK_DIR = os.path.join(ROOT, "..", "shared", "bench", "vtk")
VARIANTS = {
    "central": ["--gradient", "central", "--gradient-volume", "off"],
    "central, gradient volume (a display frame's default)": ["--gradient", "central", "--gradient-volume", "on"],
    "B-spline": ["--gradient", "bspline", "--gradient-volume", "off"],
    "B-spline, gradient volume": ["--gradient", "bspline", "--gradient-volume", "on"],
    "B-spline at the voxels, gradient volume (a still's default)": ["--gradient", "bspline-voxels",
                                                                    "--gradient-volume", "on"],
}
# Composite mode (--composite): the colon-wall transfer function given to both, VTK through
# bench_vtk_worker.py (as bench_march.sh runs it), ours for the two defaults.
COMPOSITE_VARIANTS = {
    "central, gradient volume (a display frame's default)": ["--gradient", "central", "--gradient-volume", "on"],
    "B-spline at the voxels, gradient volume (a still's default)": ["--gradient", "bspline-voxels",
                                                                    "--gradient-volume", "on"],
}
STEP, CONVERGED_STEP = 0.5, 0.1


def run(command):
    result = subprocess.run([str(c) for c in command], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"{' '.join(map(str, command))} failed ({result.returncode}):\n{result.stderr[-2000:]}")
    return result.stdout


def vtk_view(out, sample_distance, png, repeats):
    """VTK's seconds (median after the first render, and the first) for the yardstick's view."""
    line = run(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "/usr/bin/python3", os.path.join(VTK_DIR, "render.py"),
                "--volume", os.path.join(out, "phantom512.mhd"), "--mapper", "cpu", "--mode", "iso",
                "--camera-json", os.path.join(out, "phantom512.json"), "--camera", "inside",
                "--width", 1024, "--height", 1024, "--sample-distance", sample_distance, "--png", png,
                "--repeats", repeats]).strip().splitlines()[-1]
    # A volume VTK cannot find renders as empty space, quickly: a black image stops the run.
    if read_png(png).max() == 0:
        sys.exit(f"VTK's image {png} is black: is {out}/phantom512.raw readable?")
    result = json.loads(line)
    return result["median_s"], result["first_s"]


def cvc_warm_ms(out, camera, options):
    """cvc_bench view: the median milliseconds of 5 renders after the first, and the first's."""
    result = json.loads(run([os.path.join(ROOT, "build", "bench", "cvc_bench"), "view",
                             os.path.join(out, "phantom512.mhd")] + camera + ["--size", 1024, "--step", STEP] + options))
    return result["median_ms"], result["first_ms"]


def yardstick_nrrd(out):
    """The yardstick's volume as NRRD too (the VTK worker reads NRRD): a header before the raw data."""
    path = os.path.join(out, "phantom512.nrrd")
    if not os.path.exists(path):
        with open(path, "wb") as nrrd, open(os.path.join(out, "phantom512.raw"), "rb") as raw:
            nrrd.write(b"NRRD0004\ntype: short\ndimension: 3\nsizes: 512 512 451\nspacings: 0.7 0.7 0.8\n"
                       b"encoding: raw\nendian: little\n\n")
            nrrd.write(raw.read())
    return path


def vtk_composite_ms(out, camera):
    """VTK's median milliseconds of 3 composite renders after the first (colon-wall, 0.5 voxel)."""
    option = dict(zip(camera[0::2], camera[1::2]))
    job = {"volume": yardstick_nrrd(out), "threads": os.cpu_count(),
           "camera": {"position": option["--position"], "look_at": option["--look-at"], "up": option["--up"],
                      "fov": float(option["--fov"]), "size": "1024x1024"},
           "tasks": [{"mode": "composite", "iso": -500, "step": STEP, "step_mm": 0.35, "runs": 3,
                      "png": os.path.join(out, "vtk_composite.png")}],
           "result": os.path.join(out, "vtk_composite.json")}
    with open(os.path.join(out, "vtk_composite_job.json"), "w") as f:
        json.dump(job, f)
    run(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "/usr/bin/python3",
         os.path.join(ROOT, "scripts", "bench", "bench_vtk_worker.py"), os.path.join(out, "vtk_composite_job.json")])
    return statistics.median(json.load(open(job["result"]))["results"][0]["times_ms"])


def cvc_image(out, camera, options, step, refine, png):
    run([os.path.join(ROOT, "build", "app", "cvc"), "render", os.path.join(out, "phantom512.mhd")] + camera +
        ["--size", "1024x1024", "--iso", -500, "--step", step, "--refine", refine, "--force", "-o", png] + options)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--composite", action="store_true",
                        help="also composite mode (colon-wall), paired with VTK's per round")
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "bench_yardstick"))
    args = parser.parse_args()
    if not 1 <= args.rounds <= 100:
        sys.exit("--rounds must be 1 to 100")
    out = os.path.abspath(args.out)  # the MetaImage header names its data file by this path
    os.makedirs(out, exist_ok=True)
    if not os.path.exists(os.path.join(out, "phantom512.mhd")):
        run(["/usr/bin/python3", os.path.join(VTK_DIR, "make_phantom.py"), "--out", os.path.join(out, "phantom512")])
    camera = camera_options("yardstick_camera")
    print(f"machine: {os.cpu_count()} cores, load average at the start {os.getloadavg()[0]:.2f}")

    vtk_s, vtk_first_s = [], []
    ours = {name: {"ms": [], "first_ms": []} for name in VARIANTS}
    vtk_composite, composite = [], {name: [] for name in COMPOSITE_VARIANTS}
    for r in range(args.rounds):
        median_s, first_s = vtk_view(out, STEP, os.path.join(out, "vtk.png"), 5)
        vtk_s.append(median_s)
        vtk_first_s.append(first_s)
        for name, options in VARIANTS.items():
            ms, first_ms = cvc_warm_ms(out, camera, options)
            ours[name]["ms"].append(ms)
            ours[name]["first_ms"].append(first_ms)
        print(f"round {r + 1}/{args.rounds}: VTK {1000 * median_s:.0f} ms, " +
              ", ".join(f"{name} {ours[name]['ms'][-1]:.0f} ms" for name in VARIANTS), file=sys.stderr)
        if args.composite:
            vtk_composite.append(vtk_composite_ms(out, camera))
            for name, options in COMPOSITE_VARIANTS.items():
                ms, _ = cvc_warm_ms(out, camera, options + ["--mode", "composite", "--tf", "colon-wall"])
                composite[name].append(ms)
            print(f"round {r + 1}/{args.rounds}, composite: VTK {vtk_composite[-1]:.0f} ms, " +
                  ", ".join(f"{name} {composite[name][-1]:.0f} ms" for name in COMPOSITE_VARIANTS), file=sys.stderr)

    print("converged images", file=sys.stderr)
    vtk_converged = os.path.join(out, "vtk_converged.png")
    vtk_view(out, CONVERGED_STEP, vtk_converged, 0)
    vtk_error = image_errors(os.path.join(out, "vtk.png"), vtk_converged)
    errors = {}
    for n, (name, options) in enumerate(VARIANTS.items()):
        image, converged = os.path.join(out, f"cvc_{n}.png"), os.path.join(out, f"cvc_{n}_converged.png")
        cvc_image(out, camera, options, STEP, 2, image)
        cvc_image(out, camera, options, CONVERGED_STEP, 12, converged)
        errors[name] = image_errors(image, converged)

    print(f"\n| yardstick view, iso -500 HU, {STEP:g} voxel, 1024^2 | ms, median of {args.rounds} (first frame) | "
          "/ VTK, paired per round | RMSE against its own converged image | PSNR dB | SSIM |")
    print("|---|---:|---:|---:|---:|---:|")
    print(f"| VTK 9.1 CPU ray caster | {1000 * statistics.median(vtk_s):.0f} ({1000 * statistics.median(vtk_first_s):.0f}) "
          f"| 1 | {vtk_error['rmse']:.4f} | {vtk_error['psnr']:.1f} | {vtk_error['ssim']:.4f} |")
    for name in VARIANTS:
        ratio = statistics.median(ms / (1000 * v) for ms, v in zip(ours[name]["ms"], vtk_s))
        own = errors[name]
        print(f"| cvc, {name} | {statistics.median(ours[name]['ms']):.0f} ({statistics.median(ours[name]['first_ms']):.0f}) "
              f"| **{ratio:.2f}** | {own['rmse']:.4f} | {own['psnr']:.1f} | {own['ssim']:.4f} |")
    print(f"\nVTK's times, ms: {' '.join(f'{1000 * v:.0f}' for v in vtk_s)}")
    for name in VARIANTS:
        print(f"cvc {name}, ms: {' '.join(f'{v:.0f}' for v in ours[name]['ms'])}")
    if args.composite:
        print(f"\n| yardstick view, composite colon-wall, {STEP:g} voxel, 1024^2 | ms, median of {args.rounds} | "
              "/ VTK, paired per round |")
        print("|---|---:|---:|")
        print(f"| VTK 9.1 CPU ray caster (median of 3 after the first) | {statistics.median(vtk_composite):.0f} | 1 |")
        for name in COMPOSITE_VARIANTS:
            ratio = statistics.median(ms / v for ms, v in zip(composite[name], vtk_composite))
            print(f"| cvc, {name} | {statistics.median(composite[name]):.0f} | **{ratio:.2f}** |")
        print(f"\nVTK's composite times, ms: {' '.join(f'{v:.0f}' for v in vtk_composite)}")
    print(f"load average at the end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
