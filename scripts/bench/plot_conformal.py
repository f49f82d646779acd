#!/usr/bin/python3
"""Pictures for docs/conformal.md from the data `conformal_measure images RES DIR` writes.

usage: /usr/bin/python3 scripts/bench/plot_conformal.py DATA_DIR OUT_DIR

Each picture shows the box's present walls unfolded around the floor (front above, back
below, left and right at the sides), as seen from inside, for the conformal map and for the
linear baseline; content from the missing walls is tinted orange. Needs Debian's python3-numpy and python3-matplotlib; not used by CI.
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

WIDTH, HEIGHT, CHANNELS = 1024, 512, 9
# name: (box size in metres, the walls it lacks)
BOXES = {
    "cube": ((2.4, 2.4, 2.4), ("ceiling",)),
    "cabin": ((2.95, 2.21, 2.95), ("ceiling",)),
    "cave4": ((2.4, 2.4, 2.4), ("ceiling", "back")),
}
PIXELS_PER_METRE = 160


def load(path):
    data = np.fromfile(path, dtype=np.float32)
    return data.reshape(HEIGHT, WIDTH, CHANNELS)


def unfolded_directions(size, missing):
    """Display directions of every pixel of the unfolded present walls, and a mask of them."""
    w, h, d = size
    cols = int((h + w + h) * PIXELS_PER_METRE)
    rows = int((h + d + h) * PIXELS_PER_METRE)
    x = (np.arange(cols) + 0.5) / PIXELS_PER_METRE
    y = (np.arange(rows) + 0.5) / PIXELS_PER_METRE
    gx, gy = np.meshgrid(x, y)
    points = np.full((rows, cols, 3), np.nan)
    inside = np.zeros((rows, cols), dtype=bool)

    def place(mask, p):
        points[mask] = np.stack([c[mask] for c in p], axis=-1)
        inside[mask] = True

    a = (gx - h) / w  # across the floor's width
    b = (gy - h) / d  # across the floor's depth
    floor = (a >= 0) & (a < 1) & (b >= 0) & (b < 1)
    place(floor, (-w / 2 + a * w, np.full_like(a, -h / 2), -d / 2 + b * d))
    front = (a >= 0) & (a < 1) & (gy < h)
    place(front, (-w / 2 + a * w, h / 2 - gy / h * h, np.full_like(a, -d / 2)))
    back = (a >= 0) & (a < 1) & (gy >= h + d)
    if "back" not in missing:
        place(back, (-w / 2 + a * w, -h / 2 + (gy - h - d), np.full_like(a, d / 2)))
    left = (b >= 0) & (b < 1) & (gx < h)
    place(left, (np.full_like(a, -w / 2), h / 2 - gx, -d / 2 + b * d))
    right = (b >= 0) & (b < 1) & (gx >= h + w)
    place(right, (np.full_like(a, w / 2), -h / 2 + (gx - h - w), -d / 2 + b * d))
    norm = np.linalg.norm(points, axis=-1, keepdims=True)
    return points / norm, inside


def sample(data, directions):
    """Nearest sample of the equirectangular data (longitude atan2(z, x), latitude asin(y))."""
    lon = np.arctan2(directions[..., 2], directions[..., 0])
    lat = np.arcsin(np.clip(directions[..., 1], -1, 1))
    i = np.clip(((lon + np.pi) / (2 * np.pi) * WIDTH).astype(int), 0, WIDTH - 1)
    j = np.clip(((np.pi / 2 - lat) / np.pi * HEIGHT).astype(int), 0, HEIGHT - 1)
    return data[j, i]


def on_missing_wall(scene, size, missing):
    """Whether each scene direction (from the box centre) leaves the box through a missing wall."""
    w, h, d = size
    half = np.array([w, h, d]) / 2
    axes = {"ceiling": (1, 1.0), "back": (2, 1.0)}
    result = np.zeros(scene.shape[:-1], dtype=bool)
    for wall in missing:
        axis, sign = axes[wall]
        along = sign * scene[..., axis]
        reach = half[axis] / np.maximum(along, 1e-9)
        others = [a for a in range(3) if a != axis]
        inside = np.ones_like(result)
        for a in others:
            inside &= np.abs(reach * scene[..., a]) <= half[a]
        result |= (along > 0) & inside
    return result


def checkerboard(scene, size, missing):
    """A checkerboard in longitude and Mercator latitude (a conformal chart, so its cells are
    squares on the sphere); cells whose direction lies on a missing wall are tinted orange."""
    cell = np.pi / 12
    lon = np.arctan2(scene[..., 2], scene[..., 0])
    mercator = np.arctanh(np.clip(scene[..., 1], -0.999999, 0.999999))
    parity = (np.floor(lon / cell) + np.floor(mercator / cell)) % 2
    on_ceiling = on_missing_wall(scene, size, missing)
    rgb = np.stack([parity] * 3, axis=-1) * 0.85 + 0.1
    tint = np.array([1.0, 0.55, 0.1])
    rgb[on_ceiling] = rgb[on_ceiling] * tint
    return rgb


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    data_dir, out_dir = sys.argv[1], sys.argv[2]
    for name, (size, missing) in BOXES.items():
        data = load(f"{data_dir}/conformal_{name}.f32")
        directions, inside = unfolded_directions(size, missing)
        values = sample(data, np.nan_to_num(directions))

        fig, axes = plt.subplots(1, 2, figsize=(12, 6.2))
        for axis, title, first in ((axes[0], "conformal map F", 0), (axes[1], "linear baseline", 3)):
            image = checkerboard(values[..., first:first + 3], size, missing)
            image[~inside] = 1.0
            axis.imshow(image, interpolation="lanczos")
            axis.set_title(title)
            axis.axis("off")
        lacking = " and ".join(missing)
        fig.suptitle(f"{name}: scene checkerboard (15° cells, {lacking} content orange) on the unfolded walls")
        fig.tight_layout()
        fig.savefig(f"{out_dir}/conformal_checkerboard_{name}.png", dpi=110, bbox_inches="tight")
        plt.close(fig)

        fig, axes = plt.subplots(1, 2, figsize=(12, 6.2))
        for axis, title, channel in ((axes[0], "conformal map F", 6), (axes[1], "linear baseline", 7)):
            k = values[..., channel]
            image = np.log10(np.clip(k - 1.0, 1e-7, 10.0))
            image[~inside] = np.nan
            shown = axis.imshow(image, cmap="viridis", vmin=-6, vmax=1, interpolation="nearest")
            axis.set_title(title)
            axis.axis("off")
        fig.colorbar(shown, ax=axes, shrink=0.8, label="log10(K - 1),  K = σmax / σmin")
        fig.suptitle(f"{name}: quasi-conformal distortion of the baked 256² map (finite differences)")
        fig.savefig(f"{out_dir}/conformal_k_{name}.png", dpi=110, bbox_inches="tight")
        plt.close(fig)
        print(f"wrote {out_dir}/conformal_checkerboard_{name}.png and conformal_k_{name}.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
