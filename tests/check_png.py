#!/usr/bin/env python3
# check_png.py [--lit LEVEL] FILE:W:H... - each a valid PNG (chunk CRCs, zlib, row filters decoded here: no
# image tool starts per file) of that size, 8-bit RGBA, showing a lit object: at least 0.15 of its pixels
# covered (alpha > 0) and those pixels' mean brightness (max of R, G, B) at least LEVEL of 255 (default 10).
# 0.15 and 10 are half the least covered (0.317) and half the dimmest (21.2, the client test's cube) image of
# the daemon and client tests, so an empty, black, near-black or one-pixel image fails. Each file's measures
# are printed beside the minimums; --lit applies to the files after it.
import struct, sys, zlib
def check(path, w, h, min_cover, min_lit):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        return "not a PNG", False
    pos, idat, hdr = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if zlib.crc32(kind + body) != struct.unpack(">I", data[pos + 8 + n:pos + 12 + n])[0]:
            return "bad CRC in " + kind.decode(), False
        if kind == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    if not hdr or hdr[:4] != (w, h, 8, 6):
        return "header %s, expected %dx%d 8-bit RGBA" % (hdr, w, h), False
    raw, stride, prev, rows = zlib.decompress(idat), w * 4, bytearray(w * 4), []
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if f > 4 or len(line) != stride:
            return "row %d: filter %d, %d of %d bytes" % (y, f, len(line), stride), False
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
    bright = [max(px[i:i + 3]) for i in range(0, len(px), 4) if px[i + 3] > 0]
    cover = len(bright) / (w * h)
    mean = sum(bright) / len(bright) if bright else 0.0
    measured = "covered %.3f (min %.3f), mean brightness %.1f (min %.1f), peak %d" % (
        cover, min_cover, mean, min_lit, max(bright, default=0))
    return measured, cover >= min_cover and mean >= min_lit
failed, min_cover, min_lit = 0, 0.15, 10.0
args = sys.argv[1:]
while args:
    arg = args.pop(0)
    if arg == "--lit":
        min_lit = float(args.pop(0))
        continue
    path, w, h = arg.rsplit(":", 2)
    try:
        measured, good = check(path, int(w), int(h), min_cover, min_lit)
    except (OSError, ValueError, IndexError, struct.error, zlib.error) as e:
        measured, good = "unreadable: %s" % e, False
    failed += not good
    print("   %s: %s%s" % (path.rsplit("/", 1)[-1], "" if good else "refused: ", measured))
sys.exit(1 if failed else 0)
