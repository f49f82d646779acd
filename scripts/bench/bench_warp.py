#!/usr/bin/python3
"""Chord against exact warp for the stereo eyes: pixels, hit positions and time.

Usage: /usr/bin/python3 scripts/bench/bench_warp.py [--out out/bench_warp] [--scales 4,10]

At the demo's pose (colon phantom, polyp 3 ahead at 50 degrees, on the Immersive Cabin's missing
ceiling) renders one stereo ic5 frame per scale with `--warp chord` (the paper's Eq. 7: the
ray's near and far points mapped, the chord between them marched) and with `--warp exact`
(every sample mapped), both with `--hits`. For each wall and eye prints the 99th percentile of
the colour difference (levels of 255), the share of pixels more than 16 levels apart, and the
median and 99th percentile of the distance between the two first hits (mm, where both hit);
then each mode's ray-casting time per stereo frame. Benchmarks, not tests: CI does not run this.
"""
import argparse
import gzip
import os
import re
import subprocess
import sys

import numpy as np
from matplotlib.image import imread

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CVC = os.path.join(ROOT, "build", "app", "cvc")
WALLS = ["front", "back", "left", "right", "floor"]


def read_hits(path):
    with open(path, "rb") as f:
        data = f.read()
    header, payload = data.split(b"\n\n", 1)
    width, height = map(int, re.search(rb"sizes: 3 (\d+) (\d+)", header).groups())
    return np.frombuffer(gzip.decompress(payload), dtype="<f4").reshape(height, width, 3)


def render(volume, truth, scale, warp, out):
    folder = os.path.join(out, f"scale{scale}_{warp}")
    command = [CVC, "render", volume, "--display", "ic5", "--path", truth, "--polyp", "3", "--polyp-elevation", "50",
               "--scale", str(scale), "--warp", warp, "--hits", "--force", "-o", folder]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"{' '.join(command)}\n{result.stderr}")
    ms = float(re.search(r"ray casting ([0-9.]+) ms of device time", result.stdout).group(1))
    return folder, ms


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "bench_warp"))
    parser.add_argument("--scales", default="4,10")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    volume = os.path.join(args.out, "colon.nrrd")
    if not os.path.exists(volume):
        subprocess.run([CVC, "phantom", "-o", volume], check=True, capture_output=True)
    truth = volume.replace(".nrrd", ".json")

    print("| scale | eye | wall | colour p99 (levels) | pixels > 16 levels | hit distance median / p99 (mm) |")
    print("|---:|---|---|---:|---:|---:|")
    times = []
    for scale in [int(s) for s in args.scales.split(",")]:
        chord, chord_ms = render(volume, truth, scale, "chord", args.out)
        exact, exact_ms = render(volume, truth, scale, "exact", args.out)
        times.append((scale, chord_ms, exact_ms))
        for eye in ["left", "right"]:
            for wall in WALLS:
                a = imread(os.path.join(chord, "frame_0000", eye, wall + ".png"))[:, :, :3] * 255.0
                b = imread(os.path.join(exact, "frame_0000", eye, wall + ".png"))[:, :, :3] * 255.0
                diff = np.abs(a - b).max(axis=2)
                ha = read_hits(os.path.join(chord, "frame_0000", eye, wall + "_hits.nrrd"))
                hb = read_hits(os.path.join(exact, "frame_0000", eye, wall + "_hits.nrrd"))
                both = ~np.isnan(ha[:, :, 0]) & ~np.isnan(hb[:, :, 0])
                distance = np.linalg.norm(ha[both] - hb[both], axis=1)
                print(f"| {scale} | {eye} | {wall} | {np.percentile(diff, 99):.0f} | {100.0 * (diff > 16).mean():.2f} % | "
                      f"{np.median(distance):.3f} / {np.percentile(distance, 99):.3f} |", flush=True)
    for scale, chord_ms, exact_ms in times:
        print(f"scale {scale}: ray casting per stereo frame, chord {chord_ms:.0f} ms, exact {exact_ms:.0f} ms "
              f"(exact / chord {exact_ms / chord_ms:.2f})")


if __name__ == "__main__":
    main()
