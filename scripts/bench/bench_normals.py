#!/usr/bin/python3
"""Shading normals on coarse CT: time and image error of the gradient choices.

Usage: /usr/bin/python3 scripts/bench/bench_normals.py [--runs 5] [--out out/bench_normals]
       [--gradients central,bspline,bspline-voxels]

For each scene renders, alternating, the trilinear march with each `--gradient` choice and the
tricubic reference (`--filter tricubic --gradient bspline`, the smooth image of the data), and
reports per configuration the median ray-casting time (device time of the dispatch, `--runs` runs),
its ratio to the tricubic render's time in the same run, and the RMSE of the colour against the
reference over the pixels where both images hit the surface, the silhouette eroded by 4 pixels.
Scenes: the 3 mm abdominal CT (../shared/data/ct/ts_example_abdomen_3mm.nrrd) from cvc's default
outside view and from inside its air-filled colon (the camera of
docs/benchmarks/time_against_error.md), and the 0.6 mm colon phantom's inside view. Writes
side-by-side crops of the outside view to docs/images/normals_abdomen_crops.png. Benchmarks, not
tests: CI does not run this.
"""
import argparse
import os
import re
import subprocess
import sys

import numpy as np
from matplotlib.image import imread, imsave
from scipy import ndimage

from bench_scenes import camera_options

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CVC = os.path.join(ROOT, "build", "app", "cvc")
CT = os.path.join(ROOT, "..", "shared", "data", "ct", "ts_example_abdomen_3mm.nrrd")


def read_hits(path):
    """The hit flag (w) of a pinhole hit image written by `cvc render --hits`."""
    with open(path, "rb") as f:
        data = f.read()
    header, payload = data.split(b"\n\n", 1)
    sizes = re.search(rb"sizes: 4 (\d+) (\d+)", header)
    width, height = int(sizes.group(1)), int(sizes.group(2))
    return np.frombuffer(payload, dtype="<f4").reshape(height, width, 4)[:, :, 3] > 0.5


def render(scene, config, out):
    png = os.path.join(out, f"{scene['name']}_{config['name']}.png")
    hits = png.replace(".png", "_hits.nrrd")
    command = [CVC, "render", scene["volume"], "--iso", "-500", "--size", scene["size"], "--step", "0.5",
               "--filter", config["filter"], "--gradient", config["gradient"], "--gradient-volume",
               config.get("gradient_volume", "off"), "--hits", hits, "--force", "-o", png]
    command += scene.get("camera", [])
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"{' '.join(command)}\n{result.stderr}")
    ms = float(re.search(r"ray casting ([0-9.]+) ms", result.stdout).group(1))
    return ms, png, hits


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "bench_normals"))
    parser.add_argument("--gradients", default="central,bspline,bspline-voxels")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    phantom = os.path.join(args.out, "colon.nrrd")
    if not os.path.exists(phantom):
        subprocess.run([CVC, "phantom", "-o", phantom], check=True, capture_output=True)

    scenes = [
        {"name": "ct_outside", "title": "abdominal CT (3 mm), default outside view, 512^2", "volume": CT,
         "size": "512x512"},
        {"name": "ct_inside", "title": "abdominal CT (3 mm), inside the air-filled colon, 512^2", "volume": CT,
         "size": "512x512", "camera": camera_options("ct_camera")},
        {"name": "phantom_inside", "title": "colon phantom (0.6 mm), inside view, 512^2", "volume": phantom,
         "size": "512x512", "camera": camera_options("phantom_camera")},
    ]
    # bspline-voxels is read from the gradient volume (it has no taps of its own); the others from the taps.
    configs = [{"name": f"trilinear_{g}", "filter": "trilinear", "gradient": g,
                "gradient_volume": "on" if g == "bspline-voxels" else "off"} for g in args.gradients.split(",")]
    reference = {"name": "tricubic", "filter": "tricubic", "gradient": "bspline"}  # its normals are always the B-spline's

    print("| scene | configuration | ray casting ms (median) | / tricubic | RMSE vs tricubic (both hit, eroded 4 px) |")
    print("|---|---|---:|---:|---:|")
    crops = []
    for scene in scenes:
        times = {c["name"]: [] for c in configs + [reference]}
        files = {}
        for _ in range(args.runs):
            for config in configs + [reference]:
                ms, png, hits = render(scene, config, args.out)
                times[config["name"]].append(ms)
                files[config["name"]] = (png, hits)
        ref_png, ref_hits = files[reference["name"]]
        ref_image = imread(ref_png)[:, :, :3]
        ref_mask = read_hits(ref_hits)
        ref_ms = float(np.median(times[reference["name"]]))
        for config in configs + [reference]:
            png, hits = files[config["name"]]
            image = imread(png)[:, :, :3]
            mask = ndimage.binary_erosion(read_hits(hits) & ref_mask, iterations=4)
            rmse = float(np.sqrt(np.mean((image[mask] - ref_image[mask]) ** 2))) if mask.any() else float("nan")
            ms = float(np.median(times[config["name"]]))
            print(f"| {scene['title']} | {config['name'].replace('_', ', ')} | {ms:.1f} | {ms / ref_ms:.2f} | "
                  f"{rmse:.4f} |", flush=True)
            if scene["name"] == "ct_outside":
                crops.append(imread(png)[150:406, 128:384, :3])
    imsave(os.path.join(ROOT, "docs", "images", "normals_abdomen_crops.png"),
           np.concatenate([np.pad(c, ((0, 0), (0, 8), (0, 0))) for c in crops], axis=1))


if __name__ == "__main__":
    main()
