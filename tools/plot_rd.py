#!/usr/bin/python3
"""Rate-distortion plots and Bjontegaard-delta rates from a `meshlift rd` sweep.

usage: plot_rd.py DIR [-o OUTDIR] [--psnr-range LOW,HIGH]

Reads DIR/rd.csv with the columns
  mesh,input_vertices,codec,scheme,kind,param,bytes,bpv,psnr_db,rms_rel,hausdorff_rel,
  encode_s,decode_s,peak_rss_mb,error
(codec meshlift|draco; scheme linear|butterfly|loop, empty for draco; kind prefix|separate|draco;
param the target bpv or Draco's qp). Rows with a non-empty `error` are skipped and listed on
stderr. Writes into OUTDIR (default DIR):
  rd.png, rd.svg              PSNR (dB) against bits per vertex (log2 axis), one panel per mesh
  rd_<mesh>.png, .svg         the same, one figure per mesh
  bd_rate.md, bd_rate.csv     BD-rate of each meshlift scheme (prefixes and separate encodes)
                              against Draco, per mesh, over the PSNR interval (default 55-75 dB)
and prints the markdown table. Exit codes as the meshlift CLI: 2 bad arguments, 3 unreadable or
malformed rd.csv, 4 an output cannot be written. Runs on Debian's /usr/bin/python3 with
python3-numpy and python3-matplotlib.
"""
import argparse
import csv
import math
import os
import re
import sys

import numpy as np

COLUMNS = ["mesh", "input_vertices", "codec", "scheme", "kind", "param", "bytes", "bpv", "psnr_db", "rms_rel",
           "hausdorff_rel", "encode_s", "decode_s", "peak_rss_mb", "error"]
SCHEMES = ["linear", "butterfly", "loop"]
KINDS = ["prefix", "separate"]
COLOURS = {"linear": "tab:blue", "butterfly": "tab:orange", "loop": "tab:green", "draco": "black"}
TARGET_PERCENT = -75.0  # issue 6: meshlift's files <= 1/4 of Draco's at equal PSNR

EXIT_BAD_INPUT = 3
EXIT_OUTPUT_ERROR = 4


class RdError(Exception):
    """rd.csv cannot be used; the message names the reason."""


def read_rd(path):
    """Usable rows of rd.csv (dicts with bpv and psnr_db as floats) and the skipped ones with why."""
    try:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            missing = [c for c in COLUMNS if c not in (reader.fieldnames or [])]
            if missing:
                raise RdError("%s: missing columns %s (expected %s)" % (path, ",".join(missing), ",".join(COLUMNS)))
            raw = list(reader)
    except OSError as error:
        raise RdError("%s: cannot read the file: %s" % (path, error.strerror))
    rows, skipped = [], []
    for line, row in enumerate(raw, 2):
        where = "%s:%d (%s %s %s %s)" % (path, line, row["mesh"], row["codec"], row["scheme"] or "-", row["param"])
        if row["error"].strip():
            skipped.append("%s: %s" % (where, row["error"].strip()))
            continue
        try:
            row["bpv"], row["psnr_db"] = float(row["bpv"]), float(row["psnr_db"])
        except ValueError:
            skipped.append("%s: bpv '%s' or psnr_db '%s' is not a number" % (where, row["bpv"], row["psnr_db"]))
            continue
        if not (math.isfinite(row["bpv"]) and row["bpv"] > 0 and math.isfinite(row["psnr_db"])):
            skipped.append("%s: bpv %g and PSNR %g dB cannot be plotted" % (where, row["bpv"], row["psnr_db"]))
            continue
        if row["codec"] not in ("meshlift", "draco"):
            skipped.append("%s: unknown codec '%s'" % (where, row["codec"]))
            continue
        rows.append(row)
    return rows, skipped


def curves(rows, mesh):
    """{(codec or scheme, kind): [(bpv, psnr), ...] sorted by bpv} for one mesh."""
    result = {}
    for row in rows:
        if row["mesh"] != mesh:
            continue
        key = ("draco", "draco") if row["codec"] == "draco" else (row["scheme"], row["kind"])
        result.setdefault(key, []).append((row["bpv"], row["psnr_db"]))
    return {key: sorted(points) for key, points in result.items()}


# ---------------------------------------------------------------------------------------------
# Bjontegaard-delta rate
# ---------------------------------------------------------------------------------------------

def bd_rate(anchor, test, interval=(55.0, 75.0), names=("anchor", "test")):
    """Bjontegaard-delta rate of `test` against `anchor`, both lists of (rate, psnr_db).

    G. Bjontegaard, "Calculation of average PSNR differences between RD-curves", ITU-T SG16 Q.6
    VCEG-M33, Austin, April 2001: each curve is fitted by a cubic polynomial r(D) of the log rate
    as a function of the PSNR D, and the mean log-rate difference over the PSNR interval both
    curves cover is
        delta = 1 / (D_high - D_low) * integral_{D_low}^{D_high} (r_test(D) - r_anchor(D)) dD,
    giving the average rate change BD-rate = exp(delta) - 1 (negative: test needs fewer bits at
    equal quality; the natural log here and log10 with 10^delta in VCEG-M33 give the same value).
    D_low, D_high: the overlap of the two curves' PSNR ranges, clipped to `interval`.
    VCEG-M33 fits the four points of each curve; with more points we fit those inside
    [D_low, D_high] plus the nearest one outside each end (so the fit spans the interval without
    extrapolating, yet stays local), least squares, degree min(3, distinct PSNRs - 1). Each curve needs
    at least 2 points inside [D_low, D_high].

    Returns (bd_rate as a fraction or None, the reason when None, details: low, high and the
    points of each curve inside the interval).
    """
    def clean(points):
        return sorted((d, math.log(r)) for r, d in points if r > 0 and math.isfinite(r) and math.isfinite(d))

    curves_by_name = dict(zip(names, (clean(anchor), clean(test))))
    details = {"low": float("nan"), "high": float("nan"), "anchor_points": 0, "test_points": 0}
    for name, points in curves_by_name.items():
        if not points:
            return None, "no %s points" % name, details
    a, t = curves_by_name.values()
    low = max(a[0][0], t[0][0], interval[0])
    high = min(a[-1][0], t[-1][0], interval[1])
    if not high > low:
        return None, ("no PSNR overlap within %g-%g dB (%s %.1f-%.1f dB, %s %.1f-%.1f dB)"
                      % (interval[0], interval[1], names[0], a[0][0], a[-1][0], names[1], t[0][0], t[-1][0])), details
    details.update(low=low, high=high)
    inside = []
    for key, points in zip(("anchor_points", "test_points"), (a, t)):
        psnr = np.array([p[0] for p in points])
        inside.append(np.flatnonzero((psnr >= low) & (psnr <= high)))
        details[key] = len(inside[-1])
    short = ["%s has %d" % (name, len(i)) for name, i in zip(names, inside) if len(i) < 2]
    if short:
        return None, "%s point(s) in %.1f-%.1f dB, 2 needed" % (" and ".join(short), low, high), details
    integrals = []
    centre = (low + high) / 2
    for points, chosen in zip((a, t), inside):
        first, last = max(chosen[0] - 1, 0), min(chosen[-1] + 1, len(points) - 1)
        x = np.array([p[0] for p in points[first:last + 1]])
        y = np.array([p[1] for p in points[first:last + 1]])
        # Centred PSNR keeps the Vandermonde matrix well conditioned; the integral is unchanged.
        polynomial = np.polyint(np.polyfit(x - centre, y, min(3, len(np.unique(x)) - 1)))
        integrals.append(np.polyval(polynomial, high - centre) - np.polyval(polynomial, low - centre))
    delta = (integrals[1] - integrals[0]) / (high - low)
    return math.exp(delta) - 1, "", details


def bd_table(rows, interval):
    """One entry per mesh, meshlift scheme and kind: BD-rate against Draco on that mesh."""
    table = []
    for mesh in dict.fromkeys(r["mesh"] for r in rows):
        mesh_curves = curves(rows, mesh)
        draco = mesh_curves.get(("draco", "draco"), [])
        for scheme in SCHEMES + sorted({k[0] for k in mesh_curves} - set(SCHEMES) - {"draco"}):
            for kind in KINDS:
                points = mesh_curves.get((scheme, kind))
                if not points:
                    continue
                if not draco:
                    value, reason, details = None, "no Draco rows for this mesh", {
                        "low": float("nan"), "high": float("nan"), "anchor_points": 0, "test_points": len(points)}
                else:
                    names = ("Draco", "meshlift %s %s" % (scheme, kind))
                    value, reason, details = bd_rate(draco, points, interval, names)
                table.append({"mesh": mesh, "scheme": scheme, "kind": kind, "bd_rate": value, "reason": reason,
                              **details})
    return table


def format_markdown(table, interval):
    lines = ["BD-rate of meshlift against Draco (Bjontegaard, VCEG-M33, 2001): mean rate change at equal "
             "PSNR over the overlap of the two curves within %g-%g dB; negative means fewer bits than Draco. "
             "Target (issue 6): <= %g %%." % (interval[0], interval[1], TARGET_PERCENT),
             "",
             "| mesh | scheme | kind | BD-rate vs Draco | PSNR interval (dB) | points meshlift / Draco | meets target |",
             "|---|---|---|---:|---|---|---|"]
    for e in table:
        if e["bd_rate"] is None:
            value, meets = "n/a (%s)" % e["reason"], "n/a"
        else:
            value = "%+.1f %%" % (100 * e["bd_rate"])
            meets = "yes" if 100 * e["bd_rate"] <= TARGET_PERCENT else "no"
        span = "%.1f-%.1f" % (e["low"], e["high"]) if math.isfinite(e["low"]) else "-"
        lines.append("| %s | %s | %s | %s | %s | %d / %d | %s |" % (e["mesh"], e["scheme"], e["kind"], value, span,
                                                                  e["test_points"], e["anchor_points"], meets))
    return "\n".join(lines) + "\n"


def write_csv(table, path):
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["mesh", "scheme", "kind", "bd_rate_percent", "psnr_low_db", "psnr_high_db",
                         "points_meshlift", "points_draco", "note"])
        for e in table:
            writer.writerow([e["mesh"], e["scheme"], e["kind"],
                             "" if e["bd_rate"] is None else "%.3f" % (100 * e["bd_rate"]),
                             "%.3f" % e["low"] if math.isfinite(e["low"]) else "",
                             "%.3f" % e["high"] if math.isfinite(e["high"]) else "",
                             e["test_points"], e["anchor_points"], e["reason"]])


# ---------------------------------------------------------------------------------------------
# Plots
# ---------------------------------------------------------------------------------------------

def draw_panel(axes, mesh, mesh_curves, interval):
    axes.axhspan(interval[0], interval[1], color="0.93", zorder=0, label="BD-rate interval")
    schemes = SCHEMES + sorted({k[0] for k in mesh_curves} - set(SCHEMES) - {"draco"})
    for scheme in schemes:
        colour = COLOURS.get(scheme)
        prefix = mesh_curves.get((scheme, "prefix"))
        if prefix:
            axes.plot([p[0] for p in prefix], [p[1] for p in prefix], "-", color=colour, marker=".",
                      label="meshlift %s (prefixes of one stream)" % scheme)
        separate = mesh_curves.get((scheme, "separate"))
        if separate:
            axes.plot([p[0] for p in separate], [p[1] for p in separate], "o", color=colour, fillstyle="none",
                      label="meshlift %s (separate encodes)" % scheme)
    draco = mesh_curves.get(("draco", "draco"))
    if draco:
        axes.plot([p[0] for p in draco], [p[1] for p in draco], "s-", color=COLOURS["draco"], markersize=4,
                  label="Draco (qp)")
    axes.set_xscale("log", base=2)
    axes.set_xlabel("bits per input vertex")
    axes.set_ylabel("PSNR (dB)")
    axes.set_title(mesh)
    axes.grid(True, which="both", alpha=0.3)


def file_stem(mesh):
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", os.path.splitext(os.path.basename(mesh))[0]) or "mesh"


def plot(rows, out, interval):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    meshes = list(dict.fromkeys(r["mesh"] for r in rows))
    written = []
    if not meshes:
        return written
    columns = min(3, len(meshes))
    lines = math.ceil(len(meshes) / columns)
    figure, panels = plt.subplots(lines, columns, figsize=(5.5 * columns, 4.3 * lines), squeeze=False)
    legend = {}
    for axes, mesh in zip(panels.ravel(), meshes):
        draw_panel(axes, mesh, curves(rows, mesh), interval)
        for handle, label in zip(*axes.get_legend_handles_labels()):
            legend.setdefault(label, handle)
    for axes in panels.ravel()[len(meshes):]:
        axes.set_axis_off()
    # One legend for all panels, below them.
    legend_columns = 3
    legend_height = 0.25 * math.ceil(len(legend) / legend_columns) + 0.1
    figure.set_figheight(4.3 * lines + legend_height)
    figure.legend(list(legend.values()), list(legend.keys()), loc="lower center", ncol=legend_columns, fontsize=8,
                  frameon=False)
    figure.tight_layout(rect=(0, legend_height / (4.3 * lines + legend_height), 1, 1))
    for extension in ("png", "svg"):
        path = os.path.join(out, "rd." + extension)
        figure.savefig(path, dpi=110)
        written.append(path)
    plt.close(figure)
    for mesh in meshes:
        figure, axes = plt.subplots(figsize=(9.5, 4.8))
        draw_panel(axes, mesh, curves(rows, mesh), interval)
        axes.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1), borderaxespad=0)
        figure.tight_layout()
        for extension in ("png", "svg"):
            path = os.path.join(out, "rd_%s.%s" % (file_stem(mesh), extension))
            figure.savefig(path, dpi=110)
            written.append(path)
        plt.close(figure)
    return written


def main(argv):
    parser = argparse.ArgumentParser(prog="plot_rd.py", description=__doc__.split("\n")[0])
    parser.add_argument("directory", help="the sweep's output directory holding rd.csv")
    parser.add_argument("-o", "--output", help="directory for the plots and tables (default: DIR)")
    parser.add_argument("--psnr-range", default="55,75", help="BD-rate PSNR interval in dB (default 55,75)")
    args = parser.parse_args(argv)
    try:
        interval = tuple(float(x) for x in args.psnr_range.split(","))
        if len(interval) != 2 or not interval[0] < interval[1]:
            raise ValueError
    except ValueError:
        parser.error("--psnr-range expects LOW,HIGH in dB with LOW < HIGH, got '%s'" % args.psnr_range)
    out = args.output or args.directory
    try:
        rows, skipped = read_rd(os.path.join(args.directory, "rd.csv"))
    except RdError as error:
        print("plot_rd.py: %s" % error, file=sys.stderr)
        return EXIT_BAD_INPUT
    for line in skipped:
        print("plot_rd.py: skipped %s" % line, file=sys.stderr)
    if not rows:
        print("plot_rd.py: %s: no usable rows" % os.path.join(args.directory, "rd.csv"), file=sys.stderr)
        return EXIT_BAD_INPUT
    table = bd_table(rows, interval)
    markdown = format_markdown(table, interval)
    try:
        os.makedirs(out, exist_ok=True)
        written = plot(rows, out, interval)
        with open(os.path.join(out, "bd_rate.md"), "w") as f:
            f.write(markdown)
        write_csv(table, os.path.join(out, "bd_rate.csv"))
    except OSError as error:
        print("plot_rd.py: %s: cannot write: %s" % (error.filename or out, error.strerror), file=sys.stderr)
        return EXIT_OUTPUT_ERROR
    sys.stdout.write(markdown)
    print("\nwrote %s, bd_rate.md and bd_rate.csv in %s" % (", ".join(os.path.basename(p) for p in written), out),
          file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
