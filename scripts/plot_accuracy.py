#!/usr/bin/env python3
"""Heat maps for the `accuracy` section of `rayunits report`.

usage: plot_accuracy.py ACCURACY_CSV OUT_DIR

Reads the CSV written by the section (one row per format and operation) and writes
accuracy_mean.png, accuracy_max.png, accuracy_range.png and accuracy_vs_m.png into OUT_DIR.
Called by the C++ report; runs with the Agg backend (no display needed).
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

OPS = ["add", "mul", "div", "dot3"]


def load(path):
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            rows.append(r)
    if not rows:
        raise SystemExit(f"plot_accuracy: {path} has no rows")
    return rows


def grid(rows, op, key, transform=float):
    es = sorted({int(r["exp_bits"]) for r in rows})
    ms = sorted({int(r["frac_bits"]) for r in rows})
    z = np.full((len(ms), len(es)), np.nan)
    flag = np.zeros((len(ms), len(es)), dtype=bool)
    for r in rows:
        if r["op"] != op:
            continue
        i, j = ms.index(int(r["frac_bits"])), es.index(int(r["exp_bits"]))
        if int(r["used"]) > 0 or key in ("overflow", "underflow", "range"):
            z[i, j] = transform(r)
        flag[i, j] = int(r["overflow"]) > 0 or int(r["underflow"]) > 0
    return es, ms, z, flag


def heat(ax, es, ms, z, flag, title, fmt, cmap, vmin=None, vmax=None, log=True):
    data = np.log10(np.where(z > 0, z, np.nan)) if log else z
    masked = np.ma.masked_invalid(data)
    cm = plt.get_cmap(cmap).copy()
    cm.set_bad("#dddddd")
    im = ax.imshow(masked, origin="lower", aspect="auto", cmap=cm, vmin=vmin, vmax=vmax,
                   extent=(es[0] - 0.5, es[-1] + 0.5, ms[0] - 0.5, ms[-1] + 0.5))
    small = len(es) * len(ms) <= 200
    for i, m in enumerate(ms):
        for j, e in enumerate(es):
            v = z[i, j]
            if small and not (isinstance(v, float) and math.isnan(v)):
                # dark text on light cells, light text on dark ones
                r, g, b, _ = cm(im.norm(masked[i, j]))
                colour = "black" if 0.299 * r + 0.587 * g + 0.114 * b > 0.5 else "white"
                ax.text(e, m, fmt(v) + ("*" if flag[i, j] else ""), ha="center", va="center",
                        color=colour, fontsize=6 if len(es) > 4 else 8)
    ax.set_title(title)
    ax.set_xlabel("exponent bits E")
    ax.set_ylabel("fraction bits M")
    ax.set_xticks(es)
    ax.set_yticks(ms)
    return im


def four_panels(rows, key, transform, title, fmt, cmap, log, cbar_label, path):
    fig, axes = plt.subplots(2, 2, figsize=(14, 12), constrained_layout=True)
    vals = []
    for op in OPS:
        _, _, z, _ = grid(rows, op, key, transform)
        vals.append(z)
    allv = np.concatenate([v.ravel() for v in vals])
    if log:
        pos = allv[allv > 0]
        vmin, vmax = (np.log10(pos.min()), np.log10(pos.max())) if pos.size else (None, None)
    else:
        fin = allv[~np.isnan(allv)]
        vmin, vmax = (0.0, max(1e-12, float(fin.max()))) if fin.size else (None, None)
    im = None
    for ax, op in zip(axes.ravel(), OPS):
        es, ms, z, flag = grid(rows, op, key, transform)
        im = heat(ax, es, ms, z, flag, op, fmt, cmap, vmin, vmax, log)
    cb = fig.colorbar(im, ax=axes, shrink=0.8)
    cb.set_label(cbar_label)
    fig.suptitle(title)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def vs_m(rows, path):
    es = sorted({int(r["exp_bits"]) for r in rows})
    e = es[-1]  # the widest exponent: no range effects
    fig, ax = plt.subplots(figsize=(8, 5.5), constrained_layout=True)
    ms_all = sorted({int(r["frac_bits"]) for r in rows if int(r["exp_bits"]) == e})
    styles = {"add": ("o", "-"), "mul": ("s", "--"), "div": ("^", "-."), "dot3": ("D", ":")}
    for op in OPS:
        pts = sorted((int(r["frac_bits"]), float(r["mean_rel_err"])) for r in rows
                     if r["op"] == op and int(r["exp_bits"]) == e and int(r["used"]) > 0)
        if pts:
            mk, ls = styles[op]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], marker=mk, linestyle=ls, label=f"{op} (average)")
    ax.plot(ms_all, [2.0 ** -(m + 1) for m in ms_all], color="black", linewidth=0.8, label="u = 2^-(M+1)")
    ax.set_xticks(ms_all)
    ax.set_yscale("log")
    ax.set_xlabel("fraction bits M")
    ax.set_ylabel("average relative error")
    ax.set_title(f"average relative error vs fraction bits, E = {e}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main():
    if len(sys.argv) != 3:
        raise SystemExit("usage: plot_accuracy.py ACCURACY_CSV OUT_DIR")
    rows = load(sys.argv[1])
    out = sys.argv[2]
    short = lambda v: f"{v:.1e}".replace("e-0", "e-").replace("e+0", "e")  # noqa: E731
    four_panels(rows, "mean", lambda r: float(r["mean_rel_err"]),
                "average relative error (log10 colour; * = overflow/underflow in the cell)",
                short, "viridis", True, "log10 average relative error", os.path.join(out, "accuracy_mean.png"))
    four_panels(rows, "max", lambda r: float(r["max_rel_err"]),
                "maximum relative error (log10 colour; * = overflow/underflow in the cell)",
                short, "magma", True, "log10 maximum relative error", os.path.join(out, "accuracy_max.png"))
    four_panels(rows, "range",
                lambda r: 100.0 * int(r["out_of_range"]) / max(1, int(r["samples"])),
                "samples with overflow or underflow (operands or operations), %",
                lambda v: f"{v:.2g}", "Reds", False, "% of samples", os.path.join(out, "accuracy_range.png"))
    vs_m(rows, os.path.join(out, "accuracy_vs_m.png"))


if __name__ == "__main__":
    main()
