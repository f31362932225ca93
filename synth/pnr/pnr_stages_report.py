#!/usr/bin/python3
"""The unit's place-and-route numbers from its stage blocks (synth/pnr/run_pnr_stages.sh).

usage: pnr_stages_report.py --out DIR --stages STAGES.json --generic GENERIC.json
                            --command CMD --equiv proved|skipped BLOCK...

Reads DIR/BLOCK/summary.json (pnr_report.py, one per block) and writes
  DIR/summary.json  one object: per block and for the unit (sums of cell, core and die area;
                    the unit's clock = its slowest stage), every step's status
  DIR/table.md      the same as a Markdown table
  DIR/layout.png    the blocks' layout pictures side by side
A block that has not finished a step leaves its fields null and the unit's sums null.

What the unit's numbers are: each block is placed and routed on its own die, so the sums are the
area of four separate layouts, not of one floorplan (no wires between the blocks, no shared
power ring); the stage period is the block's worst path from its inputs (the previous block's
flip-flop outputs, input delay 0) through its logic to its own flip-flops, i.e. without the
launching flip-flop's clock-to-Q and the wire between the blocks.
"""
import argparse
import json
import os
import sys


def get(d, *path):
    for p in path:
        if not isinstance(d, dict) or d.get(p) is None:
            return None
        d = d[p]
    return d


def total(rows, key):
    vals = [r.get(key) for r in rows]
    return None if any(v is None for v in vals) else round(sum(vals), 1)


def fmt(v, spec='{:,.0f}'):
    return '—' if v is None else spec.format(v)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--out', required=True)
    ap.add_argument('--stages', required=True)
    ap.add_argument('--generic', required=True)
    ap.add_argument('--command', required=True)
    ap.add_argument('--equiv', required=True, choices=['proved', 'skipped'])
    ap.add_argument('blocks', nargs='+')
    a = ap.parse_args()
    stages = {b['name']: b for b in json.load(open(a.stages))['blocks']}
    generic = json.load(open(a.generic)) if os.path.exists(a.generic) else None

    rows = []
    for b in a.blocks:
        p = os.path.join(a.out, b, 'summary.json')
        s = json.load(open(p)) if os.path.exists(p) else {}
        rows.append({
            'block': b,
            'word_level_cells': get(stages, b, 'cells'),
            'flip_flop_bits_before_mapping': get(stages, b, 'ff_bits'),
            'cells_placed': s.get('cells_placed'),
            'flops': s.get('flops'),
            'cell_area_um2': s.get('cell_area_um2'),
            'core_area_um2': s.get('core_area_um2'),
            'die_area_um2': s.get('die_area_um2'),
            'die_w_um': s.get('die_w_um'), 'die_h_um': s.get('die_h_um'),
            'utilization_core': s.get('utilization_core'),
            'ratio_die_to_cell_area': s.get('ratio_die_to_cell_area'),
            'route_failed_nets': s.get('route_failed_nets'),
            'wire_length_total_um': s.get('wire_length_total_um'),
            'pre_route_worst_slack_ns': s.get('pre_route_worst_slack_ns'),
            'post_route_worst_slack_ns': s.get('post_route_worst_slack_ns'),
            'post_route_min_period_ns': s.get('post_route_min_period_ns'),
            'post_route_fmax_mhz': s.get('post_route_fmax_mhz'),
            'critical_path': get(s, 'sta_post_route_opensta_spef', 'groups', 'clk'),
            'drc_count': s.get('drc_count'),
            'lvs_result': s.get('lvs_result'),
            'steps': {k: v.get('status') for k, v in (s.get('steps') or {}).items()},
            'failures': s.get('failures'),
            'wall_time_steps_s': s.get('wall_time_steps_s'),
            'clock_ns': s.get('clock_ns'),
            'initial_density': s.get('initial_density'),
            'graywolf_fast': s.get('graywolf_fast'),
            'command': s.get('command'),
        })

    periods = [r['post_route_min_period_ns'] for r in rows]
    worst = None if any(p is None for p in periods) else max(periods)
    cell = total(rows, 'cell_area_um2')
    die = total(rows, 'die_area_um2')
    core = total(rows, 'core_area_um2')
    unit = {
        'blocks': len(rows),
        'cells_placed': total(rows, 'cells_placed'),
        'flops': total(rows, 'flops'),
        'cell_area_um2': cell,
        'core_area_um2': core,
        'die_area_um2': die,
        'utilization_core': None if cell is None or not core else round(cell / core, 4),
        'ratio_die_to_cell_area': None if cell is None or not cell or die is None else round(die / cell, 3),
        'route_failed_nets': total(rows, 'route_failed_nets'),
        'wire_length_total_um': total(rows, 'wire_length_total_um'),
        'post_route_slowest_stage_ns': worst,
        'post_route_slowest_stage': None if worst is None else rows[periods.index(worst)]['block'],
        'post_route_fmax_mhz': None if worst is None else round(1000.0 / worst, 1),
        'fmax_note': 'slowest stage block: its worst input-to-flip-flop path, post-route (OpenSTA on the '
                     'repaired qrouter SPEF); excludes the launching flip-flop clock-to-Q (in the previous '
                     'block) and the wire between blocks',
        'area_note': 'sum over the stage blocks, each placed and routed on its own die: four layouts, '
                     'not one floorplan',
        'all_steps_ok': all(r['steps'] and all(v == 'ok' for k, v in r['steps'].items() if k != 'gdsii')
                            for r in rows),
        'wall_time_steps_s': total(rows, 'wall_time_steps_s'),
    }
    summary = {
        'command': a.command,
        'method': 'stage blocks cut by synth/pnr/split_stages.py (Yosys submod), each placed and routed '
                  'by synth/pnr/run_pnr.sh --source-v; equivalence of the blocks with the unit: ' + a.equiv,
        'equivalence': a.equiv,
        'unit': unit,
        'blocks': rows,
        'generic': generic,
    }
    with open(os.path.join(a.out, 'summary.json'), 'w') as f:
        json.dump(summary, f, indent=1)
        f.write('\n')

    lines = ['| block | cells | flip-flops | cell area µm² | die µm² | utilization | die/cell | failed nets '
             '| post-route slack | stage period | steps |',
             '|---|---|---|---|---|---|---|---|---|---|---|']
    for r in rows + [dict(unit, block='**unit (sum; slowest stage)**',
                          post_route_min_period_ns=worst, post_route_worst_slack_ns=None,
                          steps={'all': 'ok' if unit['all_steps_ok'] else 'not all ok'})]:
        st = r.get('steps') or {}
        bad = [k for k, v in st.items() if v != 'ok' and k != 'gdsii']
        lines.append('| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |'.format(
            r['block'], fmt(r.get('cells_placed')), fmt(r.get('flops')), fmt(r.get('cell_area_um2')),
            fmt(r.get('die_area_um2')), fmt(r.get('utilization_core'), '{:.1%}'),
            fmt(r.get('ratio_die_to_cell_area'), '{:.3f}'), fmt(r.get('route_failed_nets')),
            fmt(r.get('post_route_worst_slack_ns'), '{:+.3f} ns'),
            fmt(r.get('post_route_min_period_ns'), '{:.3f} ns'),
            'ok' if st and not bad else ('not finished (no summary.json)' if not st else 'not ok: ' + ', '.join(bad))))
    with open(os.path.join(a.out, 'table.md'), 'w') as f:
        f.write('\n'.join(lines) + '\n')
    print('\n'.join(lines))

    pngs = [(r['block'], os.path.join(a.out, r['block'], 'layout.png')) for r in rows]
    pngs = [(b, p) for b, p in pngs if os.path.exists(p)]
    if pngs:
        import matplotlib
        matplotlib.use('Agg')
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(len(pngs), 1, figsize=(10, 4.2 * len(pngs)))
        for ax, (b, p) in zip(axes if len(pngs) > 1 else [axes], pngs):
            ax.imshow(plt.imread(p))
            ax.set_axis_off()
            ax.set_title(b, fontsize=9)
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, 'layout.png'), dpi=100)
    return 0


if __name__ == '__main__':
    sys.exit(main())
