"""Images and volumes as the benchmark scripts read and compare them: uncompressed NRRD (volumes,
hit images), PNG, and the error measures of an image against a reference (RMSE, PSNR, SSIM;
first-hit distances). Imported by scripts/bench/bench_raycaster.py (and its plots and VTK worker),
bench_yardstick.py and bench_colon.py; needs Debian's /usr/bin/python3 with python3-numpy and
python3-pil.
"""
import re

import numpy as np


# ---------------------------------------------------------------------------------------------
# Files
# ---------------------------------------------------------------------------------------------

def read_nrrd(path):
    """Header fields and the array (z, y, x[, c]) of an uncompressed little-endian NRRD."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"\n\n")
    fields = {}
    for line in data[:end].decode("ascii").splitlines()[1:]:
        if line.startswith("#") or ":" not in line:
            continue
        key, value = line.split(":", 1)
        fields[key.strip()] = value.strip().lstrip("=")
    sizes = [int(s) for s in fields["sizes"].split()]
    dtype = {"short": "<i2", "int16": "<i2", "float": "<f4", "uchar": "u1", "unsigned char": "u1"}[fields["type"]]
    if fields.get("encoding", "raw") != "raw":
        raise ValueError(f"{path}: only raw NRRD is read here")
    array = np.frombuffer(data[end + 2:], dtype=dtype)[: int(np.prod(sizes))].reshape(sizes[::-1])
    return fields, array


def spacing_of(fields):
    if "space directions" in fields:
        vectors = re.findall(r"\(([^)]*)\)", fields["space directions"])
        return [float(np.linalg.norm([float(v) for v in vec.split(",")])) for vec in vectors]
    return [float(s) for s in fields["spacings"].split()]


def read_png(path):
    from PIL import Image
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.float64) / 255.0


def write_png(path, rgb):
    from PIL import Image
    Image.fromarray(np.clip(np.round(rgb * 255.0), 0, 255).astype(np.uint8)).save(path)


# ---------------------------------------------------------------------------------------------
# Error measures
# ---------------------------------------------------------------------------------------------

def gaussian_blur(image, sigma=1.5, radius=5):
    x = np.arange(-radius, radius + 1)
    kernel = np.exp(-0.5 * (x / sigma) ** 2)
    kernel /= kernel.sum()
    out = image
    for axis in (0, 1):
        out = sum(kernel[i] * np.roll(out, i - radius, axis=axis) for i in range(len(kernel)))
    # np.roll wraps around; drop the border where it did.
    return out[radius:-radius, radius:-radius]


def ssim(a, b):
    """Mean SSIM (Wang et al. 2004: Gaussian window sigma 1.5, K1 0.01, K2 0.03) of the luma."""
    weights = np.array([0.299, 0.587, 0.114])
    x, y = a @ weights, b @ weights
    c1, c2 = 0.01 ** 2, 0.03 ** 2
    mx, my = gaussian_blur(x), gaussian_blur(y)
    sxx = gaussian_blur(x * x) - mx * mx
    syy = gaussian_blur(y * y) - my * my
    sxy = gaussian_blur(x * y) - mx * my
    s = ((2 * mx * my + c1) * (2 * sxy + c2)) / ((mx * mx + my * my + c1) * (sxx + syy + c2))
    return float(s.mean())


def image_errors(path, reference_path):
    a, b = read_png(path), read_png(reference_path)
    rmse = float(np.sqrt(np.mean((a - b) ** 2)))
    psnr = float("inf") if rmse == 0 else 20.0 * np.log10(1.0 / rmse)
    return {"rmse": rmse, "psnr": psnr, "ssim": ssim(a, b)}


def hit_errors(path, reference_path):
    """Mean and 95th percentile distance (mm) between first hits where both rays hit, and the
    fraction of pixels where one hits and the other does not."""
    _, h = read_nrrd(path)
    _, r = read_nrrd(reference_path)
    h, r = h.reshape(-1, 4).astype(np.float64), r.reshape(-1, 4).astype(np.float64)
    both = (h[:, 3] > 0.5) & (r[:, 3] > 0.5)
    mismatch = float(np.mean((h[:, 3] > 0.5) != (r[:, 3] > 0.5)))
    d = np.linalg.norm(h[both, :3] - r[both, :3], axis=1)
    if d.size == 0:
        return {"hit_mean_mm": float("nan"), "hit_p95_mm": float("nan"), "hit_mismatch": mismatch}
    return {"hit_mean_mm": float(d.mean()), "hit_p95_mm": float(np.percentile(d, 95)), "hit_mismatch": mismatch}
