"""The files `cvc colon`, `cvc coverage` and `cvc candidates` write for 3D Slicer, checked without Slicer: every
.mrk.json against the Markups schema's constraints (markups_schema.json), and against Slicer's
published schema too where a copy of it is at hand (CVC_MARKUPS_SCHEMA names one, or the shared
folder holds schemas/markups-schema-v1.0.3.json), positions taken back from
patient LPS to volume millimetres through the scan's own NRRD header, inverted here, within
0.01 mm of what colon.json and coverage.json say; the segmentation read here, label for label
equal to lumen.nrrd's colon segments on the same grid."""
import copy
import json
import os

import jsonschema
import numpy
import pytest

from conftest import CT, SHARED, TMP, run_cvc
from nrrd_file import patient_frame, read_nrrd, volume_mm_from_patient

HERE = os.path.dirname(os.path.abspath(__file__))
FIRST_SEGMENT_CODE = 10  # colon/colon_analysis.h: kLabelFirstSegment


def schemas():
    with open(os.path.join(HERE, "markups_schema.json")) as f:
        found = [json.load(f)]
    published = os.environ.get("CVC_MARKUPS_SCHEMA", "")
    shared_copy = os.path.join(SHARED, "..", "schemas", "markups-schema-v1.0.3.json")
    if not published and os.path.exists(shared_copy):
        published = shared_copy
    if published:
        with open(published) as f:
            found.append(json.load(f))
    return found


def validate(document):
    for schema in schemas():
        jsonschema.Draft7Validator(schema).validate(document)


def read_json(path):
    with open(path) as f:
        return json.load(f)


@pytest.fixture(scope="module")
def ct_colon():
    """`cvc colon` of the shared CT (it has several colon segments, and a patient frame whose x
    and y run against the voxel axes)."""
    folder = os.path.join(TMP, "slicer_colon")
    made = run_cvc("colon", CT, "--force", "-o", folder)
    assert made.returncode == 0, made.stderr
    return folder


def test_the_schema_refuses_what_slicer_would_not_read(ct_colon):
    document = read_json(os.path.join(ct_colon, "centreline_segment_1.mrk.json"))
    validate(document)
    for path, bad in ((("markups", 0, "coordinateSystem"), "XYZ"),
                      (("markups", 0, "controlPoints", 0, "position"), [1.0, 2.0]),
                      (("markups", 0, "type"), "Polyline"),
                      (("markups", 0, "display", "color"), [1.2, 0.0, 0.0])):
        broken = copy.deepcopy(document)
        place = broken
        for key in path[:-1]:
            place = place[key]
        place[path[-1]] = bad
        with pytest.raises(jsonschema.ValidationError):
            validate(broken)


def test_each_segments_centreline_is_a_curve_that_round_trips(ct_colon):
    report = read_json(os.path.join(ct_colon, "colon.json"))
    fields, _, _ = read_nrrd(CT)
    points = numpy.array(report["centreline_mm"])
    starts = report["segment_starts"] + [len(points)]
    assert len(starts) - 1 == len(report["segments"]) >= 2
    for s in range(len(starts) - 1):
        document = read_json(os.path.join(ct_colon, "centreline_segment_%d.mrk.json" % (s + 1)))
        validate(document)
        (markup,) = document["markups"]
        assert markup["type"] == "Curve" and markup["coordinateSystem"] == "LPS" and markup["coordinateUnits"] == "mm"
        lps = numpy.array([point["position"] for point in markup["controlPoints"]])
        expected = points[starts[s]:starts[s + 1]]
        assert lps.shape == expected.shape
        assert numpy.abs(volume_mm_from_patient(fields, lps) - expected).max() < 0.01
        assert numpy.abs(lps - expected).max() > 10.0  # the patient frame is another frame here
    assert not os.path.exists(os.path.join(ct_colon, "centreline_segment_%d.mrk.json" % len(starts)))


def test_the_lumen_segmentation_holds_the_colon_segments_on_the_scans_grid(ct_colon):
    report = read_json(os.path.join(ct_colon, "colon.json"))
    lumen_fields, _, codes = read_nrrd(os.path.join(ct_colon, "lumen.nrrd"))
    fields, key_values, labels = read_nrrd(os.path.join(ct_colon, "lumen.seg.nrrd"))
    ct_fields, _, _ = read_nrrd(CT)
    for key in ("sizes", "space", "space directions", "space origin"):
        assert fields[key] == lumen_fields[key], key
    for mine, scans in zip(patient_frame(fields), patient_frame(ct_fields)):
        assert numpy.allclose(mine, scans)
    segments = len(report["segments"])
    expected = numpy.where(codes >= FIRST_SEGMENT_CODE, codes - FIRST_SEGMENT_CODE + 1, 0)
    assert numpy.array_equal(labels, expected)
    assert labels.max() == segments
    for s in range(segments):
        key = "Segment%d_" % s
        assert key_values[key + "LabelValue"] == str(s + 1)
        assert key_values[key + "Name"] == "colon segment %d" % (s + 1)
        k, j, i = numpy.nonzero(labels == s + 1)
        extent = [i.min(), i.max(), j.min(), j.max(), k.min(), k.max()]
        assert key_values[key + "Extent"] == " ".join(str(n) for n in extent)
    assert ("Segment%d_ID" % segments) not in key_values
    assert key_values["Segmentation_MasterRepresentation"] == "Binary labelmap"


def test_the_unseen_patches_are_a_fiducial_list_at_the_patches_centres(phantom):
    truth = phantom.replace(".nrrd", ".json")
    folder = os.path.join(TMP, "slicer_coverage")
    made = run_cvc("coverage", phantom, "--path", truth, "--wall-size", "120x90", "--path-step", "8", "--frames", "4",
                   "--patch-pictures", "1", "--force", "-o", folder)
    assert made.returncode == 0, made.stderr
    summary = read_json(os.path.join(folder, "coverage.json"))
    document = read_json(os.path.join(folder, "unseen_patches.mrk.json"))
    validate(document)
    (markup,) = document["markups"]
    assert markup["type"] == "Fiducial"
    patches = summary["patches"]
    assert len(patches) >= 1 and len(markup["controlPoints"]) == len(patches)
    fields, _, _ = read_nrrd(phantom)
    lps = numpy.array([point["position"] for point in markup["controlPoints"]])
    centres = numpy.array([patch["centre_mm"] for patch in patches])
    assert numpy.abs(volume_mm_from_patient(fields, lps) - centres).max() < 0.01
    assert [point["label"] for point in markup["controlPoints"]] == ["patch %d" % (p + 1) for p in range(len(patches))]


def test_the_polyp_candidates_are_a_fiducial_list_at_their_centres(phantom):
    folder = os.path.join(TMP, "slicer_candidates")
    made = run_cvc("candidates", phantom, "--pictures", "0", "--force", "-o", folder)
    assert made.returncode == 0, made.stderr
    candidates = read_json(os.path.join(folder, "candidates.json"))["candidates"]
    document = read_json(os.path.join(folder, "candidates.mrk.json"))
    validate(document)
    (markup,) = document["markups"]
    assert markup["type"] == "Fiducial"
    assert len(candidates) >= 1 and len(markup["controlPoints"]) == len(candidates)
    fields, _, _ = read_nrrd(phantom)
    lps = numpy.array([point["position"] for point in markup["controlPoints"]])
    centres = numpy.array([candidate["centre_mm"] for candidate in candidates])
    assert numpy.abs(volume_mm_from_patient(fields, lps) - centres).max() < 0.01
    assert [point["label"] for point in markup["controlPoints"]] == ["candidate %d" % c["rank"] for c in candidates]
