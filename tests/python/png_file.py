"""A PNG reader in the standard library's terms (zlib and the five row filters of the PNG
specification), so the tests compare the Python module's arrays with `cvc render`'s files
through a decoder that is not the project's own."""
import struct
import zlib

import numpy


def _paeth(a, b, c):
    p = a + b - c
    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
    if pa <= pb and pa <= pc:
        return a
    return b if pb <= pc else c


def read_rgba(path):
    """The pixels of an 8-bit RGBA, non-interlaced PNG as an (h, w, 4) uint8 array."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("%s: not a PNG" % path)
    offset, chunks, header = 8, [], None
    while offset < len(data):
        (length,) = struct.unpack(">I", data[offset:offset + 4])
        kind = data[offset + 4:offset + 8]
        body = data[offset + 8:offset + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            chunks.append(body)
        offset += 12 + length
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour != 6 or interlace != 0:
        raise ValueError("%s: not 8-bit RGBA without interlace" % path)
    raw = zlib.decompress(b"".join(chunks))
    stride = width * 4
    rows = numpy.zeros((height, stride), dtype=numpy.uint8)
    previous = numpy.zeros(stride, dtype=numpy.int32)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = numpy.frombuffer(raw, dtype=numpy.uint8, count=stride, offset=y * (stride + 1) + 1).astype(numpy.int32)
        if kind == 0:
            out = line
        elif kind == 2:
            out = (line + previous) % 256
        else:  # Sub, Average and Paeth depend on the pixel to the left: byte by byte
            out = numpy.zeros(stride, dtype=numpy.int32)
            for x in range(stride):
                left = out[x - 4] if x >= 4 else 0
                up = previous[x]
                upper_left = previous[x - 4] if x >= 4 else 0
                if kind == 1:
                    predictor = left
                elif kind == 3:
                    predictor = (left + up) // 2
                elif kind == 4:
                    predictor = _paeth(left, up, upper_left)
                else:
                    raise ValueError("%s: unknown row filter %d" % (path, kind))
                out[x] = (line[x] + predictor) % 256
        rows[y] = out
        previous = out
    return rows.reshape(height, width, 4)
