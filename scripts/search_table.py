#!/usr/bin/env python3
"""Markdown table of a formulation search (rayunits search tri --out DIR): the reported designs
and the hand designs (references) from DIR/front.csv, and with --plot FILE.png the Pareto front
of everything evaluated (DIR/pareto_all.csv) as area against mean relative error.
With --md FILE the Markdown goes to FILE instead of standard output (`rayunits report`'s
search section uses that).

Designs synthesized in full (DIR/synth_*.jsonl, rows of `rayunits synth ... --flow osu018
--json`, e.g. `rayunits synth dp_ray_tri_robust --format e7m16 --stages 53 --flow osu018
--clock 4000ps --json DIR/synth_dp_ray_tri_robust_s53.jsonl`, and the synthesis row of every
DIR/gen_*/datasheet.json that `rayunits gen ... --flow osu018 --out DIR/gen_NAME` wrote) get a
second table: the cost
model's area and clock beside the synthesized ones. A row's unit is matched to a design by the
genome its module names in its "// origin:" line (written by `rayunits dp emit` and by the
search): rtl/ru_<unit>.sv for the built-in dp units (the hand designs), DIR/rtl/ru_<unit>.sv for
the search's run-time ones.

A directory of `rayunits search box` (front.json context kind "box") gets the ray-box table
instead: reported and hand designs with area, latency, the model's clock period, the errors of
t_enter / t_exit, false misses and false hits; --plot draws all 16 designs (DIR/all.csv).

With --genomes G1,G2,... the table is of the named designs instead, reported or not: their rows
in DIR/evaluations.jsonl (the evaluations of the search's context, that of its reported designs)
or, for the hand designs, DIR/front.json; the model's clock at most the search's (--clock); RTL
"pass"/"FAIL" where the design was reported and verified. A name the search did not evaluate is
an error (one line, exit 2).

With --pairs (a search with --mixed) every evaluated mixed design beside its unmixed twin (the same
genome without -wN) and its w2 sibling: area and mean-error ratios, one line each, then the range
of each ratio per w (the README's mixed-precision figures).

usage: scripts/search_table.py DIR [--plot FILE.png] [--md FILE] [--genomes G1,G2,...] [--pairs]
"""
import csv
import math
import glob
import json
import os
import re
import sys

REPO = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
REPO_RTL = os.path.join(REPO, "rtl")


def registry_tops():
    """unit name -> its RTL top module, from the registry's JSON (model/data/registry.json)."""
    with open(os.path.join(REPO, "model", "data", "registry.json")) as f:
        return {u["name"]: u["top"] for u in json.load(f)["units"]}


def unit_genome(d, unit, tops):
    """(genome, built-in?) from the origin line of the unit's module, (None, False) if none. A
    built-in unit's module is its registry top; a run-time unit of the search is ru_<unit> (the
    module name `rayunits search tri` gives it)."""
    for rtl, builtin in ((REPO_RTL, True), (os.path.join(d, "rtl"), False)):
        if builtin and unit not in tops:
            continue
        path = os.path.join(rtl, (tops[unit] if builtin else "ru_" + unit) + ".sv")
        if os.path.exists(path):
            for line in open(path):
                m = re.match(r"// origin: .*genome (\S+)", line)
                if m:
                    return m.group(1), builtin
            return None, builtin
    return None, False


def synth_table(d, rows, fitness):
    """Markdown lines: cost model vs full synthesis for every synthesized design of DIR."""
    out = []
    tops = registry_tops()
    found = []  # (file name, synthesis row)
    for path in sorted(glob.glob(os.path.join(d, "synth_*.jsonl"))):
        found += [(os.path.basename(path), json.loads(line)) for line in open(path) if line.strip()]
    for path in sorted(glob.glob(os.path.join(d, "gen_*", "datasheet.json"))):
        ds = json.load(open(path))
        if ds.get("synthesis", {}).get("area_um2") is not None:
            found.append((os.path.relpath(path, d), ds["synthesis"]))
    for path, s in found:
        unit = s["unit"]
        genome, builtin = unit_genome(d, unit, tops)
        match = [r for r in rows if r["genome"] == genome or
                 (genome is None and "dp_" + r["genome"].replace("-", "_") == unit)]  # modules emitted before origin lines
        match.sort(key=lambda r: not (builtin and r["role"].startswith("reference:")))  # a hand design's own row first
        if not match:
            out.append(f"| `{unit}` | (no design of this search) | | | | | | |")
            continue
        r = match[0]
        model_area = float(r["area_um2"])
        model_ps = fitness.get(r["genome"], {}).get("period_ps")
        err = 100.0 * (model_area - s["area_um2"]) / s["area_um2"]
        out.append(f"| `{r['genome']}` ({r['role'].replace('reference:', 'hand: ')}) | {s['stages']} "
                   f"| {model_area:,.0f} | {s['area_um2']:,.0f} | {err:+.1f} % "
                   f"| {'—' if model_ps is None else f'{1e6 / model_ps:.0f} MHz'} "
                   f"| {s['fmax_mhz']:.0f} MHz ({s['slack_ps']:+.0f} ps at {s['target_clock_ps']:.0f} ps) "
                   f"| `{path}` |")
    if not out:
        return []
    return ["", "Cost model against full synthesis (osu018, Yosys + ABC + OpenSTA, before placement):", "",
            "| design | Stages | model area µm² (estimate) | synthesized µm² | model error | model clock "
            "| STA Fmax | row |", "|---|---:|---:|---:|---:|---:|---:|---|"] + out


def model_mhz(target_ps, period_ps):
    """The cost model's clock of a design in MHz, floored: its slowest unit's, at most the search's."""
    return math.floor(1e6 / max(target_ps, period_ps) + 1e-9)


def write_text(text, argv):
    """The Markdown to --md FILE, or to standard output."""
    if "--md" in argv:
        with open(argv[argv.index("--md") + 1], "w") as fo:
            fo.write(text)
    else:
        sys.stdout.write(text)


def new_plot():
    """A figure and axes for the front plots (matplotlib, no display)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt.subplots(figsize=(7, 4.5))


def save_plot(fig, out):
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"\nwrote {out}", file=sys.stderr)


def box_main(d, argv):
    """The table (and plot) of a `rayunits search box` directory."""
    rows = list(csv.DictReader(open(os.path.join(d, "front.csv"))))
    lines = ["| design | role | area µm² (estimate) | latency | period ps (model) | mean rel. err. t "
             "| max rel. err. t | false misses | false hits | RTL |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|---|"]
    for r in rows:
        role = r["role"].replace("reference:", "hand: ")
        lines.append(f"| `{r['design']}` | {role} | {float(r['area_um2']):,.0f} | {r['latency']} "
                     f"| {float(r['period_ps']):,.0f} | {float(r['mean_rel']):.3g} | {float(r['max_rel']):.3g} "
                     f"| {r['false_misses']} | {r['false_hits']} | {r.get('rtl', '') or ''} |")
    write_text("\n".join(lines) + "\n", argv)
    if "--plot" in argv:
        out = argv[argv.index("--plot") + 1]
        allrows = list(csv.DictReader(open(os.path.join(d, "all.csv"))))
        fig, ax = new_plot()
        x = [float(r["area_um2"]) / 1e6 for r in allrows]
        y = [float(r["mean_rel"]) for r in allrows]
        c = [int(r["false_misses"]) for r in allrows]
        sc = ax.scatter(x, y, c=c, cmap="viridis", s=30)
        fig.colorbar(sc, label="false misses")
        for r in allrows:  # the chain tree (m1) has the same errors a little right of its m0: one label
            if r["design"].endswith("-m0"):
                ax.annotate(r["design"].replace("box-", "").replace("-m0", ""),
                            (float(r["area_um2"]) / 1e6, float(r["mean_rel"])), fontsize=8, xytext=(5, 3),
                            textcoords="offset points")
        ax.set_yscale("log")
        ax.set_xlabel("area, mm² (cost-model estimate, osu018)")
        ax.set_ylabel("mean relative error of t_enter, t_exit (worse of the two)")
        ax.set_title(f"rayunits search box: {os.path.basename(os.path.normpath(d))} "
                     "(each point pair: min/max tree m0, m1)", fontsize=9)
        save_plot(fig, out)


def search_fitness(d):
    """(fitness by genome of the search's evaluations and hand designs, RTL status by reported
    genome, hand design names, front.json)."""
    rows = list(csv.DictReader(open(os.path.join(d, "front.csv"))))
    rtl = {r["genome"]: r.get("rtl", "") or "" for r in rows}
    front = json.load(open(os.path.join(d, "front.json")))
    recs = [json.loads(line) for line in open(os.path.join(d, "evaluations.jsonl")) if line.strip()]
    # the search's context: that of the reported designs' evaluations (a resumed search with a
    # changed cost model or workload evaluates again in a new context; older lines are stale)
    contexts = [r["context"] for r in recs if r["genome"] in rtl]
    if not contexts:
        sys.exit(f"search_table.py: {d}/evaluations.jsonl has none of the reported designs")
    ctx = max(set(contexts), key=contexts.count)
    fit = {r["genome"]: r["fitness"] for r in recs if r["context"] == ctx}
    hand = {e["genome"]: e["name"] for e in front.get("references", [])}
    fit.update({e["genome"]: e["fitness"] for e in front.get("references", [])})  # evaluated beside the search
    return fit, rtl, hand, front


def pairs_main(d, argv):
    """Mixed designs against their twins (--pairs)."""
    fit = search_fitness(d)[0]
    lines, ranges = [], {}
    for g in sorted(fit):
        m = re.match(r"(.*)-w([123])$", g)
        if not m or m.group(1) not in fit:
            continue
        base, w = fit[m.group(1)], int(m.group(2))
        ratios = {"area": fit[g]["area_um2"] / base["area_um2"], "err": base["mean_rel"] / fit[g]["mean_rel"]}
        sib = fit.get(m.group(1) + "-w2")
        if w == 3 and sib:
            ratios["area_vs_w2"] = fit[g]["area_um2"] / sib["area_um2"]
            ratios["err_vs_w2"] = sib["mean_rel"] / fit[g]["mean_rel"]
        lines.append(f"{g}: " + ", ".join(f"{k} {v:.3g}" for k, v in ratios.items()))
        for k, v in ratios.items():
            ranges.setdefault((w, k), []).append(v)
    lines.append("ranges (area: mixed/twin, err: twin mean error/mixed; *_vs_w2: against the w2 sibling):")
    for (w, k), v in sorted(ranges.items()):
        lines.append(f"w{w} {k}: {min(v):.3g} .. {max(v):.3g} over {len(v)}")
    write_text("\n".join(lines) + "\n", argv)


def genomes_main(d, names, argv):
    """The table of named designs from DIR/evaluations.jsonl (--genomes)."""
    fit, rtl, hand, front = search_fitness(d)
    target_ps = front["context"]["period_ps"]
    missing = [n for n in names if n not in fit]
    if missing:
        print(f"search_table.py: not evaluated in {d}: {', '.join(missing)} "
              f"({len(fit)} designs were; names as in front.csv)", file=sys.stderr)
        sys.exit(2)
    lines = ["| design | area µm² (estimate) | clock MHz (estimate) | latency | mean rel. err. | max rel. err. "
             "| leaks | false misses | double hits | RTL |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for n in names:
        f = fit[n]
        mhz = model_mhz(target_ps, f["period_ps"])
        lines.append(f"| `{n}`{f' (hand: {hand[n]})' if n in hand else ''} | {f['area_um2']:,.0f} | {mhz} | {f['latency']} | {f['mean_rel']:.3g} "
                     f"| {f['max_rel']:.3g} | {f['leaks']} | {f['false_misses']} | {f['double_hits']} "
                     f"| {rtl.get(n, '')} |")
    write_text("\n".join(lines) + "\n", argv)


def main(argv):
    if len(argv) < 2 or argv[1].startswith("-"):
        sys.exit("usage: search_table.py DIR [--plot FILE.png]")
    d = argv[1]
    fj = os.path.join(d, "front.json")
    if os.path.exists(fj) and json.load(open(fj)).get("context", {}).get("kind") == "box":
        return box_main(d, argv)
    path = os.path.join(d, "front.csv")
    if not os.path.exists(path):
        sys.exit(f"search_table.py: no {path} (run rayunits search tri --out {d} first)")
    if "--pairs" in argv:
        return pairs_main(d, argv)
    if "--genomes" in argv:
        i = argv.index("--genomes")
        if i + 1 >= len(argv) or not argv[i + 1].strip(","):
            sys.exit("search_table.py: --genomes needs a comma-separated list of design names")
        return genomes_main(d, [n for n in argv[i + 1].split(",") if n], argv)
    rows = list(csv.DictReader(open(path)))
    fitness, clock_mhz = {}, None
    fj = os.path.join(d, "front.json")
    if os.path.exists(fj):
        f = json.load(open(fj))
        for e in f.get("front", []) + f.get("references", []):
            fitness[e["genome"]] = e.get("fitness", {})
        # searches with the clock period as an objective (--fused, --mixed): the cost model's clock
        if any(str(o).startswith("period_ps") for o in f.get("objectives", [])):
            target_ps = f["context"]["period_ps"]
            clock_mhz = 1e6 / target_ps
    lines = []
    emit = lines.append  # written to --md FILE or standard output below
    clock_head = " clock MHz (estimate) |" if clock_mhz else ""
    emit("| design | role | area µm² (estimate) | latency | mean rel. err. | max rel. err. "
          "| leaks | false misses | double hits | false hits | RTL |" + clock_head)
    emit("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|" + ("---:|" if clock_mhz else ""))
    for r in rows:
        role = r["role"].replace("reference:", "hand: ")
        clock = ""
        if clock_mhz:
            per = fitness.get(r["genome"], {}).get("period_ps")
            clock = f" {model_mhz(target_ps, per)} |" if per else " |"
        emit(f"| `{r['genome']}` | {role} | {float(r['area_um2']):,.0f} | {r['latency']} "
              f"| {float(r['mean_rel']):.3g} | {float(r['max_rel']):.3g} | {r['leaks']} | {r['false_misses']} "
              f"| {r['double_hits']} | {r['false_hits']} | {r.get('rtl', '') or ''} |" + clock)
    lines += synth_table(d, rows, fitness)
    write_text("\n".join(lines) + "\n", argv)
    if "--plot" in argv:
        out = argv[argv.index("--plot") + 1]
        allrows = list(csv.DictReader(open(os.path.join(d, "pareto_all.csv"))))
        fig, ax = new_plot()
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
        save_plot(fig, out)


if __name__ == "__main__":
    main(sys.argv)
