"""The Python module against `cvc` itself: the same requests give the same pixels, the same
analysis and the same one-line errors (conftest.py: what the tests share)."""
import json
import os
import threading
import time

import numpy
import pytest

import cvc
from conftest import CT, TMP, run_cvc
from nrrd_file import read_nrrd
from png_file import read_rgba

WALLS = ("front", "back", "left", "right", "floor")


def test_a_volume_from_numpy_keeps_its_voxels_and_geometry():
    array = (numpy.arange(4 * 5 * 6, dtype=numpy.int16) - 60).reshape(4, 5, 6)  # (z, y, x)
    volume = cvc.Volume(array, spacing_mm=(0.5, 0.7, 1.25), origin_mm=(10, 20, 30))
    assert volume.shape == (4, 5, 6)
    assert volume.spacing_mm == (0.5, 0.7, 1.25)
    assert volume.origin_mm == (10, 20, 30)
    assert numpy.array_equal(volume.array, array)
    assert not volume.array.flags.writeable
    rounded = cvc.Volume(array.astype(numpy.float32) + 0.4, spacing_mm=(1, 1, 1))
    assert numpy.array_equal(rounded.array, array)


def test_bad_arrays_and_files_give_the_one_line_errors_of_cvc():
    with pytest.raises(ValueError, match="3-D"):
        cvc.Volume(numpy.zeros((4, 4), dtype=numpy.int16), spacing_mm=(1, 1, 1))
    with pytest.raises(ValueError, match="finite HU"):
        cvc.Volume(numpy.full((2, 2, 2), numpy.nan, dtype=numpy.float32), spacing_mm=(1, 1, 1))
    with pytest.raises(ValueError, match="int16 or float32"):
        cvc.Volume(numpy.zeros((2, 2, 2), dtype=numpy.float64), spacing_mm=(1, 1, 1))
    with pytest.raises(RuntimeError):  # absurd spacing, refused as a loader refuses it
        cvc.Volume(numpy.zeros((2, 2, 2), dtype=numpy.int16), spacing_mm=(0, 1, 1))
    missing = os.path.join(TMP, "no_such_volume.nrrd")
    with pytest.raises(RuntimeError) as raised:
        cvc.load(missing)
    printed = run_cvc("info", missing)
    assert printed.returncode != 0
    assert printed.stderr.strip() == "cvc: error: " + str(raised.value)


def test_load_reads_the_shared_ct_voxel_for_voxel():
    volume = cvc.load(CT)
    fields, _, voxels = read_nrrd(CT)
    assert fields["type"] == "short" and fields["encoding"] == "raw"
    assert volume.shape == voxels.shape
    assert numpy.array_equal(volume.array, voxels)
    directions = [[float(n) for n in column.strip("()").split(",")] for column in fields["space directions"].split()]
    assert numpy.allclose(volume.spacing_mm, [numpy.linalg.norm(column) for column in directions])
    assert numpy.allclose(volume.origin_mm, [float(n) for n in fields["space origin"].strip("()").split(",")])


def test_render_equals_cvc_render_pixel_for_pixel_with_hits_where_it_hit():
    volume = cvc.load(CT)
    png = os.path.join(TMP, "ct_view.png")
    os.makedirs(TMP, exist_ok=True)
    camera = ["--position", "180,-700,160", "--look-at", "180,150,160", "--up", "0,0,1", "--size", "160x120"]
    made = run_cvc("render", CT, *camera, "--iso", "-500", "--force", "-o", png)
    assert made.returncode == 0, made.stderr
    rgba, hits = cvc.render(volume, (180, -700, 160), (180, 150, 160), (0, 0, 1), size=(160, 120), iso=-500, hits=True)
    assert rgba.shape == (120, 160, 4) and rgba.dtype == numpy.uint8
    assert numpy.array_equal(rgba, read_rgba(png))
    assert hits.shape == (120, 160, 3) and hits.dtype == numpy.float32
    hit = ~numpy.isnan(hits[:, :, 0])
    assert 0.05 < hit.mean() < 0.95  # the body in the middle, nothing around it
    extent = numpy.array(volume.shape[::-1]) * numpy.array(volume.spacing_mm)
    inside = hits[hit]
    assert numpy.all(inside >= -2.0) and numpy.all(inside <= extent + 2.0)
    assert numpy.all(rgba[~hit][:, :3].max(axis=1) <= rgba[hit][:, :3].max())  # misses are background


def test_render_display_equals_the_cabin_walls_of_cvc_render(phantom):
    truth = phantom.replace(".nrrd", ".json")
    folder = os.path.join(TMP, "ic5_polyp")
    made = run_cvc("render", phantom, "--display", "ic5", "--path", truth, "--polyp", "3", "--polyp-elevation", "50",
                   "--scale", "4", "--force", "-o", folder)
    assert made.returncode == 0, made.stderr
    volume = cvc.load(phantom)
    walls = cvc.render_display(volume, "ic5", path=truth, polyp=3, polyp_elevation=50, scale=4)
    for eye in ("left", "right"):
        for wall in WALLS:
            expected = read_rgba(os.path.join(folder, "frame_0000", eye, wall + ".png"))
            assert numpy.array_equal(walls[eye][wall], expected), (eye, wall)
    with open(os.path.join(folder, "render.json")) as manifest_file:
        pose = json.load(manifest_file)["poses"][0]
    for key in ("position_mm", "forward", "up"):
        assert numpy.allclose(walls["pose"][key], pose[key]), key


def test_colon_gives_what_cvc_colon_writes(phantom):
    folder = os.path.join(TMP, "colon")
    made = run_cvc("colon", phantom, "--force", "-o", folder)
    assert made.returncode == 0, made.stderr
    with open(os.path.join(folder, "colon.json")) as written_file:
        written = json.load(written_file)
    volume = cvc.load(phantom)
    before = volume.array.copy()
    result = cvc.colon(volume)
    assert numpy.array_equal(volume.array, before)  # the analysis worked on a copy
    assert result["centreline_mm"] == written["centreline_mm"]
    assert result["segment_starts"] == written["segment_starts"]
    assert result["lumen"].shape == volume.shape and result["lumen"].dtype == numpy.uint8
    assert result["lumen"].sum() > 1000
    # Every centreline point lies in the lumen the analysis found.
    spacing = numpy.array(volume.spacing_mm)
    for x, y, z in result["centreline_mm"][::25]:
        i, j, k = (numpy.round(numpy.array([x, y, z]) / spacing)).astype(int)
        assert result["lumen"][k, j, i] == 1


def test_rendering_releases_the_gil():
    volume = cvc.load(CT)
    cvc.render(volume, (180, -250, 160), (180, 150, 160), (0, 0, 1), size=(64, 64))  # the device and texture first
    ticks = [0]
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks[0] += 1

    counter = threading.Thread(target=count)
    counter.start()
    start = time.monotonic()
    cvc.render(volume, (180, -250, 160), (180, 150, 160), (0, 0, 1), size=(1024, 1024))
    seconds = time.monotonic() - start
    stop.set()
    counter.join()
    # Python code ran on the other thread all through the render (it could not with the GIL held).
    assert ticks[0] > 10000 * max(seconds, 0.01), (ticks[0], seconds)
