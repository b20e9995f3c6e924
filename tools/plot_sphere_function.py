#!/usr/bin/python3
"""Plots of a function on the sphere coded as a meshlift channel (bench/bench_sphere_function.cpp).

usage: plot_sphere_function.py DIR [-o OUTDIR] [--strip N]

Reads DIR/sphere_function.csv (columns scheme,bytes,bits_per_sample,function_psnr_db,
geometry_psnr_db) and the decoded functions unfolded on the octahedral image,
DIR/function_<bytes>.pgm|ppm (butterfly prefixes) and DIR/function_original.pgm|ppm. Writes into
OUTDIR (default DIR):
  sphere_function_rd.png, .svg   function PSNR (dB) against bits per sample (log2 axis), per scheme
  sphere_function_strip.png      the original and N (default 4) prefixes, unfolded, with their sizes
Exit codes as the meshlift CLI: 3 unreadable or malformed input, 4 an output cannot be written.
Runs on Debian's /usr/bin/python3 with python3-numpy and python3-matplotlib.
"""
import argparse
import csv
import glob
import os
import re
import sys

import numpy as np

EXIT_BAD_INPUT = 3
EXIT_OUTPUT_ERROR = 4
COLOURS = {"linear": "tab:blue", "butterfly": "tab:orange", "loop": "tab:green"}


def read_netpbm(path):
    """Binary 8-bit PGM (P5) or PPM (P6) as an array of floats in [0, 1] (H x W or H x W x 3)."""
    with open(path, "rb") as f:
        data = f.read()
    tokens = re.match(rb"(P[56])\s+(\d+)\s+(\d+)\s+(\d+)\s", data)
    if not tokens or int(tokens.group(4)) != 255:
        raise ValueError(f"{path}: not an 8-bit binary PGM/PPM")
    width, height = int(tokens.group(2)), int(tokens.group(3))
    channels = 1 if tokens.group(1) == b"P5" else 3
    pixels = np.frombuffer(data, dtype=np.uint8, count=width * height * channels, offset=tokens.end())
    image = pixels.reshape(height, width, channels).astype(float) / 255.0
    return image[:, :, 0] if channels == 1 else image


def read_rows(path):
    rows = []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            rows.append({"scheme": row["scheme"], "bytes": int(row["bytes"]),
                         "bps": float(row["bits_per_sample"]), "psnr": float(row["function_psnr_db"])})
    if not rows:
        raise ValueError(f"{path}: no rows")
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("dir")
    parser.add_argument("-o", "--output")
    parser.add_argument("--strip", type=int, default=4)
    args = parser.parse_args()
    out = args.output or args.dir
    try:
        rows = read_rows(os.path.join(args.dir, "sphere_function.csv"))
        decoded = {}
        for path in glob.glob(os.path.join(args.dir, "function_*.p[gp]m")):
            name = os.path.basename(path)[len("function_"):-4]
            decoded[name] = read_netpbm(path)
        if "original" not in decoded:
            raise ValueError(f"{args.dir}: no function_original.pgm/ppm")
    except (OSError, ValueError, KeyError) as e:
        print(f"plot_sphere_function: {e}", file=sys.stderr)
        return EXIT_BAD_INPUT

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    try:
        os.makedirs(out, exist_ok=True)
        fig, ax = plt.subplots(figsize=(6, 4))
        for scheme in ["linear", "butterfly", "loop"]:
            points = sorted((r["bps"], r["psnr"]) for r in rows if r["scheme"] == scheme)
            if points:
                ax.plot(*zip(*points), marker="o", label=scheme, color=COLOURS[scheme])
        ax.set_xscale("log", base=2)
        ax.set_xlabel("bits per sample (whole stream: sphere geometry + function)")
        ax.set_ylabel("function PSNR (dB, peak = value range)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
        ax.set_title("A function on the sphere as a meshlift channel")
        fig.tight_layout()
        for ext in ("png", "svg"):
            fig.savefig(os.path.join(out, f"sphere_function_rd.{ext}"), dpi=120)
        plt.close(fig)

        butterfly = {r["bytes"]: r for r in rows if r["scheme"] == "butterfly"}
        sizes = sorted(int(k) for k in decoded if k != "original" and int(k) in butterfly)
        if len(sizes) > args.strip:  # evenly spread over the prefixes, the whole file last
            picks = np.linspace(0, len(sizes) - 1, args.strip).round().astype(int)
            sizes = [sizes[i] for i in sorted(set(picks))]
        panels = [("original", decoded["original"])] + [
            (f"{s:,} bytes, {butterfly[s]['bps']:.2f} bits/sample\n{butterfly[s]['psnr']:.1f} dB", decoded[str(s)])
            for s in sizes]
        fig, axes = plt.subplots(1, len(panels), figsize=(3 * len(panels), 3.6))
        for ax, (title, image) in zip(np.atleast_1d(axes), panels):
            ax.imshow(image, cmap="gray" if image.ndim == 2 else None, vmin=0, vmax=1, interpolation="nearest")
            ax.set_title(title, fontsize=8)
            ax.axis("off")
        fig.tight_layout()
        fig.subplots_adjust(top=0.84)
        fig.savefig(os.path.join(out, "sphere_function_strip.png"), dpi=120)
        plt.close(fig)
    except OSError as e:
        print(f"plot_sphere_function: {e}", file=sys.stderr)
        return EXIT_OUTPUT_ERROR
    print(f"wrote {out}/sphere_function_rd.png, .svg, sphere_function_strip.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
