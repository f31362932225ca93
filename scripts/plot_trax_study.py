#!/usr/bin/env python3
"""Plots of `rayunits study trax` (issue 7 section 5).

usage: plot_trax_study.py KIND trax_KIND.csv out.png

formats    the headline plot: rays/s per area and image error (PSNR, error pixels) per format
rays       rays/s and cycles per ray for primary / + shadow / + diffuse bounce
traversal  stack vs stackless: cycles, box tests, node visits, area
noise      hardware noise unit vs software noise: rays/s, instructions, rays/s per area
texture    texture unit vs noise unit + TP sums vs software noise: the same three panels
units      FP adder/multiplier count sweep: rays/s, area, rays/s per area vs threads per unit
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def num(v):
    if v in ("inf", "+inf"):
        return float("inf")
    return float(v) if v not in ("", None) else float("nan")


def bars(ax, labels, values, title, ylabel, color):
    ax.bar(range(len(labels)), values, color=color)
    ax.set_xticks(range(len(labels)))
    ax.set_xticklabels(labels, fontsize=8)
    ax.set_title(title, fontsize=10)
    ax.set_ylabel(ylabel)
    ax.grid(axis="y", alpha=0.3)


def plot_formats(rows, fig):
    fmts = [r["format"] for r in rows]
    per_area = [num(r["rays_per_s_per_mm2"]) / 1e3 for r in rows]
    psnr = [min(num(r["psnr_db"]), 99.0) for r in rows]
    err = [num(r["error_pct"]) for r in rows]
    ok = [r["tolerated"] == "yes" for r in rows]
    has_dram = bool(rows) and "dram_bytes_per_ray" in rows[0]
    ax1 = fig.add_subplot(1, 3 if has_dram else 2, 1)
    for x, y, p, good in zip(psnr, per_area, fmts, ok):
        ax1.scatter([x], [y], color="tab:green" if good else "tab:red", s=40, zorder=3)
        ax1.annotate(p, (x, y), textcoords="offset points", xytext=(4, 4), fontsize=8)
    ax1.axvline(40, color="grey", ls="--", lw=0.8)
    ax1.set_xlabel("PSNR vs double (dB; identical images plotted at 99)")
    ax1.set_ylabel("k rays/s per mm2")
    ax1.set_title("speed per area vs image quality\n(green: <= 0.1 % error pixels and PSNR >= 40 dB)", fontsize=10)
    ax1.grid(alpha=0.3)
    ax2 = fig.add_subplot(1, 3 if has_dram else 2, 2)
    xs = range(len(fmts))
    ax2.bar(xs, [num(r["area_mm2"]) for r in rows], color="tab:blue", alpha=0.6, label="chip area")
    ax2.bar(xs, [num(r["unit_area_mm2"]) for r in rows], color="tab:blue", label="of which units")
    ax2.set_ylabel("area (mm2, osu018 cells; memories estimated)")
    ax2.set_xticks(list(xs))
    ax2.set_xticklabels(fmts, fontsize=8)
    ax3 = ax2.twinx()
    ax3.plot(list(xs), err, "o-", color="tab:red", label="error pixels (%)")
    ax3.set_ylabel("pixels more than 10 % off (%)", color="tab:red")
    ax2.legend(loc="upper left", fontsize=8)
    ax2.set_title("area and image error per format", fontsize=10)
    if has_dram:  # scene data in the format vs 32-bit words (issue 16)
        ax4 = fig.add_subplot(1, 3, 3)
        w = 0.4
        ax4.bar([x - w / 2 for x in xs], [num(r["dram_bytes_per_ray_word"]) for r in rows], w, color="tab:gray",
                label="scene in 32-bit words")
        ax4.bar([x + w / 2 for x in xs], [num(r["dram_bytes_per_ray"]) for r in rows], w, color="tab:purple",
                label="scene in the format")
        ax4.set_xticks(list(xs))
        ax4.set_xticklabels(fmts, fontsize=8)
        ax4.set_ylabel("DRAM bytes per ray")
        ax4.set_title("DRAM traffic per ray" + (" and memory access energy" if "memory_pj_per_ray" in rows[0] else ""),
                      fontsize=10)
        ax4.legend(fontsize=8, loc="upper left")
        ax4.grid(axis="y", alpha=0.3)
        if "memory_pj_per_ray" in rows[0]:  # issue 16: an estimate (Horowitz's 45 nm constants)
            ax5 = ax4.twinx()
            ax5.plot(list(xs), [num(r["memory_pj_per_ray_word"]) / 1e3 for r in rows], "s--", color="tab:gray",
                     label="energy, words")
            ax5.plot(list(xs), [num(r["memory_pj_per_ray"]) / 1e3 for r in rows], "o-", color="tab:purple",
                     label="energy, format")
            ax5.set_ylabel("memory access energy per ray (nJ, estimate)")
            ax5.set_ylim(bottom=0)
            ax5.legend(fontsize=8, loc="lower right")


def plot_rays(rows, fig):
    w = [r["workload"] for r in rows]
    bars(fig.add_subplot(1, 3, 1), w, [num(r["rays_per_s"]) / 1e6 for r in rows], "rays/s", "M rays/s", "tab:blue")
    bars(fig.add_subplot(1, 3, 2), w, [num(r["cycles_per_ray"]) for r in rows], "TP-cycles per ray", "cycles",
         "tab:orange")
    bars(fig.add_subplot(1, 3, 3), w, [num(r["l1_hit_pct"]) for r in rows], "L1 hit rate", "%", "tab:green")


def plot_traversal(rows, fig):
    t = [r["traversal"] for r in rows]
    bars(fig.add_subplot(1, 4, 1), t, [num(r["cycles"]) for r in rows], "cycles", "cycles", "tab:blue")
    bars(fig.add_subplot(1, 4, 2), t, [num(r["box_tests"]) for r in rows], "box tests", "tests", "tab:orange")
    bars(fig.add_subplot(1, 4, 3), t, [num(r["local_store_used_bytes"]) for r in rows], "local store used / thread",
         "bytes", "tab:green")
    bars(fig.add_subplot(1, 4, 4), t, [num(r["rays_per_s_per_mm2"]) / 1e3 for r in rows], "rays/s per area",
         "k rays/s per mm2", "tab:purple")


def plot_noise(rows, fig):
    n = [r["noise"] for r in rows]
    bars(fig.add_subplot(1, 3, 1), n, [num(r["rays_per_s"]) / 1e6 for r in rows], "rays/s", "M rays/s", "tab:blue")
    bars(fig.add_subplot(1, 3, 2), n, [num(r["instructions"]) / 1e6 for r in rows], "instructions", "10^6",
         "tab:orange")
    bars(fig.add_subplot(1, 3, 3), n, [num(r["rays_per_s_per_mm2"]) / 1e3 for r in rows], "rays/s per area",
         "k rays/s per mm2", "tab:purple")


def plot_texture(rows, fig):
    n = [r["variant"].replace(" + ", "\n+ ") for r in rows]
    bars(fig.add_subplot(1, 3, 1), n, [num(r["rays_per_s"]) / 1e6 for r in rows], "rays/s", "M rays/s", "tab:blue")
    bars(fig.add_subplot(1, 3, 2), n, [num(r["instructions"]) / 1e6 for r in rows], "instructions", "10^6",
         "tab:orange")
    bars(fig.add_subplot(1, 3, 3), n, [num(r["rays_per_s_per_mm2"]) / 1e3 for r in rows], "rays/s per area",
         "k rays/s per mm2", "tab:purple")


def plot_units(rows, fig):
    x = [num(r["threads_per_fp_unit"]) for r in rows]
    ax1 = fig.add_subplot(1, 2, 1)
    ax1.plot(x, [num(r["rays_per_s"]) / 1e6 for r in rows], "o-", label="M rays/s")
    ax1.set_xscale("log", base=2)
    ax1.invert_xaxis()
    ax1.set_xlabel("threads per FP adder / multiplier")
    ax1.set_ylabel("M rays/s")
    ax1.grid(alpha=0.3)
    ax1b = ax1.twinx()
    ax1b.plot(x, [num(r["area_mm2"]) for r in rows], "s--", color="tab:grey")
    ax1b.set_ylabel("area (mm2)", color="tab:grey")
    ax1.set_title("speed and area", fontsize=10)
    ax2 = fig.add_subplot(1, 2, 2)
    ax2.plot(x, [num(r["rays_per_s_per_mm2"]) / 1e3 for r in rows], "o-", color="tab:purple")
    ax2.set_xscale("log", base=2)
    ax2.invert_xaxis()
    ax2.set_xlabel("threads per FP adder / multiplier")
    ax2.set_ylabel("k rays/s per mm2")
    ax2.set_title("rays/s per area", fontsize=10)
    ax2.grid(alpha=0.3)


PLOTS = {"formats": (plot_formats, (17, 4.8)), "rays": (plot_rays, (12, 3.8)),
         "traversal": (plot_traversal, (14, 3.6)), "noise": (plot_noise, (12, 3.8)), "units": (plot_units, (12, 4.4)),
         "texture": (plot_texture, (12, 3.8))}


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in PLOTS:
        sys.exit("usage: plot_trax_study.py formats|rays|traversal|noise|units|texture trax_KIND.csv out.png")
    rows = list(csv.DictReader(open(sys.argv[2])))
    if not rows:
        sys.exit(f"{sys.argv[2]}: no rows")
    fn, size = PLOTS[sys.argv[1]]
    fig = plt.figure(figsize=size)
    fn(rows, fig)
    fig.suptitle(f"TRaX model: {sys.argv[1]} study ({sys.argv[2].split('/')[-1]})", fontsize=11)
    fig.tight_layout()
    fig.savefig(sys.argv[3], dpi=110)


if __name__ == "__main__":
    main()
