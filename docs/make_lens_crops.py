#!/usr/bin/env python3
"""Enlarged crops of the three lens pictures (scenes/lens_pinhole.toml, lens_singlet.toml,
lens_dgauss50.toml; docs/lens_scene_*.png) for the README: two windows toward the image's
corners where an edge of high contrast lies (the blue ball against the grey wall, top right;
the red ball against the floor, bottom left), rendered by prisma at 4× the pictures'
resolution (1440×960, `--crop`, 64 spp) and enlarged 2× more by pixel replication (no
interpolation: each rendered pixel stays visible), written as docs/lens_crop_<window>_<scene>.png.

Python 3 standard library only (subprocess, zlib, struct): reads and writes 8-bit RGB/RGBA
PNGs, non interlaced, which is what prisma writes. Run from the repository root after
`cargo build --release`:

    python3 docs/make_lens_crops.py
"""

import struct
import subprocess
import zlib

PRISMA = "target/release/prisma"
# The crops' resolution: 4× the pictures' 360×240.
WIDTH = 1440
SPP = 64
# (x0, y0, x1, y1) in pixels of the 1440×960 image: the blue ball's upper-right edge against
# the wall (0.7 of the half-width right of the centre, 0.3 of the half-height up) and the red
# ball's right edge against the floor (0.35 of the half-width left, 0.7 of the half-height down).
WINDOWS = {"blue": (1100, 240, 1260, 400), "red": (384, 720, 544, 880)}
SCALE = 2
SCENES = ["pinhole", "singlet", "dgauss50"]


def read_png(path):
    """(width, height, rows) with rows a list of bytearrays of RGB triples."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace != 0:
        raise ValueError(f"{path}: only 8-bit RGB/RGBA non-interlaced PNGs are read")
    channels = 3 if colour == 2 else 4
    stride = width * channels
    raw = zlib.decompress(idat)
    rows, previous = [], bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        kind, line = raw[start], bytearray(raw[start + 1 : start + 1 + stride])
        for i in range(stride):
            left = line[i - channels] if i >= channels else 0
            up = previous[i]
            upper_left = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + left) & 255
            elif kind == 2:
                line[i] = (line[i] + up) & 255
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 255
            elif kind == 4:
                p = left + up - upper_left
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - upper_left)
                predictor = left if pa <= pb and pa <= pc else (up if pb <= pc else upper_left)
                line[i] = (line[i] + predictor) & 255
        rows.append(bytearray(b for x in range(width) for b in line[x * channels : x * channels + 3]))
        previous = line
    return width, height, rows


def write_png(path, width, height, rows):
    """Writes RGB rows (bytearrays) as an 8-bit PNG (filter 0)."""

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    raw = b"".join(b"\x00" + bytes(row) for row in rows)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


def main():
    for name in SCENES:
        for window, (x0, y0, x1, y1) in WINDOWS.items():
            crop = f"out/lens_crop_{window}_{name}"
            command = [PRISMA, "render", f"scenes/lens_{name}.toml", "--width", str(WIDTH), "--spp", str(SPP),
                       "--crop", f"{x0},{y0},{x1},{y1}", "-q", "-o", f"{crop}.exr"]
            subprocess.run(command, check=True)
            width, height, rows = read_png(f"{crop}.png")
            out = []
            for row in rows:
                line = bytearray()
                for x in range(width):
                    line += row[3 * x : 3 * x + 3] * SCALE
                out.extend(bytearray(line) for _ in range(SCALE))
            target = f"docs/lens_crop_{window}_{name}.png"
            write_png(target, width * SCALE, height * SCALE, out)
            print(f"wrote {target}: {' '.join(command[1:])}, pixels {x0}–{x1 - 1} × {y0}–{y1 - 1}, ×{SCALE}")


if __name__ == "__main__":
    main()
