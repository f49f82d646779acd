"""The figures of scripts/bench/bench_raycaster.py: time against error with its Pareto front, and our
images beside VTK's. Needs Debian's /usr/bin/python3 with python3-matplotlib.
"""
import os

from bench_images import read_png


def pareto(points, key="rmse"):
    front, best = [], float("inf")
    for p in sorted(points, key=lambda p: (p["ms"], p[key])):
        if p[key] < best:
            front.append(p)
            best = p[key]
    return front


def plot_pareto(scene, sweeps, vtk, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.2))
    for ax, mode in zip(axes, ("iso", "composite")):
        points = sweeps[mode]["points"]
        front = pareto(points)
        on_front = {id(p) for p in front}
        for p in points:
            colour = "tab:red" if not p["skip"] else ("tab:green" if p["adaptive"] else "tab:blue")
            marker = "s" if p["filter"] == "tricubic" else "o"
            ax.scatter(p["ms"], p["rmse"], c=colour, marker=marker, s=36, zorder=3)
            # Label the front in full; the points behind it are many and close, so label them faintly.
            if id(p) in on_front:
                ax.annotate(p["label"], (p["ms"], p["rmse"]), fontsize=7, xytext=(4, 4), textcoords="offset points")
            else:
                ax.annotate(p["label"], (p["ms"], p["rmse"]), fontsize=5, xytext=(3, -8), textcoords="offset points",
                            color="0.45")
        ax.plot([p["ms"] for p in front], [p["rmse"] for p in front], "k--", lw=1, zorder=2, label="Pareto front")
        if vtk and mode in vtk:
            v = vtk[mode]["points"]
            ax.scatter([p["ms"] for p in v], [p["rmse_vs_vtk"] for p in v], c="tab:purple", marker="^", s=40,
                       zorder=3, label="VTK fixed-point (CPU), error vs VTK's 0.1 vx image")
            for p in v:
                ax.annotate(f"VTK {p['step']:g} vx", (p["ms"], p["rmse_vs_vtk"]), fontsize=6.5, xytext=(3, -9),
                            textcoords="offset points", color="tab:purple")
        ax.scatter([], [], c="tab:blue", marker="o", label="skipping, trilinear")
        ax.scatter([], [], c="tab:blue", marker="s", label="skipping, tricubic")
        ax.scatter([], [], c="tab:red", marker="o", label="no skipping")
        ax.scatter([], [], c="tab:green", marker="o", label="adaptive step")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("ray casting, device time (ms, median)")
        ax.set_ylabel("RMSE, RGB in [0, 1] (ours: against the tricubic 0.1 vx reference)")
        ax.set_title(f"{scene['name']}: {mode} mode")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, loc="best", framealpha=0.6)
    fig.suptitle(f"Time against error: {scene['title']}, {scene['camera']['size']}", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def side_by_side(scene, sweeps, vtk, work, path):
    """Our reference, our default setting, VTK at the same step, VTK's reference; per mode."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    modes = [m for m in ("iso", "composite") if m in vtk]
    fig, axes = plt.subplots(len(modes), 4, figsize=(13, 3.4 * len(modes)), squeeze=False)
    for row, mode in zip(axes, modes):
        ours = next(p for p in sweeps[mode]["points"]
                    if p["step"] == 0.5 and p["filter"] == "trilinear" and p["skip"] and not p["adaptive"]
                    and p.get("refine", 6) == 6)
        n = sweeps[mode]["points"].index(ours)
        v = next(p for p in vtk[mode]["points"] if p["step"] == 0.5)
        panels = [(sweeps[mode]["reference_png"], f"ours, reference ({sweeps[mode]['reference_ms']:.0f} ms)"),
                  (os.path.join(work, f"{scene['name']}_{mode}_{n}.png"),
                   f"ours, 0.5 vx trilinear ({ours['ms']:.0f} ms, RMSE {ours['rmse']:.3f})"),
                  (v["png"], f"VTK, 0.5 vx ({v['ms']:.0f} ms, RMSE {v['rmse_vs_ours']:.3f})"),
                  (vtk[mode]["reference_png"], f"VTK, 0.1 vx ({vtk[mode]['reference_ms']:.0f} ms)")]
        for ax, (png, title) in zip(row, panels):
            ax.imshow(read_png(png))
            ax.set_title(f"{mode}: {title}", fontsize=7.5)
            ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
