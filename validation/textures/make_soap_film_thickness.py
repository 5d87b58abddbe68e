"""Writes scenes/soap_film_thickness.png, the thickness texture of scenes/soap_film_texture.toml.

Python's standard library only (zlib, struct; no virtual environment needed), deterministic:
`python3 validation/textures/make_soap_film_thickness.py` rewrites the same bytes.

A 256 x 256 16-bit greyscale PNG: a film that drains towards the bottom (grey level rising
from top to bottom, as d^2 linear in depth would have it) with two swirls of thinner film rising
through it (Marangoni eddies), the grey level g in [0, 1] that prisma maps to
min + g (max - min) nm.
"""

import math
import pathlib
import struct
import zlib

SIZE = 256
OUT = pathlib.Path(__file__).resolve().parents[2] / "scenes" / "soap_film_thickness.png"


def level(x: float, y: float) -> float:
    """Grey level in [0, 1] at x, y in [0, 1] (y down from the top row)."""
    drained = math.sqrt(0.05 + 0.95 * y)
    swirl = 0.0
    for cx, cy, radius, turns in ((0.32, 0.58, 0.22, 2.5), (0.7, 0.36, 0.17, -2.0)):
        dx, dy = x - cx, y - cy
        r = math.hypot(dx, dy) / radius
        if r < 1.0:
            angle = math.atan2(dy, dx) + turns * (1.0 - r) ** 2 * math.tau
            swirl += (1.0 - r) ** 2 * (0.35 * math.cos(3.0 * angle) - 0.45)
    return min(1.0, max(0.0, drained + 0.6 * swirl))


def chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def main() -> None:
    rows = bytearray()
    for j in range(SIZE):
        rows.append(0)  # filter: none
        for i in range(SIZE):
            value = round(65535 * level((i + 0.5) / SIZE, (j + 0.5) / SIZE))
            rows += struct.pack(">H", value)
    header = struct.pack(">IIBBBBB", SIZE, SIZE, 16, 0, 0, 0, 0)  # 16-bit greyscale
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(bytes(rows), 9))
    OUT.write_bytes(png + chunk(b"IEND", b""))
    print(f"wrote {OUT} ({len(png)} bytes)")


if __name__ == "__main__":
    main()
