"""cvc.polyp_check, cvc.coverage and cvc.candidates against `cvc polyp-check`, `cvc coverage` and
`cvc candidates`: the same request gives the same document and the same files, and a bad request
the program's one-line error."""
import json
import os

import pytest

import cvc
from conftest import TMP, run_cvc

# One polyp, a pose on a wall and one over the missing ceiling, at a quarter of the cabin's walls.
POLYP_CHECK = ["--polyps", "3", "--poses", "wall,ceiling_50", "--maps", "conformal,linear", "--wall-size", "350x262"]
# Three frames of the phantom's path at small walls.
COVERAGE = ["--wall-size", "160x120", "--path-step", "8", "--frames", "3", "--patch-pictures", "1"]


def read_json(path):
    with open(path) as f:
        return json.load(f)


def read_bytes(path):
    with open(path, "rb") as f:
        return f.read()


def test_polyp_check_gives_the_document_and_crops_of_cvc_polyp_check(phantom):
    truth = phantom.replace(".nrrd", ".json")
    by_program = os.path.join(TMP, "polyp_check_program")
    made = run_cvc("polyp-check", phantom, "--truth", truth, *POLYP_CHECK, "--force", "-o", by_program)
    assert made.returncode == 0, made.stderr
    by_python = os.path.join(TMP, "polyp_check_python")
    document = cvc.polyp_check(cvc.load(phantom), truth, by_python, polyps=[3], poses=["wall", "ceiling_50"],
                               maps=["conformal", "linear"], wall_width=350, force=True)
    written = read_json(os.path.join(by_program, "polyp_check.json"))
    assert document == read_json(os.path.join(by_python, "polyp_check.json"))
    assert len(document["results"]) == 2 * 3 * 2  # poses x eyes x maps
    for key in ("plan", "results", "walls", "worst_aspect_error", "tolerance_mm", "warp"):
        assert document[key] == written[key], key
    assert document["volume"] == written["volume"] == os.path.abspath(phantom)
    assert read_bytes(os.path.join(by_python, "polyp_check.md")) == read_bytes(os.path.join(by_program, "polyp_check.md"))
    crops = sorted(os.listdir(os.path.join(by_program, "crops")))
    assert crops and crops == sorted(os.listdir(os.path.join(by_python, "crops")))
    for name in crops:
        assert read_bytes(os.path.join(by_python, "crops", name)) == read_bytes(os.path.join(by_program, "crops", name)), name
    # Without a folder it only returns the document; an occupied folder is refused without force.
    assert cvc.polyp_check(cvc.load(phantom), truth, polyps=[3], poses=["wall"], maps=["conformal"],
                           wall_width=350)["results"]
    with pytest.raises(RuntimeError, match="holds an earlier polyp check"):
        cvc.polyp_check(cvc.load(phantom), truth, by_python, polyps=[3], poses=["wall"], wall_width=350)


def test_polyp_check_refuses_what_the_program_refuses(phantom):
    truth = phantom.replace(".nrrd", ".json")
    volume = cvc.load(phantom)
    for keywords, option in (({"maps": ["linear"]}, "--maps linear"), ({"poses": ["nowhere"]}, "--poses nowhere"),
                             ({"display": "ic6"}, "--display ic6"), ({"angular_radius": 40.0}, None)):
        with pytest.raises(ValueError) as raised:
            cvc.polyp_check(volume, truth, **keywords)
        if option is None:
            continue
        printed = run_cvc("polyp-check", phantom, "--truth", truth, *option.split(), "-o", os.path.join(TMP, "refused"))
        assert printed.returncode != 0
        assert printed.stderr.strip() == "cvc: error: " + str(raised.value), option


def test_coverage_gives_the_summary_and_files_of_cvc_coverage(phantom):
    truth = phantom.replace(".nrrd", ".json")
    by_program = os.path.join(TMP, "coverage_program")
    made = run_cvc("coverage", phantom, "--path", truth, *COVERAGE, "--force", "-o", by_program)
    assert made.returncode == 0, made.stderr
    by_python = os.path.join(TMP, "coverage_python")
    volume = cvc.load(phantom)
    before = volume.array.copy()
    summary = cvc.coverage(volume, truth, by_python, wall_width=160, path_step=8, frames=3, patch_pictures=1, force=True)
    assert (volume.array == before).all()
    written = read_json(os.path.join(by_program, "coverage.json"))
    assert summary == read_json(os.path.join(by_python, "coverage.json"))
    del summary["timing"], written["timing"]  # seconds differ between runs
    assert summary == written
    assert 0.0 < summary["coverage_percent"] < 100.0
    for name in ("coverage.png", "unseen_patches.mrk.json", os.path.join("frame_0002", "sheet.png")):
        assert read_bytes(os.path.join(by_python, name)) == read_bytes(os.path.join(by_program, name)), name
    with pytest.raises(RuntimeError, match="not empty"):
        cvc.coverage(volume, truth, by_python, wall_width=160, frames=1)
    with pytest.raises(ValueError, match="directions must be"):
        cvc.coverage(volume, truth, os.path.join(TMP, "coverage_refused"), directions="sideways")


def test_candidates_gives_the_list_and_files_of_cvc_candidates(phantom):
    by_program = os.path.join(TMP, "candidates_program")
    made = run_cvc("candidates", phantom, "--pictures", "2", "--force", "-o", by_program)
    assert made.returncode == 0, made.stderr
    by_python = os.path.join(TMP, "candidates_python")
    volume = cvc.load(phantom)
    before = volume.array.copy()
    found = cvc.candidates(volume, by_python, pictures=2, force=True)
    assert (volume.array == before).all()
    written = read_json(os.path.join(by_program, "candidates.json"))
    assert found == read_json(os.path.join(by_python, "candidates.json"))
    del found["seconds"], written["seconds"]  # they differ between runs
    assert found == written
    assert len(found["candidates"]) >= 4 and found["path"]["frames"] > 100
    for name in ("candidates.mrk.json", "candidate_01.png", "candidate_02.png"):
        assert read_bytes(os.path.join(by_python, name)) == read_bytes(os.path.join(by_program, name)), name
    with pytest.raises(RuntimeError, match="exists"):
        cvc.candidates(volume, by_python)
    with pytest.raises(ValueError, match="--path-step must be"):
        cvc.candidates(volume, os.path.join(TMP, "candidates_refused"), path_step=0.0)
