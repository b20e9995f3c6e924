#!/usr/bin/python3
"""Plots PSNR against bits per vertex from `meshlift stream --csv` files, one line per file.

usage: plot_stream.py OUT.png LABEL=FILE.csv [LABEL=FILE.csv ...]   (also writes OUT.svg)
Runs on Debian's /usr/bin/python3 with python3-matplotlib.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    out = argv[1]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for spec in argv[2:]:
        label, path = spec.split("=", 1)
        with open(path) as f:
            rows = [r for r in csv.DictReader(f) if r["psnr_db"] not in ("nan", "inf")]
        xs = [float(r["bits_per_vertex"]) for r in rows]
        ys = [float(r["psnr_db"]) for r in rows]
        ys = [y if math.isfinite(y) else None for y in ys]
        ax.plot(xs, ys, marker=".", label=label)
    ax.set_xlabel("bits per vertex (whole file, headers included)")
    ax.set_ylabel("PSNR (dB), vertex RMS against the encoded mesh")
    ax.set_title("meshlift: one embedded stream, decoded at growing prefixes")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    fig.savefig(out.rsplit(".", 1)[0] + ".svg")


if __name__ == "__main__":
    main(sys.argv)
