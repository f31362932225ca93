#!/usr/bin/python3
"""The chip with and without fused multiply-add (chip.fma), side by side.

Usage: scripts/fma_compare.py OUT_DIR PLAIN_CSV FMA_CSV SCENE [PLAIN_CSV FMA_CSV SCENE ...]

Reads pairs of `rayunits study trax --kind formats` tables (the same scene, size and formats, the
second run with docs/trax/fma/config.toml) and the renderer's `--json` files in OUT_DIR/images
(written by scripts/trax_studies.sh), and writes OUT_DIR/fma_vs_plain.csv, .md and .png: per scene
and format the cycles, clock, area, rays/s per mm2 and image error of both chips, and their ratios.
Nothing here is measured by the script; it joins measured tables. Run with Debian's python3
(matplotlib).
"""
import csv
import glob
import json
import os
import sys


def die(msg):
    print(f"fma_compare.py: error: {msg}", file=sys.stderr)
    sys.exit(2)


def read(path):
    try:
        with open(path, newline="") as f:
            return {r["format"]: r for r in csv.DictReader(f)}
    except OSError as e:
        die(f"cannot read {path}: {e.strerror}")
    except KeyError:
        die(f"{path}: no 'format' column (not a `study trax --kind formats` table)")


def main(argv):
    if len(argv) < 5 or (len(argv) - 2) % 3:
        die("usage: fma_compare.py OUT_DIR PLAIN_CSV FMA_CSV SCENE [PLAIN_CSV FMA_CSV SCENE ...]")
    out = argv[1]
    cols = ["scene", "format", "cycles_plain", "cycles_fma", "cycles_ratio", "clock_mhz_plain", "clock_mhz_fma",
            "clock_unit_fma", "area_mm2_plain", "area_mm2_fma", "rays_per_s_per_mm2_plain", "rays_per_s_per_mm2_fma",
            "per_area_ratio", "psnr_db_plain", "psnr_db_fma", "error_pixels_plain", "error_pixels_fma"]
    rows = []
    for i in range(2, len(argv), 3):
        plain, fused, scene = read(argv[i]), read(argv[i + 1]), argv[i + 2]
        if set(plain) != set(fused):
            die(f"{argv[i]} and {argv[i + 1]} have different formats")
        for f in plain:
            p, q = plain[f], fused[f]
            rows.append({
                "scene": scene, "format": f,
                "cycles_plain": int(p["cycles"]), "cycles_fma": int(q["cycles"]),
                "cycles_ratio": round(int(q["cycles"]) / int(p["cycles"]), 3),
                "clock_mhz_plain": float(p["clock_mhz"]), "clock_mhz_fma": float(q["clock_mhz"]),
                "clock_unit_fma": q["clock_unit"],
                "area_mm2_plain": float(p["area_mm2"]), "area_mm2_fma": float(q["area_mm2"]),
                "rays_per_s_per_mm2_plain": float(p["rays_per_s_per_mm2"]),
                "rays_per_s_per_mm2_fma": float(q["rays_per_s_per_mm2"]),
                "per_area_ratio": round(float(q["rays_per_s_per_mm2"]) / float(p["rays_per_s_per_mm2"]), 3),
                "psnr_db_plain": float(p["psnr_db"]), "psnr_db_fma": float(q["psnr_db"]),
                "error_pixels_plain": int(p["error_pixels"]), "error_pixels_fma": int(q["error_pixels"]),
            })
    tmp = os.path.join(out, ".fma_vs_plain.csv.tmp")
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        w.writerows(rows)
    os.replace(tmp, os.path.join(out, "fma_vs_plain.csv"))

    md = ["### The chip with and without fused multiply-add (chip.fma)", "",
          "`scripts/trax_studies.sh` (its fma section); ratios are fma / plain, measured in the same run of the model.",
          "", "| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for r in rows:
        md.append("| " + " | ".join(str(r[c]) for c in cols) + " |")
    imgs = sorted(glob.glob(os.path.join(out, "images", "*.json")))
    if imgs:
        md += ["", "Renderer images (the chip's image, TraxImage.FmaEqualsRenderer), against the plain double render:",
               "", "| image | scene | format | fma | pixels > 10 % off | PSNR dB | max abs |", "|---|---|---|---|---:|---:|---:|"]
        for p in imgs:
            with open(p) as f:
                j = json.load(f)
            v = j["vs_double"]
            png = os.path.relpath(j["png"], out)  # written relative to the repository root
            md.append(f"| {png} | {j['scene']} | {j['format']} | {j['fma']} | {v['errors']} | {v['psnr_db']:.2f} | "
                      f"{v['max_abs']:.4f} |")
    tmp = os.path.join(out, ".fma_vs_plain.md.tmp")
    with open(tmp, "w") as f:
        f.write("\n".join(md) + "\n")
    os.replace(tmp, os.path.join(out, "fma_vs_plain.md"))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    fig, axes = plt.subplots(1, len(scenes), figsize=(5.5 * len(scenes), 4), squeeze=False)
    for ax, sc in zip(axes[0], scenes):
        rs = [r for r in rows if r["scene"] == sc]
        x = range(len(rs))
        ax.bar([i - 0.2 for i in x], [r["rays_per_s_per_mm2_plain"] for r in rs], 0.4, label="plain (FMUL + FADD)")
        ax.bar([i + 0.2 for i in x], [r["rays_per_s_per_mm2_fma"] for r in rs], 0.4, label="chip.fma (FFMA)")
        for i, r in zip(x, rs):
            ax.annotate(f"{r['per_area_ratio']:.2f}x", (i + 0.2, r["rays_per_s_per_mm2_fma"]), ha="center",
                        va="bottom", fontsize=8)
        ax.set_xticks(list(x))
        ax.set_xticklabels([r["format"] for r in rs], rotation=45)
        ax.set_ylabel("rays/s per mm2")
        ax.set_title(f"{sc}: rays/s per mm2 (label: fma / plain)")
        ax.legend(fontsize=8)
    fig.tight_layout()
    tmp = os.path.join(out, ".fma_vs_plain.tmp.png")
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, os.path.join(out, "fma_vs_plain.png"))
    print(f"wrote {out}/fma_vs_plain.csv, fma_vs_plain.md, fma_vs_plain.png")


if __name__ == "__main__":
    main(sys.argv)
