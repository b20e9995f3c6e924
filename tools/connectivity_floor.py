#!/usr/bin/python3
"""The floor that issue 3 sets for base connectivity: zstd -19 of a mesh's face indices coded as
differences from the previous index (as 32-bit integers and as zigzag varints), for OFF files
such as `meshlift decode M.mlz --level 0 -o M_base.off` writes. Needs the `zstd` program.

usage: tools/connectivity_floor.py BASE.off [...]
prints: file, vertices, bytes with int32 deltas, bytes with varint deltas (bits per vertex)
"""
import struct
import subprocess
import sys


def read_off(path):
    """(vertex count, triangles) of an OFF file; comments and blank lines skipped."""
    words = []
    with open(path) as f:
        for line in f:
            line = line.split("#", 1)[0]
            words.extend(line.split())
    if not words or not words[0].startswith("OFF"):
        raise SystemExit(f"{path}: not an OFF file")
    head = words[0][3:]
    i = 1 if not head else 0
    if head:
        words[0] = head
    vertices, faces = int(words[i]), int(words[i + 1])
    i += 3 + 3 * vertices
    triangles = []
    for _ in range(faces):
        n = int(words[i])
        if n != 3:
            raise SystemExit(f"{path}: a face with {n} corners (triangles only)")
        triangles.append([int(w) for w in words[i + 1:i + 4]])
        i += 4
    return vertices, triangles


def zstd_size(data):
    return len(subprocess.run(["zstd", "-19", "-c", "--no-check"], input=data, capture_output=True,
                              check=True).stdout)


def varint(value):
    out = bytearray()
    while True:
        byte = value & 0x7F
        value >>= 7
        out.append(byte | (0x80 if value else 0))
        if not value:
            return bytes(out)


def main():
    if len(sys.argv) < 2:
        raise SystemExit(__doc__)
    for path in sys.argv[1:]:
        vertices, triangles = read_off(path)
        previous = 0
        as_int32, as_varint = bytearray(), bytearray()
        for triangle in triangles:
            for v in triangle:
                d = v - previous
                previous = v
                as_int32 += struct.pack("<i", d)
                as_varint += varint(2 * d if d >= 0 else -2 * d - 1)  # zigzag
        a, b = zstd_size(bytes(as_int32)), zstd_size(bytes(as_varint))
        print(f"{path}: {vertices} vertices, zstd -19 int32 deltas {a} bytes ({8 * a / vertices:.1f} bits/vertex), "
              f"varint deltas {b} bytes ({8 * b / vertices:.1f} bits/vertex)")


if __name__ == "__main__":
    main()
