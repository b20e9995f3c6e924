#!/usr/bin/python3
"""Rate-distortion of Draco against meshlift's embedded stream on the same semi-regular mesh.

usage: compare_draco.py REFERENCE.ply WORKDIR OUT.md NAME=STREAM.csv [NAME=STREAM.csv ...]

Draco (draco_encoder/draco_decoder from Debian's `draco`) encodes REFERENCE at qp 6..16. Its
reconstruction at a qp does not depend on the connectivity coder, so the error is measured on a
`-cl 0` (sequential, vertex order kept) decode against REFERENCE vertex by vertex, and the size is
that of the default `-cl 7` file. meshlift's curves come from `meshlift stream --reference --csv`
(PSNR of every prefix, same vertex PSNR: 20 log10(bbox diagonal / RMS vertex distance)). For each
Draco point with PSNR in [55, 75] dB the table gives the meshlift size at equal PSNR (linear
interpolation on its curve) and the ratio. Runs on Debian's /usr/bin/python3 with numpy.
"""
import csv
import math
import os
import subprocess
import sys

import numpy as np


def ply_vertices(path):
    """Vertex positions of a PLY file whose vertices have float x, y, z as their only properties
    (as OpenMesh and draco_decoder write them), ascii or binary little-endian."""
    with open(path, "rb") as f:
        header = []
        while not header or header[-1] != "end_header":
            header.append(f.readline().decode("ascii", "replace").strip())
        count = next(int(line.split()[2]) for line in header if line.startswith("element vertex"))
        properties = []
        for line in header[header.index(next(l for l in header if l.startswith("element vertex"))) + 1:]:
            if not line.startswith("property"):
                break
            properties.append(line.split())
        if [p[1:] for p in properties] != [["float", "x"], ["float", "y"], ["float", "z"]]:
            sys.exit("%s: expected vertices with float x, y, z only" % path)
        if any(line.startswith("format binary_little_endian") for line in header):
            return np.frombuffer(f.read(12 * count), dtype="<f4").reshape(count, 3).astype(float)
        return np.array([f.readline().split()[:3] for _ in range(count)], dtype=float)


def psnr(reference, test):
    diagonal = np.linalg.norm(reference.max(axis=0) - reference.min(axis=0))
    rms = math.sqrt(((reference - test) ** 2).sum(axis=1).mean())
    return 20 * math.log10(diagonal / rms) if rms > 0 else float("inf")


def bytes_at(curve, target_db):
    """Bytes at which the (bytes, dB) curve first reaches target_db, linearly interpolated."""
    for (b0, d0), (b1, d1) in zip(curve, curve[1:]):
        if d0 < target_db <= d1:
            return b0 + (b1 - b0) * (target_db - d0) / (d1 - d0)
    return curve[0][0] if curve and curve[0][1] >= target_db else None


def main(argv):
    if len(argv) < 5:
        sys.exit(__doc__)
    reference_path, work, out = argv[1], argv[2], argv[3]
    streams = dict(spec.split("=", 1) for spec in argv[4:])
    os.makedirs(work, exist_ok=True)
    reference = ply_vertices(reference_path)
    n = len(reference)
    draco = []
    for qp in range(6, 17):
        small = os.path.join(work, "qp%d.drc" % qp)
        ordered = os.path.join(work, "qp%d_cl0.drc" % qp)
        decoded = os.path.join(work, "qp%d_cl0.ply" % qp)
        quiet = dict(stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
        subprocess.run(["draco_encoder", "-i", reference_path, "-o", small, "-qp", str(qp)], **quiet)
        subprocess.run(["draco_encoder", "-i", reference_path, "-o", ordered, "-qp", str(qp), "-cl", "0"], **quiet)
        subprocess.run(["draco_decoder", "-i", ordered, "-o", decoded], **quiet)
        test = ply_vertices(decoded)
        os.remove(decoded)  # large, and only needed for this measurement
        os.remove(ordered)
        if test.shape != reference.shape:
            sys.exit("draco changed the vertex count (%d -> %d)" % (n, len(test)))
        draco.append((qp, os.path.getsize(small), psnr(reference, test)))
    curves = {}
    for name, path in streams.items():
        with open(path) as f:
            rows = [r for r in csv.DictReader(f)]
        curve, best = [], -1.0
        for r in rows:  # keep the running best, so the curve is monotone in bytes
            best = max(best, float(r["psnr_db"]))
            curve.append((int(r["bytes"]), best))
        curves[name] = curve
    lines = ["| Draco qp | Draco bpv | PSNR dB | " + " | ".join("%s bpv (ratio)" % k for k in curves) + " |",
             "|" + "---|" * (3 + len(curves))]
    ratios = {k: [] for k in curves}
    for qp, size, db in draco:
        cells = []
        for name, curve in curves.items():
            b = bytes_at(curve, db)
            if b is None:
                cells.append("—")
                continue
            cells.append("%.2f (%.2f)" % (8 * b / n, b / size))
            if 55 <= db <= 75:
                ratios[name].append(b / size)
        lines.append("| %d | %.2f | %.1f | %s |" % (qp, 8.0 * size / n, db, " | ".join(cells)))
    summary = []
    for name, r in ratios.items():
        if r:
            summary.append("%s: meshlift/Draco bytes at equal PSNR in 55-75 dB: mean %.2f, worst %.2f (target <= 0.25)"
                           % (name, sum(r) / len(r), max(r)))
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n\n" + "\n".join("- " + s for s in summary) + "\n")
    print("\n".join(lines))
    print("\n".join(summary))


if __name__ == "__main__":
    main(sys.argv)
