#!/usr/bin/env python3
# check_png.py FILE:W:H... - each a valid PNG (chunk CRCs, zlib, row filters decoded here: no image tool
# starts per file) of that size, 8-bit RGBA, with lit pixels (max RGB > 0) and coverage (mean alpha > 0).
import struct, sys, zlib
def check(path, w, h):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        return "not a PNG"
    pos, idat, hdr = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if zlib.crc32(kind + body) != struct.unpack(">I", data[pos + 8 + n:pos + 12 + n])[0]:
            return "bad CRC in " + kind.decode()
        if kind == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    if not hdr or hdr[:4] != (w, h, 8, 6):
        return "header %s, expected %dx%d 8-bit RGBA" % (hdr, w, h)
    raw, stride, prev, rows = zlib.decompress(idat), w * 4, bytearray(w * 4), []
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - 4] if i >= 4 else 0
            b, c = prev[i], prev[i - 4] if i >= 4 else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    px = b"".join(rows)
    rgb_max = max(max(px[0::4]), max(px[1::4]), max(px[2::4]))
    alpha_mean = sum(px[3::4]) / (w * h)
    if rgb_max == 0 or alpha_mean == 0:
        return "blank: max RGB %d, mean alpha %.1f" % (rgb_max, alpha_mean)
    return None
failed = 0
for arg in sys.argv[1:]:
    path, w, h = arg.rsplit(":", 2)
    problem = check(path, int(w), int(h))
    if problem:
        failed += 1
    print("   %s: %s" % (path.rsplit("/", 1)[-1], problem or "valid %sx%s PNG, lit and covered" % (w, h)))
sys.exit(1 if failed else 0)
