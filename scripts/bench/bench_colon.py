#!/usr/bin/python3
"""The colon analysis measured: centreline accuracy on phantoms, the shared CT, time and memory.

Usage: /usr/bin/python3 scripts/bench/bench_colon.py [--seeds 1,2,3,4,5] [--runs 3] [--out out/bench_colon]

1. Phantoms: the default colon phantom and the anatomy phantom (`cvc phantom --anatomy`: body,
   lungs, a collapsed segment, a tagged fluid pool, five polyps) for each shape seed. `cvc colon`
   runs on each; its centreline (colon.json) is compared with the phantom's truth: the distance
   of every centreline point to the truth polyline (mean, 95th percentile, largest), the share
   of the truth within 3 mm of the centreline (outside the collapsed arcs, which have no air),
   and every point's voxel in air (below -800 HU in the cleansed volume the analysis renders).
2. The shared 3 mm abdominal CT: segments, lengths, gaps, points in air.
3. Time and peak memory: `cvc colon` on the shared CT resampled to 512x512x451 (the volumes
   benchmark's CT, `volumes_bench make`), `--runs` runs, medians; peak resident memory from GNU
   time against the int16 volume's size.
Prints Markdown tables (docs/colon.md quotes them). A benchmark, not a test: CI does not run it.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import time

import numpy as np

from bench_images import read_nrrd, spacing_of

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CVC = os.path.join(ROOT, "build", "app", "cvc")
VOLUMES_BENCH = os.path.join(ROOT, "build", "tests", "volumes", "volumes_bench")
CT = os.path.join(ROOT, "..", "shared", "data", "ct", "ts_example_abdomen_3mm.nrrd")


def run(args):
    result = subprocess.run(args, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("failed: " + " ".join(args) + "\n" + result.stderr)
    return result


def read_volume(path):
    """An uncompressed NRRD volume: (voxels as [z, y, x], spacing per axis)."""
    fields, voxels = read_nrrd(path)
    return voxels, np.array(spacing_of(fields))


def distances_to_polyline(points, line):
    """Distance of each point to the polyline, and the arc length of its nearest point."""
    a, b = line[:-1], line[1:]
    ab = b - a
    length2 = np.maximum((ab * ab).sum(1), 1e-12)
    arc = np.concatenate([[0.0], np.cumsum(np.sqrt(length2))])
    best, best_arc = np.full(len(points), np.inf), np.zeros(len(points))
    for start in range(0, len(points), 256):
        p = points[start:start + 256, None, :]
        t = np.clip(((p - a) * ab).sum(2) / length2, 0.0, 1.0)
        d = np.linalg.norm(a + t[..., None] * ab - p, axis=2)
        i = d.argmin(1)
        best[start:start + 256] = d[np.arange(len(i)), i]
        best_arc[start:start + 256] = arc[i] + t[np.arange(len(i)), i] * np.sqrt(length2[i])
    return best, best_arc


def in_air(points, voxels, spacing):
    index = np.rint(points / spacing).astype(int)
    for axis, size in enumerate(voxels.shape[::-1]):
        index[:, axis] = np.clip(index[:, axis], 0, size - 1)
    return voxels[index[:, 2], index[:, 1], index[:, 0]] < -800


def phantom_row(out, name, phantom_args):
    volume = os.path.join(out, name + ".nrrd")
    run([CVC, "phantom", "--force", "-o", volume] + phantom_args)
    truth = json.load(open(os.path.join(out, name + ".json")))
    folder = os.path.join(out, name)
    start = time.perf_counter()
    run([CVC, "colon", volume, "-o", folder, "--force"])
    seconds = time.perf_counter() - start
    report = json.load(open(os.path.join(folder, "colon.json")))
    computed = np.array(report["centreline_mm"])
    line = np.array(truth["centreline_mm"])
    d, _ = distances_to_polyline(computed, line)
    back, truth_arc = distances_to_polyline(line, computed)
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(line, axis=0), axis=1))])
    kept = np.ones(len(line), bool)
    for s0, s1 in truth.get("collapsed_arc_mm", []):
        kept &= ~((arc >= s0) & (arc <= s1))
    coverage = float((back[kept] < 3.0).mean())
    rendered = os.path.join(folder, "cleansed.nrrd")
    voxels, spacing = read_volume(rendered if os.path.exists(rendered) else volume)
    air = in_air(computed, voxels, spacing)
    # The analysis runs rectum -> caecum; the phantom's truth caecum -> rectum.
    order_ok = np.linalg.norm(computed[0] - line[-1]) < np.linalg.norm(computed[0] - line[0])
    return {"phantom": name, "segments": len(report["segments"]), "collapses": len(truth.get("collapsed_arc_mm", [])),
            "mean": d.mean(), "p95": np.percentile(d, 95), "max": d.max(), "coverage": coverage,
            "in_air": float(air.mean()), "cleansed_ml": report["cleansing"]["fluid_ml"], "order": order_ok,
            "seconds": seconds}


def region_text(region):
    """One air region as the report gives it: its class and the measures that decided it."""
    measures = []
    if "median_hu" in region:
        measures.append(f"median {region['median_hu']:.0f} HU")
    if "tubularity" in region:
        measures.append(f"tubularity {region['tubularity']:.1f}")
    return f"{region['class']} {region['volume_ml']:.1f} mL" + (f" ({', '.join(measures)})" if measures else "")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seeds", default="1,2,3,4,5")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "bench_colon"))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)

    rows = [phantom_row(args.out, "default", [])]
    for seed in [int(s) for s in args.seeds.split(",") if s]:
        rows.append(phantom_row(args.out, f"anatomy_seed{seed}", ["--anatomy", "--shape-seed", str(seed)]))
    print("| phantom | segments (collapses) | mean mm | p95 mm | max mm | truth covered | points in air | "
          "fluid cleansed mL | rectum first | cvc colon s |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---|---:|")
    for r in rows:
        print(f"| {r['phantom']} | {r['segments']} ({r['collapses']}) | {r['mean']:.2f} | {r['p95']:.2f} | "
              f"{r['max']:.2f} | {100 * r['coverage']:.1f} % | {100 * r['in_air']:.1f} % | {r['cleansed_ml']:.2f} | "
              f"{'yes' if r['order'] else 'no'} | {r['seconds']:.1f} |")

    folder = os.path.join(args.out, "abdomen_ct")
    run([CVC, "colon", CT, "-o", folder, "--force"])
    report = json.load(open(os.path.join(folder, "colon.json")))
    voxels, spacing = read_volume(CT)
    computed = np.array(report["centreline_mm"])
    print("\nShared 3 mm abdominal CT:\n")
    print("| segment | length mm | volume mL | mean lumen radius mm | gap to next mm |")
    print("|---:|---:|---:|---:|---:|")
    for i, s in enumerate(report["segments"]):
        gap = f"{report['gaps_mm'][i]:.0f}" if i < len(report["gaps_mm"]) else ""
        print(f"| {s['segment']} | {s['length_mm']:.0f} | {s['volume_ml']:.1f} | {s['mean_radius_mm']:.1f} | {gap} |")
    print(f"\npoints in air: {100 * in_air(computed, voxels, spacing).mean():.1f} %, "
          f"{report['total_length_mm']:.0f} mm in {len(report['segments'])} segments; air regions: " +
          ", ".join(region_text(r) for r in report["air_regions"]))

    large = os.path.join(args.out, "large")
    if not os.path.exists(os.path.join(large, "ct.nrrd")):
        os.makedirs(large, exist_ok=True)
        run([VOLUMES_BENCH, "make", large])
    ct = os.path.join(large, "ct.nrrd")
    volume_bytes = 512 * 512 * 451 * 2
    walls, rss = [], []
    for _ in range(args.runs):
        result = run(["/usr/bin/time", "-f", "TIME %e %M", CVC, "colon", ct, "-o", os.path.join(large, "colon"),
                      "--force"])
        seconds, kib = re.search(r"TIME ([\d.]+) (\d+)", result.stderr).groups()
        walls.append(float(seconds))
        rss.append(int(kib) * 1024)
    print(f"\n512x512x451 CT ({volume_bytes / 2**20:.0f} MiB of int16), {args.runs} runs: "
          f"cvc colon {statistics.median(walls):.1f} s wall (median; load and all outputs included; "
          f"runs {', '.join(f'{w:.1f}' for w in walls)}), peak resident memory "
          f"{statistics.median(rss) / 2**20:.0f} MiB = {statistics.median(rss) / volume_bytes:.2f}x the volume")


if __name__ == "__main__":
    main()
