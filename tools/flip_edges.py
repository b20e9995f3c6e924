#!/usr/bin/python3
"""Flips a random fraction of a closed or open triangle mesh's interior edges, where the flip keeps
the mesh manifold and neither new face turns against the old pair's normal, so that a mesh with
subdivision connectivity (`meshlift subdivide`) loses it and must be remeshed: a large test input
made from a corpus mesh (docs/RESULTS.md, "A larger input").

usage: tools/flip_edges.py IN.off OUT.off FRACTION SEED      (Debian's python3-numpy)
"""
import random
import sys

import numpy as np


def read_off(path):
    words = []
    with open(path) as f:
        for line in f:
            words.extend(line.split("#", 1)[0].split())
    if not words or not words[0].startswith("OFF"):
        raise SystemExit(f"{path}: not an OFF file")
    i = 1 if words[0] == "OFF" else 0
    if i == 0:
        words[0] = words[0][3:]
    nv, nf = int(words[i]), int(words[i + 1])
    i += 3
    positions = np.array(words[i:i + 3 * nv], dtype=float).reshape(nv, 3)
    i += 3 * nv
    faces = []
    for _ in range(nf):
        if words[i] != "3":
            raise SystemExit(f"{path}: triangles only")
        faces.append([int(w) for w in words[i + 1:i + 4]])
        i += 4
    return positions, faces


def main():
    if len(sys.argv) != 5:
        raise SystemExit(__doc__)
    source, target, fraction, seed = sys.argv[1], sys.argv[2], float(sys.argv[3]), int(sys.argv[4])
    V, F = read_off(source)
    face_of = {}  # directed edge -> face
    for fi, f in enumerate(F):
        for k in range(3):
            face_of[(f[k], f[(k + 1) % 3])] = fi
    neighbours = {}
    for a, b in face_of:
        neighbours.setdefault(a, set()).add(b)

    def normal(t):
        return np.cross(V[t[1]] - V[t[0]], V[t[2]] - V[t[0]])

    interior = [e for e in face_of if e[0] < e[1] and (e[1], e[0]) in face_of]
    rng = random.Random(seed)
    rng.shuffle(interior)
    wanted, flipped, touched = int(fraction * len(interior)), 0, set()
    for a, b in interior:
        if flipped >= wanted:
            break
        f, g = face_of.get((a, b)), face_of.get((b, a))
        if f is None or g is None or f in touched or g in touched:
            continue
        c = next(v for v in F[f] if v not in (a, b))
        d = next(v for v in F[g] if v not in (a, b))
        if c == d or d in neighbours[c]:
            continue  # the new edge exists already: the flip would make the mesh non-manifold
        # f = (a, b, c), g = (b, a, d) as oriented; the flip makes (c, a, d) and (d, b, c).
        new_f, new_g = [c, a, d], [d, b, c]
        old = normal(F[f]) + normal(F[g])
        if np.dot(normal(new_f), old) <= 0 or np.dot(normal(new_g), old) <= 0:
            continue
        del face_of[(a, b)], face_of[(b, a)]
        neighbours[a].discard(b), neighbours[b].discard(a)
        neighbours[c].add(d), neighbours[d].add(c)
        F[f], F[g] = new_f, new_g
        for fi in (f, g):
            for k in range(3):
                face_of[(F[fi][k], F[fi][(k + 1) % 3])] = fi
        touched.update((f, g))
        flipped += 1
    with open(target, "w") as out:
        out.write(f"OFF\n{len(V)} {len(F)} 0\n")
        for p in V:
            out.write(f"{p[0]:.9g} {p[1]:.9g} {p[2]:.9g}\n")
        for t in F:
            out.write(f"3 {t[0]} {t[1]} {t[2]}\n")
    print(f"{flipped} edges flipped")


if __name__ == "__main__":
    main()
