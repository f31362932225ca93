#!/usr/bin/env python3
"""Plot a synthesis sweep (rayunits synth-sweep): usage plot_sweep.py synth_sweep.json out.png

Four panels: area (NAND2-eq) vs fraction bits at the smallest and the largest stage count of
each unit; area vs stages; estimated Fmax (delay model of synth/README.md) vs stages; iCE40
Fmax from nextpnr vs stages (when the sweep ran with --fpga). One colour per unit, one marker
per format. Rows with an "error" are left out (they are listed in the JSON and CSV).
"""
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MARKERS = "osD^vP*Xh<>"


def main(argv):
    if len(argv) != 3:
        sys.exit("usage: plot_sweep.py synth_sweep.json out.png")
    with open(argv[1]) as f:
        data = json.load(f)
    rows = [r for r in data["rows"] if "error" not in r and r.get("frac_bits") is not None]
    if not rows:
        sys.exit("plot_sweep.py: no successful floating-point rows to plot in " + argv[1])
    units = sorted({r["unit"] for r in rows})
    fmts = sorted({r["format"] for r in rows}, key=lambda f: (int(f.split("m")[1].split("-")[0]), f))
    colour = {u: "C%d" % i for i, u in enumerate(units)}
    marker = {f: MARKERS[i % len(MARKERS)] for i, f in enumerate(fmts)}

    fig, ax = plt.subplots(2, 2, figsize=(13, 9))
    (a_fb, a_st), (f_est, f_ice) = ax

    for u in units:
        ur = [r for r in rows if r["unit"] == u]
        smin = min(r["stages"] for r in ur)
        # largest stage count reached by every format of this unit
        per_fmt_max = {}
        for r in ur:
            per_fmt_max[r["format"]] = max(per_fmt_max.get(r["format"], -1), r["stages"])
        for style, pick in (("-", lambda r: r["stages"] == smin),
                            ("--", lambda r: r["stages"] == per_fmt_max[r["format"]])):
            pts = sorted((r["frac_bits"], r["area_nand2"], r["stages"]) for r in ur if pick(r))
            if not pts:
                continue
            lab = "%s, %s" % (u, "s%d" % smin if style == "-" else "max stages")
            a_fb.plot([p[0] for p in pts], [p[1] for p in pts], style, color=colour[u], marker="o", label=lab)
        for f in fmts:
            fr = sorted((r for r in ur if r["format"] == f), key=lambda r: r["stages"])
            if not fr:
                continue
            st = [r["stages"] for r in fr]
            a_st.plot(st, [r["area_nand2"] for r in fr], "-", color=colour[u], marker=marker[f],
                      label="%s %s" % (u, f))
            f_est.plot(st, [r["fmax_est_mhz"] for r in fr], "-", color=colour[u], marker=marker[f],
                       label="%s %s" % (u, f))
            ice = [(r["stages"], r["ice40"]["fmax_mhz"]) for r in fr
                   if r.get("ice40") and r["ice40"].get("fmax_mhz") is not None]
            if ice:
                f_ice.plot([p[0] for p in ice], [p[1] for p in ice], "-", color=colour[u], marker=marker[f],
                           label="%s %s" % (u, f))

    a_fb.set_xlabel("fraction bits M")
    a_fb.set_ylabel("area (NAND2-eq)")
    a_fb.set_title("area vs fraction bits (solid: fewest stages, dashed: most)")
    a_st.set_xlabel("pipeline stages")
    a_st.set_ylabel("area (NAND2-eq)")
    a_st.set_title("area vs stages")
    f_est.set_xlabel("pipeline stages")
    f_est.set_ylabel("estimated Fmax (MHz)")
    f_est.set_title("estimated Fmax, delay model %s" % data.get("meta", {}).get("delay_model", "?"))
    f_ice.set_xlabel("pipeline stages")
    f_ice.set_ylabel("iCE40 Fmax (MHz, nextpnr)")
    f_ice.set_title("iCE40 %s Fmax (nextpnr)" % next(
        (r["ice40"]["device"] for r in rows if r.get("ice40")), "?"))
    if not f_ice.lines:
        f_ice.text(0.5, 0.5, "no place-and-route data\n(run the sweep with --fpga)", ha="center",
                   va="center", transform=f_ice.transAxes)
    for a in (a_fb, a_st, f_est, f_ice):
        a.grid(True, alpha=0.3)
        if a.lines:
            a.legend(fontsize=7, ncol=2)
    meta = data.get("meta", {})
    fig.suptitle("rayunits synthesis sweep: %s, commit %s" % (meta.get("yosys", "?"), meta.get("commit", "?")),
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(argv[2], dpi=110)


if __name__ == "__main__":
    main(sys.argv)
