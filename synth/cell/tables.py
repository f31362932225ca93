#!/usr/bin/python3
"""Tables and the area-delay plot of the osu018 cell-flow measurements (synth/cell/run.py).

Reads synth/results/cell/*.jsonl (the checked-in rows; every row carries its command) and
writes synth/results/cell/tables.md and synth/results/cell/area_delay.png.

    /usr/bin/python3 synth/cell/tables.py [--out DIR]
"""
import argparse
import glob
import json
import os
import statistics

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RES = os.path.join(ROOT, "synth", "results", "cell")

FP_UNITS = ["fp_add", "fp_mul", "fp_div", "fp_sqrt", "fp_fma", "fp_cmp", "fp_dot3", "fp_dot3_fused", "fp_cvt"]
RAY_UNITS = ["ray_box", "ray_tri_robust", "ray_tri_mt"]
FORMATS = ["e5m10", "e7m16", "e8m23"]

# Kensler, Table 4.1 (65 nm, Design Compiler; shared/reference/table_4_1_noise_area.csv).
KENSLER_41 = [  # stages, retimed, MHz, comb, seq, total
    (0, "no", 344, 60350, 0, 60350),
    (1, "no", 337, 57052, 2470, 59522),
    (3, "yes", 1000, 76256, 11980, 88236),
    (4, "yes", 1000, 58090, 11470, 69560),
]
KENSLER_ALU = 34000  # binary32 FP ALU (add/sub/mul), um2, same flow, 1 GHz
KENSLER_DOT3 = 111000  # binary32 3-element dot product
# FO4 of Kensler's 65 nm process: not stated by him. Rule of thumb FO4 ~ 360 ps per um of drawn
# gate length at typical conditions (500 ps/um worst case): 65 nm -> 23.4 ps (32.5 ps worst case).
FO4_65_PS = 0.36 * 65
FO4_65_WORST_PS = 0.50 * 65


def fmt_int(v):
    return f"{v:,.0f}"


def load():
    rows = []
    for p in sorted(glob.glob(os.path.join(RES, "*.jsonl"))):
        with open(p) as f:
            for line in f:
                if line.strip():
                    r = json.loads(line)
                    r["_file"] = os.path.basename(p)
                    rows.append(r)
    return rows


# RTL options that make a different circuit of the same unit: such rows are keyed (and shown)
# as "unit Option=V" (ray_box OptConservative=2, ray_tri_robust OptRecip=1).
VARIANT_PARAMS = ("OptConservative", "OptRecip")


def key(r):
    p = r.get("params") or {}
    var = " ".join(f"{k}={p[k]}" for k in VARIANT_PARAMS if p.get(k))
    return (r["unit"] + (" " + var if var else ""), r.get("format"), r["stages"])


def cell_rows(rows):
    """Rows of the targeted cell flow (ends, curves, match tries), by (unit, format, stages)."""
    out = {}
    for r in rows:
        # registers placed by measured delays: only in the placement table
        if r.get("flow") == "osu018" and r.get("target_clock_ps") and "period_ps" in r and \
                r.get("placement", "depth") == "depth":
            out.setdefault(key(r), []).append(r)
    for k in out:
        out[k].sort(key=lambda r: (r["period_ps"], r["area_um2"]))
    return out


def generic_rows(rows):
    return {key(r): r for r in rows if r.get("flow") == "generic" and "area_nand2" in r}


def nf_rows(rows):
    return {key(r): r for r in rows if r.get("flow") == "osu018" and r.get("target_clock_ps") is None
            and "period_ps" in r}


def has_ends(rs):
    """A point measured at both ends (200 ps and 1 us targets), not only by matched-clock tries."""
    t = {r["target_clock_ps"] for r in rs}
    return FAST in t or any(x <= 2000 for x in t)


FAST = 200.0


def fastest(rs):
    return min(rs, key=lambda r: (r["period_ps"], r["area_um2"]))


def smallest(rs):
    return min(rs, key=lambda r: (r["area_um2"], r["period_ps"]))


def ends_command(rs):
    for r in rs:
        if r["point"].endswith(".ends") or r["point"].endswith(".relaxed"):
            return r["command"]
    return rs[0]["command"]


def ns(ps):
    return f"{ps / 1000:.2f}"


def note_marks(rs):
    return " †" if any(r.get("driver_note") for r in rs) else ""


def fp_table(cr, gr, units, formats, title_cmd):
    lines = [
        "| unit | format | Stages | fastest: clock ns | Fmax MHz | FO4/cycle | area um2 (comb + seq) | smallest: area um2 | at clock ns | critical segment | NAND2-eq (generic estimate) |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---|---:|",
    ]
    for u in units:
        for f in formats:
            ks = sorted(k for k in cr if k[0] == u and k[1] == f and has_ends(cr[k]))
            for k in ks:
                rs = cr[k]
                a, b = fastest(rs), smallest(rs)
                g = gr.get(k)
                seg = a["critical_path"]
                lines.append(
                    f"| {u} | {f} | {k[2]} | {ns(a['period_ps'])} | {a['fmax_mhz']:.1f} | {a['period_fo4']:.1f} | "
                    f"{fmt_int(a['area_um2'])} ({fmt_int(a['area_comb_um2'])} + {fmt_int(a['area_seq_um2'])}) | "
                    f"{fmt_int(b['area_um2'])} | {ns(b['period_ps'])} | {seg['segment']} of {seg['segments']} | "
                    f"{fmt_int(g['area_nand2']) if g else '—'} |{note_marks(rs)}")
    return lines


def placement_table(rows):
    """Depth-based vs delay-based register placement at equal Stages (fastest mappings)."""
    pts = {}
    for r in rows:
        for how in ("depth", "delay"):
            if r.get("point", "").endswith(".place_" + how) and "period_ps" in r:
                pts.setdefault(key(r), {})[how] = r
    lines = ["| unit | format | Stages | depth: worst stage ns | stage periods ns | delay: worst stage ns | "
             "stage periods ns | delay / depth period | area um2 depth → delay |",
             "|---|---|---:|---:|---|---:|---|---:|---|"]
    ratios = []
    order = {u: i for i, u in enumerate(["fp_add", "fp_mul", "fp_div", "fp_cmp"])}
    fmts = {f: i for i, f in enumerate(["e5m10", "e7m16", "e8m23"])}
    for k in sorted(pts, key=lambda k: (order.get(k[0], 9), fmts.get(k[1], 9), k[2])):
        p = pts[k]
        if "depth" not in p or "delay" not in p:
            continue
        a, b = p["depth"], p["delay"]
        st = lambda r: " / ".join(f"{x / 1000:.2f}" for x in (r.get("stage_periods_ps") or []))
        ratio = b["period_ps"] / a["period_ps"]
        ratios.append(ratio)
        lines.append(f"| {k[0]} | {k[1]} | {k[2]} | {ns(a['period_ps'])} | {st(a)} | {ns(b['period_ps'])} | {st(b)} | "
                     f"{ratio:.3f} | {fmt_int(a['area_um2'])} → {fmt_int(b['area_um2'])} |")
    if ratios:
        s = sorted(ratios)
        med = s[len(s) // 2] if len(s) % 2 else (s[len(s) // 2 - 1] + s[len(s) // 2]) / 2
        better = sum(1 for x in ratios if x < 0.99)
        worse = sum(1 for x in ratios if x > 1.01)
        lines += ["", f"{len(ratios)} configurations: delay-based placement faster by more than 1 % in {better}, "
                  f"slower by more than 1 % in {worse}; median period ratio {med:.3f}, best {s[0]:.3f}, "
                  f"worst {s[-1]:.3f}."]
    return lines


def curve_table(cr):
    lines = ["| unit | format | Stages | target ps | achieved ps | Fmax MHz | FO4/cycle | met | area um2 | comb | seq | cells | critical path segment, cells | file |",
             "|---|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---|---|"]
    order = {u: i for i, u in enumerate(FP_UNITS + RAY_UNITS + ["noise"])}
    for k in sorted(cr, key=lambda k: (order.get(k[0], 99), k[1] or "", k[2])):
        for r in sorted(cr[k], key=lambda r: r["target_clock_ps"]):
            cp = r["critical_path"]
            lines.append(
                f"| {k[0]} | {k[1] or '—'} | {k[2]} | {r['target_clock_ps']:.0f} | {r['period_ps']:.0f} | {r['fmax_mhz']:.1f} | "
                f"{r['period_fo4']:.1f} | {'yes' if r['met'] else 'no'} | {fmt_int(r['area_um2'])} | {fmt_int(r['area_comb_um2'])} | "
                f"{fmt_int(r['area_seq_um2'])} | {r['cell_count']} | {cp['segment']}/{cp['segments']}, {cp['cells']} | {r['_file']} |")
    return lines


def noise_table(cr, gr, unit="noise"):
    lines = [
        "| Stages | fastest: clock ns | MHz | FO4/cycle | area um2 | comb | seq | smallest: area um2 | comb | seq | at MHz | NAND2-eq (generic estimate) | Kensler (65 nm, DC): MHz | FO4/cycle (est.) | um2 comb + seq = total |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    kens = {s: (ret, mhz, c, q, t) for s, ret, mhz, c, q, t in KENSLER_41}
    for s in range(0, 8):
        k = (unit, None, s)
        if k not in cr:
            continue
        a, b = fastest(cr[k]), smallest(cr[k])
        g = gr.get(k)
        if s in kens:
            ret, mhz, c, q, t = kens[s]
            kcol = (f"{mhz}{' (retimed)' if ret == 'yes' else ''} | {1e6 / mhz / FO4_65_PS:.0f} | "
                    f"{fmt_int(c)} + {fmt_int(q)} = {fmt_int(t)}")
        else:
            kcol = "— | — | —"
        lines.append(
            f"| {s} | {ns(a['period_ps'])} | {a['fmax_mhz']:.1f} | {a['period_fo4']:.1f} | {fmt_int(a['area_um2'])} | "
            f"{fmt_int(a['area_comb_um2'])} | {fmt_int(a['area_seq_um2'])} | {fmt_int(b['area_um2'])} | "
            f"{fmt_int(b['area_comb_um2'])} | {fmt_int(b['area_seq_um2'])} | {b['fmax_mhz']:.1f} | "
            f"{fmt_int(g['area_nand2']) if g else '—'} | {kcol} |{note_marks(cr[k])}")
    return lines


def match_tables(rows):
    """Matched clock: for each clock, each unit's smallest Stages that met it."""
    by_clk = {}
    for r in rows:
        if "match_clock_ps" in r and "period_ps" in r and "meets_match_clock" in r:
            by_clk.setdefault(r["match_clock_ps"], {}).setdefault(r["unit"], []).append(r)
    out = []
    summary = {}
    for clk in sorted(by_clk):
        units = by_clk[clk]
        out.append(f"\n**Clock {clk / 1000:g} ns ({1e6 / clk:.0f} MHz, {clk / 98.32:.1f} FO4 of osu018)**\n")
        out.append("| unit | Stages tried (best ns) | smallest Stages meeting it | ABC target ps | achieved ns | area um2 (comb + seq) | command |")
        out.append("|---|---|---:|---:|---:|---:|---|")
        met = {}
        for u in ["noise", "fp_add", "fp_mul", "fp_dot3", "noise_trunc"]:
            rs = sorted(units.get(u, []), key=lambda r: r["stages"])
            if not rs:
                out.append(f"| {u} | not run | | | | | |")
                continue
            ok_stages = sorted({r["stages"] for r in rs if r.get("meets_match_clock")})
            m = None
            if ok_stages:  # the smallest Stages that meets it; of its mappings the smallest that meets it
                m = min((r for r in rs if r["stages"] == ok_stages[0] and r["meets_match_clock"]),
                        key=lambda r: r["area_um2"])
            per_s = {}
            for r in rs:
                per_s.setdefault(r["stages"], []).append(r)
            tried = ", ".join(f"{s_} ({min(x['period_ps'] for x in v) / 1000:.2f})" for s_, v in sorted(per_s.items()))
            if m:
                met[u] = m
                out.append(f"| {u} | {tried} | {m['stages']} | {m['target_clock_ps']:.0f} | {ns(m['period_ps'])} | {fmt_int(m['area_um2'])} "
                           f"({fmt_int(m['area_comb_um2'])} + {fmt_int(m['area_seq_um2'])}) | `{m['command']}` |")
            else:
                out.append(f"| {u} | {tried} | none up to {max(per_s)} | | | | |")
        if all(u in met for u in ["noise", "fp_add", "fp_mul", "fp_dot3"]):
            n, a, mu, d = (met[u]["area_um2"] for u in ["noise", "fp_add", "fp_mul", "fp_dot3"])
            summary[clk] = dict(alu=n / (a + mu), dot3=n / d, noise=n, add=a, mul=mu, d=d,
                                stages={u: met[u]["stages"] for u in met})
            out.append("")
            out.append(f"noise / (fp_add + fp_mul) = {fmt_int(n)} / ({fmt_int(a)} + {fmt_int(mu)}) = **{n / (a + mu):.2f}** "
                       f"(Kensler 2.0 at 1 GHz); noise / fp_dot3 = {fmt_int(n)} / {fmt_int(d)} = **{n / d:.2f}** (Kensler 0.63).")
            if "noise_trunc" in met:
                t = met["noise_trunc"]["area_um2"]
                summary[clk].update(trunc=t, trunc_alu=t / (a + mu), trunc_mul=t / mu, trunc_dot3=t / d)
                out.append("")
                out.append(f"noise_trunc / (fp_add + fp_mul) = {fmt_int(t)} / ({fmt_int(a)} + {fmt_int(mu)}) = **{t / (a + mu):.2f}** "
                           f"(Kensler 2.0); noise_trunc / fp_mul = **{t / mu:.2f}**; noise_trunc / fp_dot3 = {fmt_int(t)} / "
                           f"{fmt_int(d)} = **{t / d:.2f}** (Kensler 0.63); noise_trunc / noise = **{t / n:.2f}**.")
    return out, summary


def ray_table(cr):
    lines = ["| unit | format | Stages | fastest: clock ns | Fmax MHz | FO4/cycle | area um2 | smallest: area um2 | at clock ns | command |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|---|"]
    for u in RAY_UNITS:
        for f in ["e7m16", "e8m23"]:
            for k in sorted(k for k in cr if k[0].split()[0] == u and k[1] == f):
                rs = cr[k]
                a, b = fastest(rs), smallest(rs)
                fast_known = any(r["target_clock_ps"] <= 2000 for r in rs)
                lines.append(
                    f"| {k[0]} | {f} | {k[2]} | {ns(a['period_ps']) if fast_known else '(not run)'} | "
                    f"{format(a['fmax_mhz'], '.1f') if fast_known else ''} | {format(a['period_fo4'], '.1f') if fast_known else ''} | "
                    f"{fmt_int(a['area_um2']) if fast_known else ''} | {fmt_int(b['area_um2'])} | {ns(b['period_ps'])} | "
                    f"{'; '.join(sorted({'`' + r['command'] + '`' for r in rs}))} |")
    def fast_rows(rs):
        return [r for r in rs if r["target_clock_ps"] <= 2000]

    def ratio_line(label, ka, kb):
        """Area ratio of two points: smallest mappings, and fastest mappings where both were run."""
        ba, bb = smallest(cr[ka]), smallest(cr[kb])
        line = (f"- {label}: smallest mappings {fmt_int(ba['area_um2'])} / {fmt_int(bb['area_um2'])} um2 = "
                f"**{ba['area_um2'] / bb['area_um2']:.2f}**")
        fa, fb = fast_rows(cr[ka]), fast_rows(cr[kb])
        if fa and fb:
            line += (f"; fastest mappings {fmt_int(fa[0]['area_um2'])} / {fmt_int(fb[0]['area_um2'])} um2 = "
                     f"{fa[0]['area_um2'] / fb[0]['area_um2']:.2f} (clocks {ns(fa[0]['period_ps'])} / "
                     f"{ns(fb[0]['period_ps'])} ns)")
        return line

    ratio = []
    for f in ["e7m16", "e8m23"]:
        for s_r, s_m in [(0, 0), (29, 33)]:
            kr, km = ("ray_tri_robust", f, s_r), ("ray_tri_mt", f, s_m)
            if kr in cr and km in cr:
                ratio.append(ratio_line(f"{f}, robust Stages {s_r} / MT Stages {s_m}", kr, km))
    # the variants beside their base circuit and a second reference (issue 14 sections 3 and 4)
    for var, base, other in [("ray_tri_robust OptRecip=1", "ray_tri_robust", "ray_tri_mt"),
                             ("ray_box OptConservative=1", "ray_box", None),
                             ("ray_box OptConservative=2", "ray_box", "ray_box OptConservative=1")]:
        for k in sorted(k for k in cr if k[0] == var):
            for ref in (base, other):
                kb = (ref, k[1], k[2]) if ref else None
                if kb in cr:
                    ratio.append(ratio_line(f"{k[1]} Stages {k[2]}, {var} / {ref}", k, kb))
    return lines, ratio


def time_table(rows):
    """Wall time of the flow per unit and format, from the rows' own seconds."""
    runs = {}
    for r in rows:
        if r.get("flow") != "osu018" or "step_seconds" not in r or "match_clock_ps" in r:
            continue
        runs.setdefault((r["unit"], r.get("format"), r["stages"], r["point"]), []).append(r)
    agg = {}
    for (u, f, s, p), rs in runs.items():
        a = agg.setdefault((u, f), dict(premap=[], abc=[], sta=[], total=0.0, runs=0, clocks=0, stages=set()))
        a["premap"].append(rs[0]["step_seconds"]["premap_shared"])
        a["abc"] += [r["step_seconds"]["abc_map"] for r in rs]
        a["sta"] += [r["step_seconds"]["sta"] for r in rs]
        a["total"] += rs[0]["driver_seconds"]
        a["runs"] += 1
        a["clocks"] += len(rs)
        a["stages"].add(s)
    gen = {}
    for r in rows:
        if r.get("flow") == "generic" and "seconds" in r:
            gen.setdefault((r["unit"], r.get("format")), []).append(r["seconds"])
    order = {u: i for i, u in enumerate(FP_UNITS + ["noise"] + RAY_UNITS)}
    lines = ["| unit | format | Stages measured | runs | mappings | synth + dfflibmap s (median, max) | ABC map per target s (median, max) | STA per target s (median) | wall s, all runs | generic flow s (median) |",
             "|---|---|---|---:|---:|---:|---:|---:|---:|---:|"]
    for (u, f) in sorted(agg, key=lambda k: (order.get(k[0], 99), k[1] or "")):
        a = agg[(u, f)]
        g = gen.get((u, f))
        lines.append(f"| {u} | {f or '—'} | {', '.join(map(str, sorted(a['stages'])))} | {a['runs']} | {a['clocks']} | "
                     f"{statistics.median(a['premap']):.1f}, {max(a['premap']):.1f} | "
                     f"{statistics.median(a['abc']):.1f}, {max(a['abc']):.1f} | {statistics.median(a['sta']):.2f} | "
                     f"{a['total']:.0f} | {statistics.median(g):.1f} |" if g else
                     f"| {u} | {f or '—'} | {', '.join(map(str, sorted(a['stages'])))} | {a['runs']} | {a['clocks']} | "
                     f"{statistics.median(a['premap']):.1f}, {max(a['premap']):.1f} | "
                     f"{statistics.median(a['abc']):.1f}, {max(a['abc']):.1f} | {statistics.median(a['sta']):.2f} | "
                     f"{a['total']:.0f} | — |")
    total = sum(a["total"] for a in agg.values())
    return lines, total


def _unused_nf_table(cr, nf):
    lines = ["| unit | format | Stages | `&nf` (no target): area um2, clock ns | map flow fastest: area, clock ns | map flow smallest: area, clock ns | `&nf` ABC s | map ABC s (per target) |",
             "|---|---|---:|---:|---:|---:|---:|---:|"]
    for k, r in sorted(nf.items(), key=lambda kv: (kv[0][0], kv[0][1] or "", kv[0][2])):
        if k not in cr:
            continue
        a, b = fastest(cr[k]), smallest(cr[k])
        abc = statistics.median(x["step_seconds"]["abc_map"] for x in cr[k])
        lines.append(f"| {k[0]} | {k[1] or '—'} | {k[2]} | {fmt_int(r['area_um2'])}, {ns(r['period_ps'])} | "
                     f"{fmt_int(a['area_um2'])}, {ns(a['period_ps'])} | {fmt_int(b['area_um2'])}, {ns(b['period_ps'])} | "
                     f"{r['step_seconds']['abc_map']:.1f} | {abc:.1f} |")
    return lines


def plot(cr, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
    panels = FP_UNITS + ["noise", "ray_box", "ray_tri"]
    fig, axes = plt.subplots(2, 4, figsize=(20, 9.5))
    colors = {"e5m10": "tab:blue", "e7m16": "tab:orange", "e8m23": "tab:green"}
    for ax, name in zip(axes.flat, panels):
        ks = sorted(k for k in cr if (k[0] == name or (name == "ray_tri" and k[0].startswith("ray_tri")))
                    and (has_ends(cr[k]) or k[0].startswith("ray_tri")))  # not the matched-clock tries
        stages_sorted = sorted({k[2] for k in ks})
        for k in ks:
            rs = sorted(cr[k], key=lambda r: r["period_ps"])
            x = [r["period_ps"] / 1000 for r in rs]
            y = [r["area_um2"] for r in rs]
            if name == "noise":
                c = plt.cm.viridis(k[2] / 7)
                label = f"Stages {k[2]}"
                ls = "-"
            else:
                c = colors.get(k[1], "k") if not k[0].startswith("ray_tri") else (
                    "tab:red" if k[0] == "ray_tri_robust" else "tab:purple")
                rank = stages_sorted.index(k[2]) if k[2] in stages_sorted else 0
                ls = ["-", "--", ":", "-."][min(rank, 3)]
                label = (f"{k[0].replace('ray_tri_', '')} " if k[0].startswith("ray_tri") else "") + f"{k[1]} s{k[2]}"
            ax.plot(x, y, marker="o", ms=3.5, ls=ls, color=c, label=label)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.xaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_title(name + (" (robust, MT)" if name == "ray_tri" else ""))
        ax.set_xlabel("achieved clock period (ns, STA)")
        ax.set_ylabel("area (um², osu018)")
        ax.grid(True, which="both", alpha=0.3)
        if ks:
            ax.legend(fontsize=6.5, ncol=2)
    fig.suptitle("Area-delay curves in the osu018 flow (abc map -D / buffer / upsize / dnsize at each target; "
                 "a point per target clock). synth/cell/run.py; synth/cell/tables.py", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=RES)
    args = ap.parse_args()
    rows = load()
    cr, gr, nf = cell_rows(rows), generic_rows(rows), nf_rows(rows)
    fo4 = next((r["fo4_ps"] for r in rows if r.get("fo4_ps")), None)
    built = sorted({r.get("built_from", "") for r in rows if r.get("built_from")})
    hashes = sorted({(r["unit"], r["rtl_hash"]) for r in rows if r.get("rtl_hash")})
    md = ["# Cost in the osu018 standard-cell flow (issue 13 §4, §5)", "",
          "Generated by `/usr/bin/python3 synth/cell/tables.py` from the JSON Lines next to this file, which",
          "`/usr/bin/python3 synth/cell/run.py -j 2` made (resumable; every row carries its `command`).",
          f"Library osu018 (`osu018_stdcells.lib`, typical corner, no wire-load model: before placement), "
          f"FO4 = {fo4} ps measured by STA; Yosys 0.23, ABC (Debian berkeley-abc), OpenSTA 2.0.17. "
          "Each unit sits in the register harness (every input from a DFFPOSX1, every output into one), so a "
          "clock covers input-to-register and register-to-output paths; area is the unit's own (harness excluded).",
          "", "Built from: " + "; ".join(built) if built else "", "",
          "How a curve is made: `--clock 200ps,1000000ps` gives the two ends — every target below a unit's "
          "minimum delay maps to the same netlist (checked: fp_add e8m23 Stages 0 at 2, 4 and 8 ns gives 59,078 um2 "
          "and 12.47 ns each time), so 200 ps is \"as fast as ABC can\", and 1 µs is the area-oriented mapping; "
          "a second run maps at P0 + {0.25, 0.5, 0.75} (P1 − P0) between the achieved periods of the two ends. "
          "\"fastest\" = the row with the shortest achieved period (= STA Fmax), \"smallest\" = the row with the least "
          "area. † = ABC died on one target and the driver replaced it (the row's `driver_note` says which).",
          ""]
    md += ["## FP units", ""] + fp_table(cr, gr, FP_UNITS, FORMATS, None)
    md += ["", "NAND2-eq: the generic flow (`rayunits synth U --format F --stages S --generic-only`), a labelled "
           "estimate of this project's own weights, for comparison only."]
    md += ["", "## Noise unit by pipeline depth (Table 4.1 analogue)", ""] + noise_table(cr, gr)
    md += ["", "## The truncated noise unit (noise_trunc, issue 15) by pipeline depth", "",
           "Same columns (docs/NOISE.md, \"The truncated datapath\"); its area relative to ru_noise at equal Stages:", ""]
    md += noise_table(cr, gr, "noise_trunc")
    ratios = []
    for st in range(0, 8):
        k0, k1 = ("noise", None, st), ("noise_trunc", None, st)
        if k0 in cr and k1 in cr:
            ratios.append(f"Stages {st}: smallest {smallest(cr[k1])['area_um2'] / smallest(cr[k0])['area_um2']:.3f}, "
                          f"fastest {fastest(cr[k1])['area_um2'] / fastest(cr[k0])['area_um2']:.3f} "
                          f"({fastest(cr[k1])['fmax_mhz']:.1f} vs {fastest(cr[k0])['fmax_mhz']:.1f} MHz)")
    if ratios:
        md += ["", "noise_trunc / noise area at equal Stages: " + "; ".join(ratios) + "."]
    md += ["", f"Kensler's FO4 per cycle is an estimate: his 65 nm process's FO4 is not given; the rule of thumb FO4 ≈ "
           f"360 ps × drawn gate length in µm (typical corner; 500 ps/µm worst case) gives {FO4_65_PS:.1f} ps "
           f"({FO4_65_WORST_PS:.1f} ps), so his 1 GHz is ≈ {1000 / FO4_65_PS:.0f} FO4 ({1000 / FO4_65_WORST_PS:.0f}) and his "
           f"combinational 344 MHz ≈ {1e6 / 344 / FO4_65_PS:.0f} FO4 ({1e6 / 344 / FO4_65_WORST_PS:.0f}). The same rule gives "
           f"65 ps for 180 nm against the {fo4} ps STA measures for osu018."]
    mt, summary = match_tables(rows)
    md += ["", "## Matched clock: noise vs fp_add + fp_mul vs fp_dot3 (e8m23)", "",
           "Each unit at the smallest Stages with a mapping whose STA period is within the clock T (each Stages "
           "tried is mapped at T and at T − 500 ps, because ABC's target does not include the harness registers' "
           "clock-to-Q and setup, ≈ 0.4 ns; bisection between the Stages the fastest mappings bracket, which "
           "assumes the reachable period falls with Stages). Area = the smaller of the two mappings that meets T."] + mt
    rl, ratio = ray_table(cr)
    md += ["", "## Ray units", ""] + rl + ["", "Area ratios (robust / Möller–Trumbore; variants / their base circuit):"] + ratio
    md += ["", "## Register placement: depth estimates vs measured delays", "",
           "Each configuration mapped as fast as ABC can (200 ps target) twice: with the RTL's own depth "
           "estimates (`rayunits synth U --format F --stages S --flow osu018 --clock 200ps --stage-periods`) and "
           "with the registers placed by delays measured in osu018 (`... --placement delay`: the unit with every "
           "cut registered is mapped and timed first, each segment's logic delay becomes its weight in the same "
           "RTL placement function, ru_pipe_pkg::cut_mask). Stage periods: OpenSTA's period of each pipeline "
           "stage (its worst register), stage 1 first; the worst is the unit's clock.", ""] + placement_table(rows)
    md += ["", "## Every mapping (area-delay curves)", "", "![area vs achieved period](area_delay.png)", ""] + curve_table(cr)
    tl, total = time_table(rows)
    md += ["", "## Speed of the flow (benchmark: 2 cores, two runs at once under `nice`)", "",
           "From each row's `step_seconds` (synth + dfflibmap once per run, ABC and STA per target) and the "
           "driver's wall time per run (`driver_seconds`). Load average ≈ 2 during these runs (only these two); "
           "a first pass of the same 47 `ends` runs at load 5–9 (other jobs on the machine) took 38.2 min "
           "instead of 10.0 (median 3.8× longer per run).", ""] + tl
    md += ["", f"Sum of the wall times above: {total / 60:.1f} min. A run = one `rayunits synth` (one Yosys `synth` + "
           "`dfflibmap`, then one ABC mapping and one STA per target clock)."]
    md += ["", "## Script choice", "",
           "Yosys's own `abc -liberty -D T` runs ABC's `&nf` mapper, which gave the same netlist for every -D "
           "(synth/README.md, \"The cell-library flow\"), so the flow maps with the classic `strash; ifraig; scorr; "
           "dc2; strash; dch -f; map -D T; topo; buffer -p; upsize -D T; dnsize -D T`. Its cost against `&nf`, "
           "measured before `&nf` was dropped from the flow (commit 331a20c, where `--flow osu018` without "
           "`--clock` still ran `&nf`; same machine, load 5–9):", "",
           "| unit | `&nf`: area um2, clock ns | map flow, 1 µs target: area, clock | map flow, 200 ps target: area, clock |",
           "|---|---|---|---|",
           "| fp_add e8m23 Stages 0 | 53,329, 19.00 | 46,121, 17.44 | 59,078, 12.47 |",
           "| fp_dot3 e8m23 Stages 0 | 565,797, 55.38 | 554,069, 51.01 | 616,317, 37.07 |",
           "",
           "So the timing-driven script costs nothing against `&nf`: at an area-oriented target it is smaller "
           "and faster, at a tight one it buys 25–35 % more speed for 10–30 % more area, and ABC takes about "
           "as long (fp_add e8m23: 1.8 s for `&nf`, 1.5–2.0 s per map-flow target of 12–50 ns in the same minute; "
           "fp_dot3 e8m23: 68 s for `&nf`, 63–66 s per target). `topo` (added after 331a20c) fixed ABC's \"node N has no fanout\" abort in `buffer`/"
           "`upsize`, which hit 6 of 52 `ends` runs here (fp_add e5m10 Stages 5, fp_dot3 e5m10 Stages 0 and 10, "
           "fp_dot3 e7m16 Stages 0, noise Stages 1 at 200 ps, noise Stages 4 at 1 µs); it changed no result of the "
           "runs that had succeeded without it (the 92 rows of those 46 runs compared equal in area and period)."]
    fails = sorted(glob.glob(os.path.join(RES, "*.failed.json")))
    if fails:
        md += ["", "## Runs that failed", ""]
        for p in fails:
            with open(p) as f:
                e = json.loads(f.read())
            md.append(f"- `{e['command']}`: exit {e['exit_status']} after {e['seconds']} s: {' / '.join(e['stderr_tail'])[-300:]}")
    md += ["", "RTL hashes of the rows: " + ", ".join(f"{u} {h}" for u, h in hashes), ""]
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "tables.md"), "w") as f:
        f.write("\n".join(md))
    plot(cr, os.path.join(args.out, "area_delay.png"))
    with open(os.path.join(args.out, "summary.json"), "w") as f:
        json.dump({str(k): v for k, v in summary.items()}, f, indent=1, sort_keys=True)
    print("wrote", os.path.join(args.out, "tables.md"), "and area_delay.png")


if __name__ == "__main__":
    main()
