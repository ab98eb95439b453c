#!/usr/bin/env python3
"""Writes scenes/textures/bricks-normal.png (run from the repository root;
the output is deterministic and committed): a tangent-space normal map of
a brick wall for scenes/normal-box.json (README "Normal maps").

The map covers 4 x 8 bricks of 1/4 x 1/8 of the texture (a running bond:
every other row shifted by half a brick), 256 x 256 texels. Inside a
brick the face is flat, n = (0, 0, 1); across its outer BEVEL texels the
face slopes down into the mortar at 40 degrees, the normal tilted towards
the brick's outside (+x on its right edge, -y on its bottom edge, ...);
the mortar joints are flat again, set back. Encoded as glTF's normal
textures are: rgb = (n + 1) / 2, x along increasing u, y along
increasing v (the image's top row is v = 1).
"""
import math
import struct
import zlib

SIZE = 256
COLS, ROWS = 4, 8
MORTAR = 3  # texels of joint on each side of a brick
BEVEL = 6   # texels of slope inside them
SLOPE = math.radians(40)


def normal(x, y):
    """Tangent-space normal at texel (x, y), y counted up from v = 0."""
    bw, bh = SIZE // COLS, SIZE // ROWS
    row = y // bh
    xs = (x + (bw // 2 if row % 2 else 0)) % SIZE
    lx, ly = xs % bw, y % bh  # within the brick's cell
    # Distances to the brick face's four edges, inside the mortar border.
    left, right = lx - MORTAR, bw - 1 - MORTAR - lx
    bottom, top = ly - MORTAR, bh - 1 - MORTAR - ly
    d = min(left, right, bottom, top)
    if d < 0 or d >= BEVEL:
        return (0.0, 0.0, 1.0)  # mortar or the brick's flat face
    s, c = math.sin(SLOPE), math.cos(SLOPE)
    if d == left:
        return (-s, 0.0, c)
    if d == right:
        return (s, 0.0, c)
    if d == bottom:
        return (0.0, -s, c)
    return (0.0, s, c)


def encode(v):
    return max(0, min(255, round((v + 1) / 2 * 255)))


def main():
    rows = []
    for py in range(SIZE):  # the top row first: v = 1
        y = SIZE - 1 - py
        line = bytearray([0])
        for x in range(SIZE):
            line += bytes(encode(c) for c in normal(x, y))
        rows.append(bytes(line))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    png = b"\x89PNG\r\n\x1a\n"
    png += chunk(b"IHDR", struct.pack(">IIBBBBB", SIZE, SIZE, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(b"".join(rows), 9))
    png += chunk(b"IEND", b"")
    with open("scenes/textures/bricks-normal.png", "wb") as f:
        f.write(png)


if __name__ == "__main__":
    main()
