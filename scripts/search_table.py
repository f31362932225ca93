#!/usr/bin/env python3
"""Markdown table of a formulation search (rayunits search tri --out DIR): the reported designs
and the hand designs (references) from DIR/front.csv, and with --plot FILE.png the Pareto front
of everything evaluated (DIR/pareto_all.csv) as area against mean relative error.

usage: scripts/search_table.py DIR [--plot FILE.png]
"""
import csv
import os
import sys


def main(argv):
    if len(argv) < 2 or argv[1].startswith("-"):
        sys.exit("usage: search_table.py DIR [--plot FILE.png]")
    d = argv[1]
    path = os.path.join(d, "front.csv")
    if not os.path.exists(path):
        sys.exit(f"search_table.py: no {path} (run rayunits search tri --out {d} first)")
    rows = list(csv.DictReader(open(path)))
    print("| design | role | area µm² (estimate) | latency | mean rel. err. | max rel. err. "
          "| leaks | false misses | double hits | false hits | RTL |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|")
    for r in rows:
        role = r["role"].replace("reference:", "hand: ")
        print(f"| `{r['genome']}` | {role} | {float(r['area_um2']):,.0f} | {r['latency']} "
              f"| {float(r['mean_rel']):.3g} | {float(r['max_rel']):.3g} | {r['leaks']} | {r['false_misses']} "
              f"| {r['double_hits']} | {r['false_hits']} | {r.get('rtl', '') or ''} |")
    if "--plot" in argv:
        out = argv[argv.index("--plot") + 1]
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        allrows = list(csv.DictReader(open(os.path.join(d, "pareto_all.csv"))))
        fig, ax = plt.subplots(figsize=(7, 4.5))
        x = [float(r["area_um2"]) / 1e6 for r in allrows]
        y = [float(r["mean_rel"]) for r in allrows]
        c = [int(r["leaks"]) + int(r["false_misses"]) for r in allrows]
        sc = ax.scatter(x, y, c=c, cmap="viridis", s=14, label="Pareto front (all evaluated)")
        fig.colorbar(sc, label="misses (leaks + false misses)")
        labelled = 0
        for r in rows:
            if r["role"] == "front":
                ax.scatter(float(r["area_um2"]) / 1e6, float(r["mean_rel"]), facecolors="none",
                           edgecolors="k", s=60)
            else:
                ax.scatter(float(r["area_um2"]) / 1e6, float(r["mean_rel"]), marker="x", c="r", s=60)
                ax.annotate(r["role"].replace("reference:", ""),
                            (float(r["area_um2"]) / 1e6, float(r["mean_rel"])), fontsize=8,
                            xytext=(4, 4 + 10 * labelled), textcoords="offset points",
                            arrowprops={"arrowstyle": "-", "lw": 0.5})
                labelled += 1
        ax.set_yscale("log")
        ax.set_xlabel("area, mm² (cost-model estimate, osu018)")
        ax.set_ylabel("mean relative error of t, β, γ (worst of the three)")
        ax.set_title(f"rayunits search tri: {os.path.basename(os.path.normpath(d))} "
                     "(circles: reported, x: hand designs)", fontsize=9)
        fig.tight_layout()
        fig.savefig(out, dpi=110)
        print(f"\nwrote {out}", file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv)
