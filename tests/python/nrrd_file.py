"""A NRRD reader in the standard library's and numpy's terms (raw or gzip, little-endian, the
scalar types cvc writes), so the tests read the program's volumes, labels and segmentations
through a decoder that is not the project's own."""
import gzip

import numpy

_TYPES = {"short": "<i2", "int16": "<i2", "uchar": "u1", "uint8": "u1", "unsigned char": "u1"}


def read_nrrd(path):
    """(fields, key_values, voxels): the header's `field: value` and `key:=value` lines, and the
    voxels as a (z, y, x) array."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"\n\n")
    fields, key_values = {}, {}
    for line in data[:end].decode().splitlines()[1:]:
        if line.startswith("#"):
            continue
        if ":=" in line:
            key, value = line.split(":=", 1)
            key_values[key] = value
        elif ":" in line:
            key, value = line.split(":", 1)
            fields[key.strip()] = value.strip()
    payload = data[end + 2:]
    if fields["encoding"] == "gzip":
        payload = gzip.decompress(payload)
    elif fields["encoding"] != "raw":
        raise ValueError("%s: encoding %s" % (path, fields["encoding"]))
    if fields.get("endian", "little") != "little":
        raise ValueError("%s: big-endian" % path)
    x, y, z = (int(n) for n in fields["sizes"].split())
    voxels = numpy.frombuffer(payload, dtype=_TYPES[fields["type"]], count=x * y * z).reshape(z, y, x)
    return fields, key_values, voxels


def patient_frame(fields):
    """(origin, columns): patient LPS = origin + columns @ (index) for the header's geometry, the
    columns being the space directions (spacing included)."""
    assert fields["space"] == "left-posterior-superior"
    columns = numpy.array([[float(n) for n in column.strip("()").split(",")] for column in fields["space directions"].split()]).T
    origin = numpy.array([float(n) for n in fields["space origin"].strip("()").split(",")])
    return origin, columns


def volume_mm_from_patient(fields, lps):
    """Volume millimetres (index x spacing, cvc's frame) of patient LPS points, by inverting the
    header's geometry here."""
    origin, columns = patient_frame(fields)
    spacing = numpy.linalg.norm(columns, axis=0)
    index = numpy.linalg.solve(columns, (numpy.asarray(lps, dtype=float) - origin).T).T
    return index * spacing
