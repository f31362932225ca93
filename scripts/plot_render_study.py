#!/usr/bin/env python3
"""Plot of `rayunits study image`: pixels more than 10 % off and PSNR vs fraction bits, per
algorithm (and exponent width), with the dissertation's Tables 3.5/3.6 beside them when
shared/reference/table_3_5_3_6_image_errors.csv is found.
usage: plot_render_study.py image_errors.csv out.png"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def main():
    rows = read(sys.argv[1])
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    series = {}
    for r in rows:
        key = (r["algorithm"], r["exp_bits"])
        series.setdefault(key, []).append(r)
    for (algo, e), rs in sorted(series.items()):
        rs.sort(key=lambda r: int(r["frac_bits"]))
        m = [int(r["frac_bits"]) for r in rs]
        err = [100.0 * int(r["errors"]) / int(r["pixels"]) for r in rs]
        psnr = [float(r["psnr"]) if r["psnr"] != "inf" else 150.0 for r in rs]
        style = "-o" if algo == "robust" else "--s"
        ax1.plot(m, [max(x, 1e-4) for x in err], style, label=f"{rs[0]['scene']} {algo} e{e}")
        ax2.plot(m, psnr, style, label=f"{rs[0]['scene']} {algo} e{e}")
    here = os.path.dirname(os.path.abspath(__file__))
    for ref in [os.path.join(here, "..", "..", "shared", "reference", "table_3_5_3_6_image_errors.csv"),
                "/work/shared/reference/table_3_5_3_6_image_errors.csv"]:
        if os.path.exists(ref):
            ref_rows = read(ref)
            for scene, pixels in (("bunny", 512 * 512), ("sponza", 512 * 512)):
                rr = [r for r in ref_rows if r["scene"] == scene]
                m = [int(r["significand_bits"]) for r in rr]
                for algo, col in (("mt", "mt"), ("robust", "robust")):
                    ax1.plot(m, [max(100.0 * int(r[col + "_errors"]) / pixels, 1e-4) for r in rr], ":",
                             alpha=0.5, label=f"Kensler {scene} {algo}")
                    ax2.plot(m, [float(r[col + "_psnr"]) for r in rr], ":", alpha=0.5, label=f"Kensler {scene} {algo}")
            break
    ax1.set_yscale("log")
    ax1.set_xlabel("fraction bits")
    ax1.set_ylabel("% pixels > 10% off the double render")
    ax2.set_xlabel("fraction bits")
    ax2.set_ylabel("PSNR (dB; identical plotted at 150)")
    ax1.grid(alpha=0.3)
    ax2.grid(alpha=0.3)
    ax2.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=110)


if __name__ == "__main__":
    main()
