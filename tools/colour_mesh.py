#!/usr/bin/python3
"""A mesh with a colour per vertex, for measuring how meshlift codes colours (docs/RESULTS.md,
"Vertex colours"): reads an OFF, writes an ascii PLY with `uchar red, green, blue` per vertex.

    /usr/bin/python3 tools/colour_mesh.py IN.off OUT.ply smooth|checker|none

smooth: each component a sine of the vertex's position along one axis of the bounding box,
255 (1/2 + 1/2 sin(8 u_k + k)), u_k in [0, 1] across the box; checker: two colours in 8 x 8 x 8
cells of the box (a piecewise-constant field, like a segmentation); none: no colours.
Standard library only."""
import math
import sys


def read_off(path):
    tokens = open(path).read().split()
    if tokens[0] not in ('OFF', 'COFF'):
        raise SystemExit('%s: not an OFF file' % path)
    per_vertex = 3 if tokens[0] == 'OFF' else 7
    vertices, faces = int(tokens[1]), int(tokens[2])
    at = 4
    positions = []
    for _ in range(vertices):
        positions.append(tuple(float(x) for x in tokens[at:at + 3]))
        at += per_vertex
    polygons = []
    for _ in range(faces):
        n = int(tokens[at])
        polygons.append([int(x) for x in tokens[at + 1:at + 1 + n]])
        at += 1 + n
    return positions, polygons


def main(argv):
    if len(argv) != 4 or argv[3] not in ('smooth', 'checker', 'none'):
        print(__doc__, file=sys.stderr)
        return 2
    positions, polygons = read_off(argv[1])
    kind = argv[3]
    lo = [min(p[k] for p in positions) for k in range(3)]
    hi = [max(p[k] for p in positions) for k in range(3)]

    def colour(p):
        u = [(p[k] - lo[k]) / (hi[k] - lo[k]) if hi[k] > lo[k] else 0.0 for k in range(3)]
        if kind == 'smooth':
            return [int(round(255 * (0.5 + 0.5 * math.sin(8 * u[k] + k)))) for k in range(3)]
        cell = sum(min(int(8 * x), 7) for x in u) % 2
        return [230, 40, 40] if cell else [40, 40, 230]

    with open(argv[2], 'w') as out:
        out.write('ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\n'
                  'property float z\n' % len(positions))
        if kind != 'none':
            out.write('property uchar red\nproperty uchar green\nproperty uchar blue\n')
        out.write('element face %d\nproperty list uchar int vertex_indices\nend_header\n' % len(polygons))
        for p in positions:
            out.write('%r %r %r' % p + ('' if kind == 'none' else ' %d %d %d' % tuple(colour(p))) + '\n')
        for f in polygons:
            out.write('%d %s\n' % (len(f), ' '.join(str(i) for i in f)))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
