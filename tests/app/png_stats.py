#!/usr/bin/env python3
"""Pixel statistics of a PNG for the app tests (standard library only: zlib and struct).

usage: png_stats.py FILE X0 Y0 X1 Y1 KIND
prints WIDTHxHEIGHT and the fraction of pixels in the rectangle [X0, X1) x [Y0, Y1) (fractions of
the image size when <= 1) that are of KIND: red (a red species), blue (the blue species), panel (ImGui's
dark blue widgets), white (curves and text), any (not the background colour).
"""
import struct
import sys
import zlib


def read_png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, width, height, channels = 8, b"", 0, 0, 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, color = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and color in (2, 6), "8-bit RGB or RGBA only"
            channels = 3 if color == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b = prev[i]
            c = prev[i - channels] if i >= channels else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return width, height, channels, rows


def main():
    path, x0, y0, x1, y1, kind = sys.argv[1:7]
    width, height, channels, rows = read_png(path)
    def coord(v, size):
        v = float(v)
        return int(v * size) if v <= 1 else int(v)
    x0, x1 = coord(x0, width), coord(x1, width)
    y0, y1 = coord(y0, height), coord(y1, height)
    tests = {
        "red": lambda r, g, b: r > 120 and g < 100 and b < 100,
        "blue": lambda r, g, b: b > 110 and b > r + 40,
        "panel": lambda r, g, b: b >= 60 and b >= r + 30 and g >= r,
        "white": lambda r, g, b: r > 200 and g > 200 and b > 200,
        "any": lambda r, g, b: abs(r - 14) + abs(g - 15) + abs(b - 19) > 30,
    }
    test = tests[kind]
    hits = total = 0
    for y in range(y0, y1, 2):
        row = rows[y]
        for x in range(x0, x1, 2):
            i = x * channels
            hits += test(row[i], row[i + 1], row[i + 2])
            total += 1
    print(f"{width}x{height} {hits / max(total, 1):.4f}")


if __name__ == "__main__":
    main()
