#!/usr/bin/python3
"""Plots of `rayunits noise study` (called by it; rerun by hand: plot_noise.py OUT_DIR [DPI]).

Reads OUT_DIR/noise_error_vs_bits.csv and the slice/spectrum PNGs; writes
  noise_error_vs_bits.png  max/RMS error and PSNR of the fixed-point model vs fraction bits
  noise_gallery.png        every slice above its power spectrum (the figures of sec. 4.5-4.8)
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.image as mpimg  # noqa: E402


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit("usage: plot_noise.py OUT_DIR [DPI]")
    out = sys.argv[1]
    dpi = int(sys.argv[2]) if len(sys.argv) == 3 else 110
    rows = list(csv.DictReader(open(os.path.join(out, "noise_error_vs_bits.csv"))))
    # the error curves: rows with the exact output width (out_w = 2B - 1), one per datapath
    # (full = ru_noise, trunc = ru_noise_trunc; files without the column are the full datapath)
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    ax2 = ax.twinx()
    for dp, style in (("full", "-"), ("trunc", ":")):
        curve = [r for r in rows if int(r["out_w"]) == 2 * int(r["frac_bits"]) - 1 and r.get("datapath", "full") == dp]
        if not curve:
            continue
        b = [int(r["frac_bits"]) for r in curve]
        ax.semilogy(b, [float(r["max_abs"]) for r in curve], "o" + style, color="tab:blue", label="max |error| " + dp)
        ax.semilogy(b, [float(r["rms"]) for r in curve], "s" + style, color="tab:orange", label="RMS error " + dp)
        ax2.plot(b, [float(r["psnr_db"]) for r in curve], "^" + style, color="tab:green", label="PSNR (8-bit image) " + dp)
    ax.set_xlabel("fraction bits B")
    ax.set_ylabel("error (units of N, |N| <= 0.18)")
    ax.grid(True, which="both", alpha=0.3)
    ax2.set_ylabel("PSNR dB")
    lines = ax.get_legend_handles_labels()
    lines2 = ax2.get_legend_handles_labels()
    ax.legend(lines[0] + lines2[0], lines[1] + lines2[1], loc="center right")
    ax.set_title("fixed-point noise model vs float half-resolution reference")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "noise_error_vs_bits.png"), dpi=dpi)
    plt.close(fig)

    names = [r["noise"] for r in csv.DictReader(open(os.path.join(out, "noise_spectra.csv")))]
    fig, axes = plt.subplots(2, len(names), figsize=(2.3 * len(names), 4.9))
    for i, n in enumerate(names):
        for j, kind in enumerate(("slice", "spectrum")):
            p = os.path.join(out, "noise_%s_%s.png" % (n, kind))
            a = axes[j][i]
            a.imshow(mpimg.imread(p), cmap="gray", vmin=0, vmax=1)
            a.set_xticks([])
            a.set_yticks([])
            if j == 0:
                a.set_title(n.replace("_", " "), fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "noise_gallery.png"), dpi=dpi)
    plt.close(fig)
    print("plot_noise.py: wrote noise_error_vs_bits.png and noise_gallery.png in " + out)


if __name__ == "__main__":
    main()
