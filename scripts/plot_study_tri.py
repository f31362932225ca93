#!/usr/bin/env python3
"""Heat maps of `rayunits study tri` (dissertation Tables 3.2-3.4 shape).

usage: plot_study_tri.py study_tri_tables.csv out.png

Top row: this run's lowest average relative error of V, Va and V0..2 per (significand bits,
exponent bits), log10 colour scale; bottom row: the dissertation's values from the same CSV
(column dissertation_avg_rel_error), when present. Empty cells were not evaluated.
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

VOLUMES = [("V", "V (Table 3.2)"), ("Va", "Va (Table 3.3)"), ("V012", "V0..2 (Table 3.4)")]


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_study_tri.py study_tri_tables.csv out.png")
    rows = [r for r in csv.DictReader(line for line in open(sys.argv[1]) if not line.startswith("#"))]
    if not rows:
        sys.exit(f"{sys.argv[1]}: no rows")
    ms = sorted({int(r["significand_bits"]) for r in rows})
    es = sorted({int(r["exponent_bits"]) for r in rows})
    have_ref = any(r["dissertation_avg_rel_error"] for r in rows)
    nrow = 2 if have_ref else 1
    fig, axes = plt.subplots(nrow, 3, figsize=(13, 5.2 * nrow), squeeze=False)
    for col, (vol, title) in enumerate(VOLUMES):
        for row, key in enumerate(["avg_rel_error", "dissertation_avg_rel_error"][:nrow]):
            grid = np.full((len(ms), len(es)), np.nan)
            for r in rows:
                if r["volume"] != vol or not r[key]:
                    continue
                v = float(r[key])
                if v > 0:
                    grid[ms.index(int(r["significand_bits"])), es.index(int(r["exponent_bits"]))] = math.log10(v)
            ax = axes[row][col]
            im = ax.imshow(grid, origin="upper", aspect="auto", cmap="viridis", vmin=-8, vmax=1)
            ax.set_xticks(range(len(es)))
            ax.set_xticklabels(es)
            ax.set_yticks(range(len(ms)))
            ax.set_yticklabels(ms, fontsize=7)
            ax.set_xlabel("exponent bits")
            ax.set_ylabel("significand (fraction) bits")
            ax.set_title(("this run: " if row == 0 else "dissertation: ") + title, fontsize=10)
            for i in range(len(ms)):
                for j in range(len(es)):
                    if not np.isnan(grid[i, j]):
                        ax.text(j, i, f"{grid[i, j]:.1f}", ha="center", va="center", fontsize=5.5,
                                color="white" if grid[i, j] < -3 else "black")
            fig.colorbar(im, ax=ax, label="log10 avg. relative error")
    fig.suptitle("Lowest average relative error over all equivalent scalar triple products")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=110)


if __name__ == "__main__":
    main()
