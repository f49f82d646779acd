#!/usr/bin/python3
"""Polyp candidates measured: sensitivity per size class and false positives per volume on
random-polyp phantoms, an FROC curve, and the candidates on the shared CT.

Usage: /usr/bin/python3 scripts/bench/bench_candidates.py [--seeds 201,202,203,204,205]
       [--polyps 10] [--out out/bench_candidates] [--images docs/images]

1. Phantoms: for each seed and variant, `cvc phantom --random-polyps N --seed S` (5-15 mm
   sessile, pedunculated and flat polyps, a quarter on a fold's ridge; haustral folds always),
   with the variants: plain; `--anatomy` (body, lungs, a collapsed stretch, a pool of tagged
   fluid that the analysis cleanses); `--shape-seed S` (the colon's curve moved). Then
   `cvc candidates` on it. A candidate marks a polyp when its centre lies within the polyp's
   radius plus 3 mm of the polyp's centre or apex (base moved its height along the wall's
   normal); a polyp is found when a candidate marks it; a candidate that marks no polyp (of any
   size) is a false positive.
2. The FROC curve: sensitivity for polyps of 6 mm and more against false positives per volume,
   as the score threshold sweeps; written to IMAGES/candidates_froc.png.
3. The shared 3 mm abdominal CT (no known polyp): every candidate is a false positive; the
   first eight candidates' pictures in IMAGES/candidates_ct.png for a reader to judge.
Prints Markdown tables (docs/candidates.md). A benchmark, not a test: CI does not run it.
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CVC = os.path.join(ROOT, "build", "app", "cvc")
SHARED_CT = os.path.join(ROOT, "..", "shared", "data", "ct", "ts_example_abdomen_3mm.nrrd")
CLASSES = [("< 6 mm", 0.0, 6.0), ("6-9 mm", 6.0, 10.0), (">= 10 mm", 10.0, 1e9)]


def run(arguments):
    subprocess.run([CVC] + arguments, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def marks(candidate, polyp):
    c = np.array(candidate["centre_mm"])
    apex = np.array(polyp["base_mm"]) + polyp["height_mm"] * np.array(polyp["base_normal"])
    reach = 0.5 * polyp["diameter_mm"] + 3.0
    return min(np.linalg.norm(c - np.array(polyp["centre_mm"])), np.linalg.norm(c - apex)) <= reach


def phantom_case(out, seed, variant, options, polyps):
    base = os.path.join(out, f"seed_{seed}_{variant}")
    if not os.path.exists(base + ".nrrd"):
        run(["phantom", "--random-polyps", str(polyps), "--seed", str(seed), "-o", base + ".nrrd", "--force"] + options)
    run(["candidates", base + ".nrrd", "-o", base + "_candidates", "--force", "--pictures", "0"])
    truth = json.load(open(base + ".json"))["polyps"]
    found = json.load(open(os.path.join(base + "_candidates", "candidates.json")))
    return truth, found


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="201,202,203,204,205")
    parser.add_argument("--polyps", type=int, default=10)
    parser.add_argument("--out", default="out/bench_candidates")
    parser.add_argument("--images", default="docs/images")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    seeds = [int(s) for s in args.seeds.split(",")]
    cases = []  # (seed, variant, truth, candidates document)
    for seed in seeds:
        for variant, options in (("plain", []), ("anatomy", ["--anatomy"]), ("shape", ["--shape-seed", str(seed)])):
            truth, doc = phantom_case(args.out, seed, variant, options, args.polyps)
            cases.append((seed, variant, truth, doc))
            print(f"seed {seed} {variant}: {len(doc['candidates'])} candidates in {doc['seconds']:.1f} s", file=sys.stderr)

    # Per polyp: its size class, kind, and the best score of a candidate marking it (None: missed);
    # per volume: the scores of the candidates that mark nothing.
    polyp_rows, false_scores, misses = [], [], []
    for seed, variant, truth, doc in cases:
        marked = [False] * len(doc["candidates"])
        for polyp in truth:
            scores = [c["score"] for i, c in enumerate(doc["candidates"]) if marks(c, polyp)]
            for i, c in enumerate(doc["candidates"]):
                marked[i] = marked[i] or marks(c, polyp)
            kind = polyp["kind"] + (" on a fold" if polyp["on_fold"] else "")
            polyp_rows.append((polyp["diameter_mm"], kind, max(scores) if scores else None, variant))
            if not scores and polyp["diameter_mm"] >= 6.0:
                misses.append(f"seed {seed} {variant}: {kind}, {polyp['diameter_mm']:.1f} mm")
        false_scores.append([c["score"] for i, c in enumerate(doc["candidates"]) if not marked[i]])
    volumes = len(cases)

    print(f"Phantoms: seeds {args.seeds}, {args.polyps} random polyps each, three variants (plain, anatomy, "
          f"shape): {volumes} volumes, {len(polyp_rows)} polyps. Every candidate reported (no score threshold):\n")
    print("| size class | polyps | found | sensitivity |")
    print("|---|---:|---:|---:|")
    for name, low, high in CLASSES:
        rows = [r for r in polyp_rows if low <= r[0] < high]
        hit = sum(1 for r in rows if r[2] is not None)
        print(f"| {name} | {len(rows)} | {hit} | {100.0 * hit / max(1, len(rows)):.0f} % |")
    large = [r for r in polyp_rows if r[0] >= 6.0]
    hit = sum(1 for r in large if r[2] is not None)
    fp = sum(len(s) for s in false_scores)
    print(f"| 6 mm and more | {len(large)} | {hit} | {100.0 * hit / max(1, len(large)):.1f} % |\n")
    print(f"False positives: {fp} in {volumes} volumes, {fp / volumes:.2f} per volume "
          f"(most in one volume: {max(len(s) for s in false_scores)}).\n")
    print("| polyp kind (6 mm and more) | polyps | found |")
    print("|---|---:|---:|")
    for kind in sorted({r[1] for r in large}):
        rows = [r for r in large if r[1] == kind]
        print(f"| {kind} | {len(rows)} | {sum(1 for r in rows if r[2] is not None)} |")
    print("\n| variant | volumes | sensitivity, 6 mm and more | false positives per volume |")
    print("|---|---:|---:|---:|")
    for variant in ("plain", "anatomy", "shape"):
        rows = [r for r in large if r[3] == variant]
        fps = [len(s) for (seed, v, t, d), s in zip(cases, false_scores) if v == variant]
        print(f"| {variant} | {len(fps)} | {sum(1 for r in rows if r[2] is not None)} / {len(rows)} | {np.mean(fps):.2f} |")
    print("\nMissed polyps of 6 mm and more: " + ("; ".join(misses) if misses else "none") + ".\n")

    # The shared CT.
    ct_out = os.path.join(args.out, "shared_ct")
    run(["candidates", SHARED_CT, "-o", ct_out, "--force", "--pictures", "8"])
    ct = json.load(open(os.path.join(ct_out, "candidates.json")))
    counts = ct["counts"]
    print(f"The shared 3 mm abdominal CT (no known polyp): {len(ct['candidates'])} candidates, all false positives "
          f"({counts['cap_regions']} cap regions; dropped {counts['dropped_small']} small, {counts['dropped_elongated']} "
          f"elongated, {counts['dropped_unmeasured']} unmeasured or under 4 mm); at a score of 0.3 and more "
          f"{sum(1 for c in ct['candidates'] if c['score'] >= 0.3)}; in {ct['seconds']:.1f} s.")

    # FROC: a threshold t keeps the candidates of score >= t.
    ct_scores = [c["score"] for c in ct["candidates"]]

    def at(t):
        sensitivity = sum(1 for r in large if r[2] is not None and r[2] >= t) / max(1, len(large))
        return (sum(1 for f in false_scores for s in f if s >= t) / volumes, sensitivity,
                sum(1 for s in ct_scores if s >= t))

    thresholds = sorted({r[2] for r in large if r[2] is not None} | {s for f in false_scores for s in f} |
                        set(ct_scores) | {0.0})
    curve = [at(t) for t in thresholds]
    print("\n| score threshold | sensitivity, 6 mm and more | false positives per phantom | false positives on the shared CT |")
    print("|---:|---:|---:|---:|")
    for target in (0.0, 0.1, 0.2, 0.3, 0.4, 0.5):
        fp_per_volume, sensitivity, ct_fp = at(target)
        print(f"| {target:.1f} | {100.0 * sensitivity:.1f} % | {fp_per_volume:.2f} | {ct_fp} |")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    import matplotlib.pyplot as plt
    os.makedirs(args.images, exist_ok=True)
    figure, axes = plt.subplots(figsize=(6, 4))
    axes.plot([c[0] for c in curve], [100 * c[1] for c in curve], marker=".", color="tab:blue",
              label="false positives on the phantoms (per volume)")
    # The phantoms have little else that is shaped like a polyp: the same thresholds against the
    # false positives on the real CT show the trade the score offers.
    axes.plot([c[2] for c in curve], [100 * c[1] for c in curve], marker=".",
              color="tab:red", label="false positives on the shared CT")
    axes.legend(loc="lower right", fontsize=8)
    axes.set_xlabel("false positives per volume")
    axes.set_ylabel("sensitivity, polyps of 6 mm and more (%)")
    axes.set_title(f"cvc candidates: FROC over {volumes} random-polyp phantoms")
    axes.set_ylim(0, 102)
    axes.set_xlim(left=0)
    axes.grid(alpha=0.3)
    figure.tight_layout()
    figure.savefig(os.path.join(args.images, "candidates_froc.png"), dpi=110)
    plt.close(figure)

    shown = [c for c in ct["candidates"] if c.get("picture")][:8]
    if shown:
        figure, axes = plt.subplots(2, 4, figsize=(10, 5.4))
        for axis in axes.flat:
            axis.axis("off")
        for axis, c in zip(axes.flat, shown):
            axis.imshow(mpimg.imread(os.path.join(ct_out, c["picture"])))
            axis.set_title(f"#{c['rank']}: {c['diameter_mm']:.0f} mm, score {c['score']:.2f}\nframe {c['nearest_frame']}",
                           fontsize=9)
        figure.suptitle("The shared CT's first candidates, seen from the lumen (all false positives)")
        figure.tight_layout()
        figure.savefig(os.path.join(args.images, "candidates_ct.png"), dpi=90)
        plt.close(figure)


if __name__ == "__main__":
    main()
