#!/usr/bin/env python3
"""Plot of `rayunits pareto --out DIR` (DIR/pareto.csv): one panel per group, one axis against
another (log scales where all values are positive and span more than a decade), the remaining
axis as colour; points on the front in colour and labelled (one label per distinct point name
without its target clock), dominated points grey.

usage: plot_pareto.py pareto.csv out.png [--axes I,J] [--title TEXT]
  --axes I,J   which pareto axes (1-based) go on the panel's x and y (default 1,2)
"""
import argparse
import csv
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.colors as mcolors  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402


def spans_decades(vals):
    pos = [v for v in vals if v > 0]
    return bool(pos) and len(pos) == len(vals) and max(pos) / min(pos) > 10


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("png")
    ap.add_argument("--axes", default="1,2")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    with open(a.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit("plot_pareto.py: no points in " + a.csv)
    naxes = 3 if "axis3" in rows[0] else 2
    try:
        ix, iy = (int(t) for t in a.axes.split(","))
    except ValueError:
        raise SystemExit("plot_pareto.py: --axes I,J: two axis numbers, e.g. 3,2")
    if not (1 <= ix <= naxes and 1 <= iy <= naxes and ix != iy):
        raise SystemExit("plot_pareto.py: --axes %s: two different axes in 1..%d" % (a.axes, naxes))
    rest = [k for k in range(1, naxes + 1) if k not in (ix, iy)]
    ic = rest[0] if rest else None
    groups = []
    for r in rows:
        if r["group"] not in groups:
            groups.append(r["group"])
    n = len(groups)
    cols = min(n, 3)
    lines = (n + cols - 1) // cols
    fig, axes = plt.subplots(lines, cols, figsize=(5.4 * cols, 4.3 * lines), squeeze=False)
    for k, g in enumerate(groups):
        ax = axes[k // cols][k % cols]
        pts = [r for r in rows if r["group"] == g]
        val = lambda r, i: float(r["axis%d" % i])  # noqa: E731
        xs = [val(r, ix) for r in pts]
        ys = [val(r, iy) for r in pts]
        front = [r["dominated"] == "0" for r in pts]
        ax.scatter([x for x, f in zip(xs, front) if not f], [y for y, f in zip(ys, front) if not f],
                   c="0.78", s=18, label="dominated", zorder=1)
        fx = [x for x, f in zip(xs, front) if f]
        fy = [y for y, f in zip(ys, front) if f]
        if ic:
            zs = [val(r, ic) for r, f in zip(pts, front) if f]
            norm = mcolors.LogNorm() if spans_decades(zs) else None
            sc = ax.scatter(fx, fy, c=zs, cmap="viridis", norm=norm, s=34, edgecolors="k", linewidths=0.4,
                            label="front", zorder=2)
            fig.colorbar(sc, ax=ax).set_label(pts[0]["axis%d_field" % ic])
        else:
            ax.scatter(fx, fy, c="C0", s=34, edgecolors="k", linewidths=0.4, label="front", zorder=2)
        seen = set()
        for r, x, y, f in zip(pts, xs, ys, front):
            short = re.sub(r"\s*\d+ps$", "", r["label"])
            if f and short not in seen:
                seen.add(short)
                ax.annotate(short, (x, y), fontsize=6, xytext=(3, 3), textcoords="offset points")
        if spans_decades(xs):
            ax.set_xscale("log")
        if spans_decades(ys):
            ax.set_yscale("log")
        ax.set_xlabel(pts[0]["axis%d_field" % ix])
        ax.set_ylabel(pts[0]["axis%d_field" % iy])
        ax.set_title("%s: %d of %d on the front" % (g, sum(front), len(pts)), fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    for k in range(n, lines * cols):
        axes[k // cols][k % cols].axis("off")
    if a.title:
        fig.suptitle(a.title)
    fig.tight_layout()
    fig.savefig(a.png, dpi=110)


if __name__ == "__main__":
    main()
