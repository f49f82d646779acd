"""The distribution of `cvc polyp-check` results over many polyps (scripts/bench/bench_polyps.sh).

Usage: /usr/bin/python3 scripts/bench/polyp_check_distribution.py DISPLAY OUT.md WORST_CROP.png RUN_DIR...

Each RUN_DIR is a polyp-check output folder (polyp_check.json, crops/) of one random-polyp
phantom. Over the polyps of 6 mm and more it writes a Markdown section: per targeted pose, map
and eye the median, 95th percentile and worst aspect, circularity and grid-angle errors and the
share within the targets (3 %, 3 %, 2 degrees); the linear baseline against the conformal map;
the measured error against the map's prediction for unoccluded polyps, and which term the report
names where they are more than a point apart; and the worst conformal result's crops (reference,
conformal, linear), copied to WORST_CROP.png. Needs Debian's /usr/bin/python3 (numpy).
"""
import collections
import json
import os
import shutil
import sys

import numpy as np

ASPECT_TARGET, CIRCULARITY_TARGET, GRID_TARGET_DEG = 0.03, 0.03, 2.0
EYES = ["left", "centre", "right"]
# Why polyp-check leaves a result out of the targets (its "untargeted_because").
REASONS = {
    "not in view": "no place on the polyp's path shows it in full view",
    "prediction": "the map's prediction from the polyp's place exceeds 2 %, for its outline or, where the eye "
                  "came closer past a fold, for a circle of its angular radius",
    "pose": "the pose's floor exceeds the target",
}


def number(value):
    return float("nan") if value is None else float(value)


def within_targets(r):
    """Whether a result is visible with its aspect, circularity and grid errors within the targets."""
    return (r["visible"] and number(r["aspect_error"]) <= ASPECT_TARGET
            and number(r["circularity_error"]) <= CIRCULARITY_TARGET
            and number(r["grid_angle_error_deg"]) <= GRID_TARGET_DEG)


def is_occluded(r):
    """Whether a fold or a bend hides part of the polyp in its reference, as polyp-check's budget
    counts it: a tenth of its outline unseen, or over half a percent hidden by something in front
    ("reference_hidden_in_front_share", absent from runs before it was recorded)."""
    return r["reference_unoccluded_share"] < 0.9 or r.get("reference_hidden_in_front_share", 0.0) > 0.005


def load(run_dirs):
    """The results of every run, each with its run folder and its polyp's kind from the truth
    ("sessile", "pedunculated" or "flat", "/fold" added for one on a fold; "?" without a truth)."""
    results, plans = [], []
    for run in run_dirs:
        doc = json.load(open(os.path.join(run, "polyp_check.json")))
        plans.append(doc["plan"])
        polyps = json.load(open(doc["truth"]))["polyps"] if os.path.exists(doc["truth"]) else []
        for r in doc["results"]:
            r["run"] = run
            p = polyps[r["polyp"]] if r["polyp"] < len(polyps) else {}
            r["kind"] = p.get("kind", "?") + ("/fold" if p.get("on_fold") else "")
            results.append(r)
    return results, plans


def percent(x):
    return "–" if not np.isfinite(x) else f"{100 * x:.1f} %"


def summary(values):
    v = np.array([x for x in values if np.isfinite(x)])
    if v.size == 0:
        return float("nan"), float("nan"), float("nan")
    return float(np.median(v)), float(np.percentile(v, 95)), float(v.max())


def main():
    display, out_md, worst_png, runs = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    results, plans = load(runs)
    big = [r for r in results if r["diameter_mm"] >= 6.0]
    polyps = {(r["run"], r["polyp"]) for r in big}
    lines = []
    say = lines.append
    radii = sorted({p["angular_radius_deg"] for p in plans})
    say(f"{len(polyps)} polyps of 6 mm and more from {len(runs)} phantoms; eyes where the polyps subtend "
        f"{', '.join(f'{r:g}' for r in radii)} degrees (closer where a fold or bend hides them).")
    targeted_poses = [p["name"] for p in plans[0]["poses"] if p["targeted"]]
    reported_poses = [p["name"] for p in plans[0]["poses"] if not p["targeted"]]
    say(f"Targeted poses: {', '.join(targeted_poses)}; reported: {', '.join(reported_poses) or 'none'}.")
    # Results at targeted poses that the check reports without holding them to the targets, and why.
    left_out = [r for r in big if r["map"] == "conformal" and not r["targeted"] and r["pose"] in targeted_poses]
    if left_out:
        reasons = collections.Counter(r.get("untargeted_because") or "prediction" for r in left_out)
        within = sum(1 for r in left_out if within_targets(r))
        am, ap, aw = summary([number(r["aspect_error"]) for r in left_out if r["visible"]])
        say(f"At the targeted poses {len(left_out)} conformal results are reported, not targeted ("
            + ", ".join(f"{REASONS.get(k, k)}: {v}" for k, v in reasons.most_common())
            + f"); {within} of them are within the targets all the same (aspect median / p95 / worst "
            f"{percent(am)} / {percent(ap)} / {percent(aw)}).")
    say("")

    # Per pose, map and eye, over the targeted results (a polyp that came closer may leave a pose).
    say("| pose | map | eye | results | aspect median / p95 / worst | circularity median / p95 / worst | "
        "grid median / p95 / worst | within targets |")
    say("|---|---|---|---:|---:|---:|---:|---:|")
    groups = collections.defaultdict(list)
    for r in big:
        if r["targeted"] and r["map"] != "none":
            groups[(r["pose"], r["map"], r["eye"])].append(r)
    order = {name: i for i, name in enumerate(p["name"] for p in plans[0]["poses"])}
    worst_conformal = None
    for (pose, map_name, eye), rs in sorted(groups.items(), key=lambda kv: (order.get(kv[0][0], 99), kv[0][1], EYES.index(kv[0][2]))):
        a = [number(r["aspect_error"]) for r in rs]
        c = [number(r["circularity_error"]) for r in rs]
        g = [number(r["grid_angle_error_deg"]) for r in rs]
        within = sum(1 for r in rs if within_targets(r))
        am, ap, aw = summary(a)
        cm, cp, cw = summary(c)
        gm, gp, gw = summary(g)
        say(f"| {pose} | {map_name} | {eye} | {len(rs)} | {percent(am)} / {percent(ap)} / {percent(aw)} | "
            f"{percent(cm)} / {percent(cp)} / {percent(cw)} | {gm:.2f}° / {gp:.2f}° / {gw:.2f}° | {within}/{len(rs)} |")
        if map_name == "conformal":
            for r in rs:
                if worst_conformal is None or number(r["aspect_error"]) > number(worst_conformal["aspect_error"]):
                    worst_conformal = r
    say("")

    conformal = [r for r in big if r["targeted"] and r["map"] == "conformal"]
    passed = [r for r in conformal if within_targets(r)]
    say(f"Conformal, targeted poses, every eye: {len(passed)} of {len(conformal)} results within the targets "
        f"({100 * len(passed) / max(len(conformal), 1):.1f} %).")
    by_eye = collections.Counter(r["eye"] for r in conformal if r not in passed)
    if by_eye:
        say(f"Outside them by eye: {', '.join(f'{eye} {by_eye[eye]}' for eye in EYES if by_eye[eye])}.")
        # What the results outside the targets have in common, first match wins.
        centre_passed = {(r["run"], r["polyp"], r["pose"]) for r in passed if r["eye"] == "centre"}
        kinds = collections.Counter()
        for r in conformal:
            if r in passed:
                continue
            if not r["visible"]:
                kinds["not in view (no place on the path shows the polyp, or too few pixels)"] += 1
            elif is_occluded(r):
                kinds["occluded (a fold or bend hides a tenth of its outline, or its edge lies across it)"] += 1
            elif r["reference_unoccluded_share"] < 0.95:
                kinds["partly hidden (5-10 % of its outline unseen: a fold's edge, or the rim's rounding)"] += 1
            elif r["eye"] != "centre" and (r["run"], r["polyp"], r["pose"]) in centre_passed:
                kinds["one stereo eye only (the centre eye within the targets)"] += 1
            elif number(r["pixels_across"]) < 40:
                kinds["small image (under 40 pixels across)"] += 1
            else:
                kinds["other"] += 1
        say("Outside them by kind: " + "; ".join(f"{k}: {v}" for k, v in kinds.most_common()) + ".")
    # By the polyp's kind: where the results outside the targets come from.
    say("")
    say("| polyp kind | polyps | targeted conformal results | within targets | aspect median / p95 / worst |")
    say("|---|---:|---:|---:|---:|")
    for kind in sorted({r["kind"] for r in conformal}):
        rs = [r for r in conformal if r["kind"] == kind]
        n_polyps = len({(r["run"], r["polyp"]) for r in rs})
        am, ap, aw = summary([number(r["aspect_error"]) for r in rs if r["visible"]])
        say(f"| {kind} | {n_polyps} | {len(rs)} | {sum(1 for r in rs if r in passed)} | "
            f"{percent(am)} / {percent(ap)} / {percent(aw)} |")
    # How much the reference itself moves between the eyes, which see the polyp from 0.65 mm
    # apart: a shape whose measure changes that much with so small a step is one the targets
    # cannot resolve (the rim of a flat polyp meets the wall at a grazing angle).
    references = collections.defaultdict(dict)
    for r in big:
        if r["map"] == "conformal" and r["reference_pixels"] >= 100:
            references[(r["run"], r["polyp"], r["pose"], r["kind"])][r["eye"]] = r["reference_aspect"]
    spreads = collections.defaultdict(list)
    for (run, polyp, pose, kind), by_eye in references.items():
        if len(by_eye) == 3:
            v = np.array(list(by_eye.values()))
            spreads[kind].append((v.max() - v.min()) / v.mean())
    say("The reference's own aspect across the three eyes (the same pinhole, 0.65 mm apart), median / p95: " +
        "; ".join(f"{kind} {percent(np.median(v))} / {percent(np.percentile(v, 95))}" for kind, v in sorted(spreads.items())) +
        ".")
    say("")
    # The linear baseline at the same polyp, pose and eye.
    linear = {(r["run"], r["polyp"], r["pose"], r["eye"]): r for r in big if r["targeted"] and r["map"] == "linear"}
    worst_c = max((number(r["aspect_error"]) for r in conformal if r["visible"]), default=float("nan"))
    worst_l = max((number(r["aspect_error"]) for r in linear.values() if r["visible"]), default=float("nan"))
    ratios = [number(linear[k]["aspect_error"]) / max(number(r["aspect_error"]), 1e-4)
              for r in conformal for k in [(r["run"], r["polyp"], r["pose"], r["eye"])]
              if k in linear and r["visible"] and linear[k]["visible"]]
    say(f"Worst aspect error over the targeted poses: conformal {percent(worst_c)}, linear {percent(worst_l)} "
        f"({worst_l / worst_c:.1f} times); per result the linear map's error is {np.median(ratios):.0f} times the "
        f"conformal map's at the median and {np.percentile(ratios, 5):.1f} times at the 5th percentile.")
    say("")

    # Measured against predicted, unoccluded polyps.
    unoccluded = [r for r in conformal if r["visible"] and not is_occluded(r) and r["predicted"]["found"]]
    for eye in EYES:
        rs = [r for r in unoccluded if r["eye"] == eye]
        gaps = [abs(number(r["aspect_error"]) - number(r["predicted"]["aspect_error"])) for r in rs]
        within = sum(1 for x in gaps if x <= 0.01)
        circle_within = sum(1 for r in rs if abs(number(r["aspect_error"]) - number(r["predicted_circle"]["aspect_error"])) <= 0.01)
        causes = collections.Counter(r["apart_from_prediction_because"] for r in rs
                                     if r["apart_from_prediction_because"])
        say(f"- {eye} eye, unoccluded: measured within a point of the prediction in {within} of {len(rs)} results "
            f"(median gap {100 * np.median(gaps) if gaps else float('nan'):.2f} points, worst "
            f"{100 * max(gaps) if gaps else float('nan'):.1f}; within a point of the circle's prediction in "
            f"{circle_within}); apart because: "
            f"{', '.join(f'{k} {v}' for k, v in causes.most_common()) or 'none'}.")
    occluded = [r for r in conformal if is_occluded(r)]
    say(f"- occluded (a fold or bend hides more than a tenth of the polyp's outline, or something in front of it "
        f"more than half a percent): {len(occluded)} of "
        f"{len(conformal)} targeted conformal results.")
    say("")
    if worst_conformal is not None:
        crop = os.path.join(worst_conformal["run"], "crops",
                            f"polyp_{worst_conformal['polyp']}_{worst_conformal['pose']}_{worst_conformal['eye']}.png")
        if os.path.exists(crop):
            shutil.copyfile(crop, worst_png)
        r = worst_conformal
        say(f"The worst conformal result: polyp {r['polyp']} of {os.path.basename(r['run'].rstrip('/'))} "
            f"({r['diameter_mm']:.1f} mm), {r['pose']}, {r['eye']} eye: aspect {percent(number(r['aspect_error']))} "
            f"(predicted {percent(number(r['predicted']['aspect_error']))}, centre eye "
            f"{percent(number(r['centre_aspect_error']))}, exact warp {percent(number(r['exact_warp_aspect_error']))}; "
            f"apart because: {r['apart_from_prediction_because'] or '–'}), unoccluded share "
            f"{r['reference_unoccluded_share']:.2f}.")
    open(out_md, "w").write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
