#!/usr/bin/python3
"""Split a flat pipelined netlist into one block per pipeline stage (issue 13 section 3).

usage: split_stages.py IN.json OUT.json TOP [--report REPORT.json]
       split_stages.py --plain-ports SUB.json OUT.json TOP


IN.json is Yosys `write_json` of the flattened unit after `proc; flatten; opt; memory; opt;
techmap t:*dff*; opt_clean` (word-level logic, single-bit flip-flops, no processes or memories;
the flip-flops are split so that bits whose output nobody reads are removed: `memory` on the
noise unit's gradient tables leaves 240 such bits, reading a wire it no longer drives). Every
flip-flop cell (type containing "dff")
gets a rank: 1 + the largest rank of the flip-flops reachable backwards from its inputs through
combinational cells (top-level inputs have rank 0). Every combinational cell belongs to the
stage of the flip-flops it feeds: forwards through combinational cells to the first flip-flops
(or to the top-level outputs, which count as rank R+1 if they are driven combinationally, R the
largest flip-flop rank). Block s = the combinational cells feeding rank s plus the rank-s
flip-flops ("output-registered" blocks), so a stage's register-to-register path lies in one
block except the launching flip-flop's clock-to-Q, which sits in the previous block.

The script stops with an error if a combinational cell feeds flip-flops of two different ranks
(an unbalanced pipeline: the stage is not well defined), or a flip-flop depends on one of its
own rank (a loop). It writes OUT.json = IN.json with the attribute submod = "stN" on every
cell, for Yosys `read_json OUT.json; submod` (which names the modules TOP_stN), and prints (and with --report writes) the blocks'
cell counts by type.

With --plain-ports, SUB.json is the design after `submod`: the ports of every TOP_stN module
(named after the flattened wires, e.g. `u_unit.l4_q`) are renamed to plain identifiers
(`u_unit_l4_q`) in the module and in TOP's instances, since qflow's BLIF/DEF steps do not take
escaped Verilog names.
"""
import collections
import json
import re
import sys


def is_ff(cell):
    return 'dff' in cell['type'].lower()


def is_clockish(cell, port):
    """Clock and asynchronous reset inputs of a flip-flop: not data, they set no rank."""
    return is_ff(cell) and (port in ('CLK', 'C', 'ARST') or (port == 'R' and cell['type'].startswith('$_DFF_')))


def plain(name):
    return re.sub(r'[^A-Za-z0-9_]', '_', name)


def plain_ports(src, dst, top):
    design = json.load(open(src))
    mods = design['modules']
    blocks = [m for m in mods if m.startswith(top + '_st')]
    if not blocks:
        sys.exit(f'split_stages.py: error: no {top}_stN modules in {src} (run submod first)')
    for m in blocks:
        mod = mods[m]
        new = {plain(p): v for p, v in mod['ports'].items()}
        if len(new) != len(mod['ports']):
            sys.exit(f'split_stages.py: error: two ports of {m} have the same plain name')
        mod['ports'] = new
        mod['netnames'] = {plain(n) if plain(n) in new else n: v for n, v in mod['netnames'].items()}
    for c in mods[top]['cells'].values():
        if c['type'] in blocks:
            c['connections'] = {plain(p): v for p, v in c['connections'].items()}
            c['port_directions'] = {plain(p): v for p, v in c.get('port_directions', {}).items()}
    with open(dst, 'w') as f:
        json.dump(design, f)
    return 0


def main(argv):
    if len(argv) == 5 and argv[1] == '--plain-ports':
        return plain_ports(argv[2], argv[3], argv[4])
    args = [a for a in argv[1:] if not a.startswith('--')]
    report = None
    if '--report' in argv:
        report = argv[argv.index('--report') + 1]
        args.remove(report)
    if len(args) != 3:
        sys.exit('usage: split_stages.py IN.json OUT.json TOP [--report REPORT.json]')
    src, dst, top = args
    design = json.load(open(src))
    if top not in design['modules']:
        sys.exit(f'split_stages.py: error: module {top} not in {src} (has: {", ".join(design["modules"])})')
    mod = design['modules'][top]
    cells = mod['cells']
    if not cells:
        sys.exit(f'split_stages.py: error: module {top} has no cells')

    driver = {}       # bit -> cell name
    readers = collections.defaultdict(list)  # bit -> cell names
    for name, c in cells.items():
        dirs = c.get('port_directions', {})
        for port, bits in c['connections'].items():
            d = dirs.get(port)
            if d is None:
                sys.exit(f'split_stages.py: error: cell {name} ({c["type"]}) has no port_directions '
                         '(write the JSON after proc/flatten with `write_json`)')
            for b in bits:
                if isinstance(b, str):
                    continue  # constant
                if d == 'output':
                    driver[b] = name
                elif not is_clockish(c, port):
                    readers[b].append(name)
    out_bits = set()
    for pname, p in mod['ports'].items():
        if p['direction'] == 'output':
            out_bits.update(b for b in p['bits'] if not isinstance(b, str))

    def inputs_of(name):
        c = cells[name]
        for port, bits in c['connections'].items():
            if c['port_directions'][port] != 'input':
                continue
            if is_clockish(c, port):
                continue
            for b in bits:
                if not isinstance(b, str) and b in driver:
                    yield driver[b]

    # rank of each flip-flop: longest register count from the inputs (memoized DFS through comb cells)
    ff_rank = {}
    comb_src_rank = {}  # comb cell -> largest rank among flip-flops (or 0) feeding it

    def src_rank(name, stack):
        if is_ff(cells[name]):
            return ff_rank_of(name, stack)
        if name in comb_src_rank:
            return comb_src_rank[name]
        if name in stack:
            sys.exit(f'split_stages.py: error: combinational loop through {name}')
        stack.add(name)
        r = max((src_rank(p, stack) for p in inputs_of(name)), default=0)
        stack.discard(name)
        comb_src_rank[name] = r
        return r

    def ff_rank_of(name, stack):
        if name in ff_rank:
            if ff_rank[name] is None:
                sys.exit(f'split_stages.py: error: flip-flop {name} depends on itself (a loop, not a pipeline)')
            return ff_rank[name]
        ff_rank[name] = None
        r = 1
        for p in inputs_of(name):
            if is_ff(cells[p]):
                r = max(r, ff_rank_of(p, stack) + 1)
            else:
                r = max(r, src_rank(p, set()) + 1)
        ff_rank[name] = r
        return r

    sys.setrecursionlimit(100000)
    for name in cells:
        if is_ff(cells[name]):
            ff_rank_of(name, set())
    top_rank = max(ff_rank.values(), default=0)

    # stage of each comb cell: the ranks of the first flip-flops (or outputs) downstream
    comb_sink = {}

    def sinks(name, stack):
        if name in comb_sink:
            return comb_sink[name]
        stack.add(name)
        s = set()
        for port, bits in cells[name]['connections'].items():
            if cells[name]['port_directions'][port] != 'output':
                continue
            for b in bits:
                if isinstance(b, str):
                    continue
                if b in out_bits:
                    s.add(top_rank + 1)
                for r in readers.get(b, ()):
                    if is_ff(cells[r]):
                        s.add(ff_rank[r])
                    elif r not in stack:
                        s |= sinks(r, stack)
        stack.discard(name)
        comb_sink[name] = frozenset(s)
        return comb_sink[name]

    block = {}
    for name, c in cells.items():
        if is_ff(c):
            block[name] = ff_rank[name]
            continue
        s = sinks(name, set())
        if not s:
            block[name] = None  # drives nothing: opt_clean removes it
            continue
        if len(s) != 1:
            sys.exit(f'split_stages.py: error: cell {name} ({c["type"]}) feeds flip-flops of ranks '
                     f'{sorted(s)}: the pipeline is not balanced, stages are not well defined')
        block[name] = next(iter(s))

    nblocks = max(v for v in block.values() if v is not None)
    summary = {'top': top, 'blocks': []}
    for s in range(1, nblocks + 1):
        names = [n for n, b in block.items() if b == s]
        types = collections.Counter(cells[n]['type'] for n in names)
        ff_bits = sum(len(cells[n]['connections']['Q']) for n in names if is_ff(cells[n]))
        summary['blocks'].append({'name': f'{top}_st{s}', 'stage': s, 'cells': len(names),
                                  'ff_bits': ff_bits, 'types': dict(sorted(types.items()))})
    summary['unassigned'] = sum(1 for b in block.values() if b is None)
    summary['flip_flop_ranks'] = top_rank
    summary['output_driven_combinationally'] = nblocks > top_rank
    for name, c in cells.items():
        if block[name] is not None:
            c.setdefault('attributes', {})['submod'] = f'st{block[name]}'  # submod names it TOP_stN
    # A named wire with a bit that no cell and no port touches (e.g. fp_add's u_rp.c_sig[11]) would
    # become a block port with an undriven bit (`check -assert` fails): drop such names; the bits
    # that are connected keep their connections under Yosys's own names.
    touched = set(out_bits)
    for p in mod['ports'].values():
        touched.update(b for b in p['bits'] if not isinstance(b, str))
    for c in cells.values():
        for bits in c['connections'].values():
            touched.update(b for b in bits if not isinstance(b, str))
    dangling = [n for n, w in mod['netnames'].items()
                if any(not isinstance(b, str) and b not in touched for b in w['bits'])]
    for n in dangling:
        del mod['netnames'][n]
    summary['dropped_wire_names'] = dangling
    with open(dst, 'w') as f:
        json.dump(design, f)
    for b in summary['blocks']:
        print(f"{b['name']}: {b['cells']} word-level cells, {b['ff_bits']} flip-flop bits")
    if report:
        with open(report, 'w') as f:
            json.dump(summary, f, indent=1)
            f.write('\n')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
