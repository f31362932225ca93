#!/usr/bin/python3
"""Summarize one qflow run (synth/pnr/run_pnr.sh): areas, timing, checks, picture.

usage: pnr_report.py --work DIR --top TOP --out DIR --meta META.json [--no-png]

Reads (all optional except the LEF; a missing file leaves its fields null):
  DIR/layout/TOP.def            placed (and, after route, routed) DEF
  DIR/source/TOP_mapped.blif    qflow's yosys+abc netlist (before blifFanout)
  DIR/synthesis/TOP.blif        the netlist handed to placement (after blifFanout)
  DIR/keep/*.log, *.out         per-step logs kept by run_pnr.sh
Writes OUT/summary.json (one object) and OUT/layout.png.

Areas: cell area = sum of the LEF SIZE (width x height) of every placed component
except filler (FILL) cells; core = the bounding box of the cell rows (every
component, fill included: addspacers.tcl fills each row to the same length); die =
the DEF DIEAREA (core plus the pin/power ring margin). Utilization = cell / core.
"""
import argparse
import json
import os
import re
import sys

TECH = '/usr/share/qflow/tech/osu018'
FILL = re.compile(r'^FILL')


def read_lef_sizes(path):
    sizes, cur = {}, None
    with open(path) as f:
        for line in f:
            s = line.split()
            if not s:
                continue
            if s[0] == 'MACRO':
                cur = s[1]
            elif s[0] == 'SIZE' and cur:
                sizes[cur] = (float(s[1]), float(s[3]))
            elif s[0] == 'END' and len(s) > 1 and s[1] == cur:
                cur = None
    return sizes


def read_def(path, want_routes):
    d = {'units': 100.0, 'die': None, 'comps': [], 'wires': {}, 'pins': []}
    sect = None
    layer = None
    last = None
    with open(path) as f:
        for line in f:
            s = line.split()
            if not s:
                continue
            k = s[0]
            if k == 'UNITS':
                d['units'] = float(s[3])
            elif k == 'DIEAREA':
                n = [float(x) for x in re.findall(r'-?\d+(?:\.\d+)?', line)]
                d['die'] = n[:4]
            elif k in ('COMPONENTS', 'NETS', 'PINS', 'SPECIALNETS'):
                sect = k
            elif k == 'END' and len(s) > 1:
                sect = None
            elif sect == 'COMPONENTS' and k == '-':
                m = re.search(r'PLACED\s*\(\s*(-?\d+)\s+(-?\d+)\s*\)\s*(\w+)', line)
                if m:
                    d['comps'].append((s[1], s[2], float(m.group(1)), float(m.group(2))))
            elif sect == 'PINS' and 'PLACED' in line:
                m = re.search(r'PLACED\s*\(\s*(-?\d+)\s+(-?\d+)', line)
                if m:
                    d['pins'].append((float(m.group(1)), float(m.group(2))))
            elif want_routes and sect == 'NETS':
                if k in ('+', 'NEW'):
                    i = 1
                    if k == '+':
                        if len(s) < 2 or s[1] != 'ROUTED':
                            continue
                        i = 2
                    if i >= len(s):
                        continue
                    layer = s[i]
                    pts = re.findall(r'\(\s*(\S+)\s+(\S+)\s*(?:\S+\s*)?\)', line)
                    last = None
                    seg = d['wires'].setdefault(layer, [])
                    for xs, ys in pts:
                        x = last[0] if xs == '*' else float(xs)
                        y = last[1] if ys == '*' else float(ys)
                        if last is not None and (x, y) != last:
                            seg.append((last, (x, y)))
                        last = (x, y)
    return d


def count_blif(path):
    counts = {}
    if not os.path.exists(path):
        return None
    with open(path) as f:
        for line in f:
            if line.startswith(('.subckt', '.gate')):
                c = line.split()[1]
                counts[c] = counts.get(c, 0) + 1
    return counts


def area_of(counts, sizes):
    if counts is None:
        return None
    return round(sum(n * sizes[c][0] * sizes[c][1] for c, n in counts.items() if c in sizes), 2)


def read(path):
    try:
        with open(path, errors='replace') as f:
            return f.read()
    except OSError:
        return None


def last_float(pattern, text, group=1):
    if not text:
        return None
    m = re.findall(pattern, text)
    if not m:
        return None
    v = m[-1] if isinstance(m[-1], str) else m[-1][group - 1]
    return float(v)


def parse_opensta(text):
    """OpenSTA 'report_checks -path_delay max -group_count 1' per group, plus wns/tns."""
    if not text:
        return None
    res = {}
    for block in re.split(r'\n(?=Startpoint: )', text):
        g = re.search(r'Path Group: (\S+)', block)
        sl = re.search(r'(-?\d+\.\d+)\s+slack \((MET|VIOLATED)\)', block)
        if g and sl and re.search(r'Path Type: max', block):
            sp = re.search(r'Startpoint: (\S+)', block).group(1)
            ep = re.search(r'Endpoint: (\S+)', block).group(1)
            arr = re.search(r'(-?\d+\.\d+)\s+data arrival time', block)
            req = re.search(r'(-?\d+\.\d+)\s+data required time', block)
            res[g.group(1)] = {'slack_ns': float(sl.group(1)), 'startpoint': sp, 'endpoint': ep,
                               'arrival_ns': float(arr.group(1)) if arr else None,
                               'required_ns': float(req.group(1)) if req else None}
    wns = re.search(r'^wns (-?\d+\.\d+)', text, re.M)
    tns = re.search(r'^tns (-?\d+\.\d+)', text, re.M)
    out = {'groups': res, 'wns_ns': float(wns.group(1)) if wns else None,
           'tns_ns': float(tns.group(1)) if tns else None}
    ann = re.search(r'spef_fix: (.*)', text)
    if ann:
        out['spef_fix'] = ann.group(1).strip()
    return out


def parse_vesta(text):
    """Vesta's worst register-to-register path and worst input-to-register path."""
    if not text:
        return None
    out = {}
    # The first "Top 20 maximum delay paths" block is register to register.
    parts = text.split('Top 20 maximum delay paths:')
    if len(parts) > 1:
        m = re.search(r'Path (\S+) to (\S+) delay (\S+) ps\s+Slack = (\S+) ps', parts[1])
        if m:
            out['reg2reg_delay_ps'] = float(m.group(3))
            out['reg2reg_slack_ps'] = float(m.group(4))
            out['reg2reg_path'] = '%s -> %s' % (m.group(1), m.group(2))
        m = re.search(r'Computed maximum clock frequency \(zero margin\) = (\S+) MHz', parts[1])
        if m:
            out['fmax_mhz_zero_margin'] = float(m.group(1))
        if 'reg2reg_slack_ps' in out:
            out['meets_timing'] = out['reg2reg_slack_ps'] >= 0
    if len(parts) > 2:
        m = re.search(r'Path input pin (\S+) to (\S+) delay (\S+) ps', parts[2])
        if m:
            out['in2reg_delay_ps'] = float(m.group(3))
            out['in2reg_path'] = '%s -> %s' % (m.group(1), m.group(2))
    m = re.findall(r'Computed maximum clock frequency \(zero margin\) = (\S+) MHz', text)
    if m:
        out['fmax_mhz_zero_margin'] = float(m[0])
    return out or None


def plot(d, sizes, out_png, title, note):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection, PatchCollection
    from matplotlib.patches import Rectangle

    u = d['units']
    x0, y0, x1, y1 = [v / u for v in d['die']]
    w, h = x1 - x0, y1 - y0
    routed = sum(len(v) for v in d['wires'].values()) > 0
    ncol = 2 if routed else 1
    fig_w = 7.0 * ncol
    fig, axes = plt.subplots(1, ncol, figsize=(fig_w, 7.0 * h / w + 1.2), squeeze=False)
    classes = [('flip-flop', '#d62728', re.compile(r'^DFF|^LATCH')),
               ('buffer / inverter', '#ff7f0e', re.compile(r'^(BUF|CLKBUF|INV)')),
               ('logic', '#1f77b4', re.compile(r'.')),
               ]
    groups = {c[0]: [] for c in classes}
    fills = []
    for name, macro, x, y in d['comps']:
        sz = sizes.get(macro)
        if not sz:
            continue
        r = Rectangle((x / u, y / u), sz[0], sz[1])
        if FILL.match(macro):
            fills.append(r)
            continue
        for cname, _, rx in classes:
            if rx.match(macro):
                groups[cname].append(r)
                break
    ax = axes[0][0]
    ax.add_collection(PatchCollection(fills, facecolor='#eeeeee', edgecolor='none'))
    for cname, col, _ in classes:
        ax.add_collection(PatchCollection(groups[cname], facecolor=col, edgecolor='white',
                                          linewidth=0.05, label=cname))
    handles = [Rectangle((0, 0), 1, 1, color=col) for _, col, _ in classes] + \
              [Rectangle((0, 0), 1, 1, color='#eeeeee')]
    labels = ['%s (%d)' % (c, len(groups[c])) for c, _, _ in classes] + ['fill (%d)' % len(fills)]
    ax.legend(handles, labels, loc='upper center', bbox_to_anchor=(0.5, -0.02), ncol=2, fontsize=8,
              frameon=False)
    ax.set_title('placement (cells)', fontsize=10)
    if routed:
        ax2 = axes[0][1]
        colors = {'metal1': '#1f77b4', 'metal2': '#d62728', 'metal3': '#2ca02c',
                  'metal4': '#9467bd', 'metal5': '#ff7f0e', 'metal6': '#8c564b'}
        hs, ls = [], []
        for layer in sorted(d['wires']):
            segs = [((a[0] / u, a[1] / u), (b[0] / u, b[1] / u)) for a, b in d['wires'][layer]]
            col = colors.get(layer, 'black')
            ax2.add_collection(LineCollection(segs, colors=col, linewidths=0.3, alpha=1.0))
            hs.append(Rectangle((0, 0), 1, 1, color=col))
            ls.append('%s (%d)' % (layer, len(segs)))
        ax2.legend(hs, ls, loc='upper center', bbox_to_anchor=(0.5, -0.02), ncol=3, fontsize=8,
                   frameon=False)
        ax2.set_title('routing (signal wires by layer)', fontsize=10)
    for a in axes[0]:
        a.add_patch(Rectangle((x0, y0), w, h, fill=False, edgecolor='black', linewidth=0.6))
        a.set_xlim(x0 - 0.01 * w, x1 + 0.01 * w)
        a.set_ylim(y0 - 0.01 * h, y1 + 0.01 * h)
        a.set_aspect('equal')
        a.set_ylabel('µm', fontsize=8)
        a.tick_params(labelsize=7)
    fig.suptitle(title + '\n' + note, fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)
    plt.close(fig)
    try:  # a 128-colour palette keeps the file small (the repository stays lean)
        from PIL import Image
        Image.open(out_png).convert('RGB').quantize(colors=128, method=Image.Quantize.MEDIANCUT).save(out_png, optimize=True)
    except ImportError:
        pass


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--work', required=True)
    ap.add_argument('--top', required=True)
    ap.add_argument('--out', required=True)
    ap.add_argument('--meta', required=True)
    ap.add_argument('--no-png', action='store_true')
    a = ap.parse_args()
    W, T = a.work, a.top
    keep = os.path.join(W, 'keep')
    meta = json.load(open(a.meta))
    sizes = read_lef_sizes(os.path.join(TECH, 'osu018_stdcells.lef'))

    res = dict(meta)
    deff = os.path.join(W, 'layout', T + '.def')
    d = None
    if os.path.exists(deff):
        d = read_def(deff, want_routes=not a.no_png)
        u = d['units']
        placed = {}
        for _, macro, _, _ in d['comps']:
            placed[macro] = placed.get(macro, 0) + 1
        cells = {c: n for c, n in placed.items() if not FILL.match(c)}
        cell_area = area_of(cells, sizes)
        xs = [x / u for _, _, x, _ in d['comps']]
        ys = [y / u for _, _, _, y in d['comps']]
        xe = [x / u + sizes[m][0] for _, m, x, _ in d['comps'] if m in sizes]
        ye = [y / u + sizes[m][1] for _, m, _, y in d['comps'] if m in sizes]
        core_w, core_h = max(xe) - min(xs), max(ye) - min(ys)
        core = core_w * core_h
        x0, y0, x1, y1 = [v / u for v in d['die']]
        die = (x1 - x0) * (y1 - y0)
        rows = len(set(ys))
        res.update({
            'cells_placed': sum(cells.values()),
            'cells_by_type': dict(sorted(cells.items(), key=lambda kv: -kv[1])),
            'fill_cells': sum(n for c, n in placed.items() if FILL.match(c)),
            'cell_area_um2': cell_area,
            'flops': sum(n for c, n in cells.items() if c.startswith('DFF')),
            'rows': rows,
            'core_w_um': round(core_w, 2), 'core_h_um': round(core_h, 2),
            'core_area_um2': round(core, 2),
            'die_w_um': round(x1 - x0, 2), 'die_h_um': round(y1 - y0, 2),
            'die_area_um2': round(die, 2),
            'utilization_core': round(cell_area / core, 4),
            'utilization_die': round(cell_area / die, 4),
            'ratio_die_to_cell_area': round(die / cell_area, 3),
            'ratio_core_to_cell_area': round(core / cell_area, 3),
        })
    mapped = count_blif(os.path.join(W, 'source', T + '_mapped.blif'))
    fan = count_blif(os.path.join(W, 'synthesis', T + '.blif'))
    res['abc_mapped_cells'] = sum(mapped.values()) if mapped else None
    res['abc_mapped_cell_area_um2'] = area_of(mapped, sizes)
    res['prefanout_note'] = 'abc_mapped_* = qflow yosys/abc netlist before blifFanout buffering/resizing'
    res['placed_netlist_cells'] = sum(fan.values()) if fan else None
    res['placed_netlist_cell_area_um2'] = area_of(fan, sizes)

    route_log = read(os.path.join(keep, 'route.log')) or ''
    route_out = read(os.path.join(keep, 'route.out')) or ''
    rt = route_log + route_out
    if 'Final: No failed routes!' in rt:
        res['route_failed_nets'] = 0
    else:
        m = re.findall(r'Final: Failed net routes: (\d+)', rt)
        res['route_failed_nets'] = int(m[-1]) if m else None
    m = re.findall(r'Progress: Stage \d total routes completed: (\d+)', rt)
    res['route_segments_completed'] = int(m[-1]) if m else None
    if d and d['wires']:
        res['wire_length_um'] = {k: round(sum(abs(a[0] - b[0]) + abs(a[1] - b[1]) for a, b in v) / d['units'], 1)
                                 for k, v in sorted(d['wires'].items())}
        res['wire_length_total_um'] = round(sum(res['wire_length_um'].values()), 1)

    res['sta_pre_route_opensta'] = parse_opensta(read(os.path.join(keep, 'opensta_pre.txt')))
    res['sta_pre_route_vesta'] = parse_vesta(read(os.path.join(keep, 'sta.log')))
    res['sta_post_route_vesta'] = parse_vesta(read(os.path.join(keep, 'post_sta.log')))
    res['sta_post_route_opensta_sdf'] = parse_opensta(read(os.path.join(keep, 'opensta_sdf.txt')))
    post = parse_opensta(read(os.path.join(keep, 'opensta_spef.txt')))
    res['sta_post_route_opensta_spef'] = post
    clk = meta.get('clock_ns')
    if post and 'clk' in post['groups'] and clk:
        ws = post['groups']['clk']['slack_ns']
        res['post_route_worst_slack_ns'] = ws
        res['post_route_min_period_ns'] = round(clk - ws, 3)
        res['post_route_fmax_mhz'] = round(1000.0 / (clk - ws), 1)
        res['post_route_timing_source'] = 'OpenSTA 2.0.17, qrouter-extracted SPEF (rc2dly, repaired by fix_spef.py), ideal clock, in/out delay 0'
    pre = res['sta_pre_route_opensta']
    if pre and 'clk' in pre['groups'] and clk:
        ws = pre['groups']['clk']['slack_ns']
        res['pre_route_worst_slack_ns'] = ws
        res['pre_route_fmax_mhz'] = round(1000.0 / (clk - ws), 1)

    drc = read(os.path.join(keep, 'drc.log'))
    m = re.findall(r'^drc = (\d+)', drc or '', re.M)
    res['drc_count'] = int(m[-1]) if m else None
    lvs = read(os.path.join(keep, 'lvs.log')) or ''
    m = re.findall(r'Total errors = (\d+)', lvs)
    res['lvs_errors'] = int(m[-1]) if m else None
    res['lvs_result'] = 'match' if 'Netlists match' in lvs else ('mismatch' if lvs else None)
    mig = read(os.path.join(keep, 'migrate.log')) or ''
    res['extraction'] = 'magic extract + ext2spice done' if 'exttospice finished' in mig or \
        'exttospice finished' in (read(os.path.join(keep, 'migrate.out')) or '') else None
    gds = read(os.path.join(keep, 'gdsii.log')) or ''
    if gds:
        res['gds_cells_unavailable'] = len(set(re.findall(r'Cell (\S+) is unavailable', gds)))
        m = re.search(r'Cannot open .*', gds)
        res['gds_note'] = m.group(0) if m else None

    os.makedirs(a.out, exist_ok=True)
    if d and not a.no_png:
        note = ''
        if res.get('die_area_um2'):
            note = 'osu018 (0.18 µm), die %.0f × %.0f µm = %.0f µm², cells %.0f µm², core utilization %.1f%%' % (
                res['die_w_um'], res['die_h_um'], res['die_area_um2'], res['cell_area_um2'],
                100 * res['utilization_core'])
        title = '%s (%s) — qflow %s' % (T, meta.get('config', ''), 'placed and routed' if d['wires'] else 'placed')
        plot(d, sizes, os.path.join(a.out, 'layout.png'), title, note)
        res['picture'] = 'layout.png'
    with open(os.path.join(a.out, 'summary.json'), 'w') as f:
        json.dump(res, f, indent=2)
        f.write('\n')
    print(json.dumps({k: res.get(k) for k in ('cell_area_um2', 'core_area_um2', 'die_area_um2',
                                                'utilization_core', 'ratio_die_to_cell_area',
                                                'post_route_worst_slack_ns', 'post_route_fmax_mhz',
                                                'drc_count', 'route_failed_nets')}))


if __name__ == '__main__':
    sys.exit(main())
