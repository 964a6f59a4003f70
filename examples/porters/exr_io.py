"""Minimal OpenEXR reader/writer in pure Python (no numpy, no OpenImageIO).

Written from the OpenEXR file-layout document (openexr.com, "OpenEXR File Layout": magic
20000630, version field, header attributes, chlist, line-offset table, scanline chunks; the
ZIP/ZIPS/RLE predictor and byte interleave of "Compression"). Reads single-part scanline files
with HALF or FLOAT channels, compression NONE, RLE, ZIPS or ZIP; writes single-part scanline
FLOAT RGBA with no compression. That is what hdrconform exports (float32 RGBA) and reads back.
"""
import struct
import zlib
from array import array

MAGIC = 20000630
_LINES_PER_BLOCK = {0: 1, 1: 1, 2: 1, 3: 16}  # NONE, RLE, ZIPS, ZIP
_PIXEL_SIZE = {0: 4, 1: 2, 2: 4}  # UINT, HALF, FLOAT


class ExrError(Exception):
    pass


def _cstr(buf, pos):
    end = buf.index(b"\0", pos)
    return buf[pos:end].decode("latin-1"), end + 1


def _undo_predictor_interleave(raw):
    # Predictor: each byte after the first is stored as (b[i] - b[i-1] + 128) mod 256.
    t = bytearray(raw)
    for i in range(1, len(t)):
        t[i] = (t[i - 1] + t[i] - 128) & 0xFF
    # Interleave: the first half holds the even-indexed bytes, the second half the odd ones.
    half = (len(t) + 1) // 2
    out = bytearray(len(t))
    out[0::2] = t[:half]
    out[1::2] = t[half:]
    return bytes(out)


def _rle_decode(data):
    out = bytearray()
    i = 0
    n = len(data)
    while i < n:
        count = struct.unpack_from("b", data, i)[0]
        i += 1
        if count < 0:
            out += data[i:i - count]
            i -= count
        else:
            out += bytes([data[i]]) * (count + 1)
            i += 1
    return bytes(out)


def read_exr(path):
    """Returns (width, height, {channel name: flat list of floats, row-major})."""
    with open(path, "rb") as f:
        buf = f.read()
    if len(buf) < 8 or struct.unpack_from("<i", buf, 0)[0] != MAGIC:
        raise ExrError(f"{path}: not an OpenEXR file")
    version = struct.unpack_from("<i", buf, 4)[0]
    if version & 0x1A00:  # tiled, multi-part or deep
        raise ExrError(f"{path}: only single-part scanline files are read (version {version:#x})")
    pos = 8
    attrs = {}
    while buf[pos] != 0:
        name, pos = _cstr(buf, pos)
        typ, pos = _cstr(buf, pos)
        size = struct.unpack_from("<i", buf, pos)[0]
        pos += 4
        attrs[name] = (typ, buf[pos:pos + size])
        pos += size
    pos += 1
    channels = []
    chl = attrs["channels"][1]
    p = 0
    while chl[p] != 0:
        cname, p = _cstr(chl, p)
        ptype = struct.unpack_from("<i", chl, p)[0]
        xs, ys = struct.unpack_from("<ii", chl, p + 8)
        p += 16
        if xs != 1 or ys != 1:
            raise ExrError(f"{path}: subsampled channel {cname}")
        channels.append((cname, ptype))
    compression = attrs["compression"][1][0]
    if compression not in _LINES_PER_BLOCK:
        raise ExrError(f"{path}: compression {compression} is not read (NONE, RLE, ZIPS, ZIP are)")
    xmin, ymin, xmax, ymax = struct.unpack("<iiii", attrs["dataWindow"][1])
    width, height = xmax - xmin + 1, ymax - ymin + 1
    lpb = _LINES_PER_BLOCK[compression]
    nblocks = (height + lpb - 1) // lpb
    offsets = struct.unpack_from(f"<{nblocks}Q", buf, pos)
    planes = {c: [0.0] * (width * height) for c, _ in channels}
    for off in offsets:
        y, size = struct.unpack_from("<ii", buf, off)
        data = buf[off + 8:off + 8 + size]
        nlines = min(lpb, ymax - y + 1)
        expected = nlines * width * sum(_PIXEL_SIZE[t] for _, t in channels)
        if compression == 0 or len(data) == expected:
            raw = data
        elif compression == 1:
            raw = _undo_predictor_interleave(_rle_decode(data))
        else:
            raw = _undo_predictor_interleave(zlib.decompress(data))
        q = 0
        for line in range(nlines):
            row = (y - ymin + line) * width
            for cname, ptype in channels:
                if ptype == 1:
                    vals = struct.unpack_from(f"<{width}e", raw, q)
                elif ptype == 2:
                    vals = struct.unpack_from(f"<{width}f", raw, q)
                else:
                    vals = struct.unpack_from(f"<{width}I", raw, q)
                q += width * _PIXEL_SIZE[ptype]
                planes[cname][row:row + width] = vals
    return width, height, planes


def _attr(name, typ, payload):
    return name.encode() + b"\0" + typ.encode() + b"\0" + struct.pack("<i", len(payload)) + payload


def write_exr(path, width, height, planes):
    """Writes planes {'R','G','B','A': flat lists of floats} as FLOAT channels, no compression."""
    names = sorted(planes)  # OpenEXR stores channels in alphabetical order
    chl = b"".join(n.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for n in names) + b"\0"
    header = struct.pack("<ii", MAGIC, 2)
    header += _attr("channels", "chlist", chl)
    header += _attr("compression", "compression", b"\0")
    box = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    header += _attr("dataWindow", "box2i", box)
    header += _attr("displayWindow", "box2i", box)
    header += _attr("lineOrder", "lineOrder", b"\0")
    header += _attr("pixelAspectRatio", "float", struct.pack("<f", 1.0))
    header += _attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0))
    header += _attr("screenWindowWidth", "float", struct.pack("<f", 1.0))
    header += b"\0"
    line_bytes = width * 4 * len(names)
    first = len(header) + 8 * height
    offsets = struct.pack(f"<{height}Q", *[first + y * (8 + line_bytes) for y in range(height)])
    chunks = []
    for y in range(height):
        row = array("f")
        for n in names:
            row.extend(planes[n][y * width:(y + 1) * width])
        if row.itemsize != 4:
            raise ExrError("array('f') is not 32-bit on this platform")
        chunks.append(struct.pack("<ii", y, line_bytes) + row.tobytes())
    with open(path, "wb") as f:
        f.write(header + offsets + b"".join(chunks))
