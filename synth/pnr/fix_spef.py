#!/usr/bin/python3
"""Repair the SPEF that qflow 1.3.17's rc2dly writes so that OpenSTA can read it.

rc2dly (qflow 1.3.17, Debian) writes two things OpenSTA cannot use:
  * the header says "*C_UNIT 1 FF" but every capacitance is in pF (pin loads of
    osu018 appear as 0.018, i.e. 18 fF; the liberty's capacitive_load_unit is pF);
  * internal RC nodes are written "19_3" (net index, underscore, node), which is not
    a SPEF node name; SPEF wants "*19:3" (the net's name-map index, the delimiter, a
    node number).
  * name-map entries keep the router's names ("b_i[16_bF_buf3]", "u_unit.c1_aux[10]")
    while the netlist OpenSTA reads (<top>.rtlnopwr.v) spells them with '_' for each
    of . [ ] < > $ ("b_i_16_bF_buf3_", "u_unit_c1_aux_10_"); bus bits of ports stay
    "b_i[16]". With the netlist given, each name is kept when the netlist has it,
    otherwise replaced by its '_' spelling when the netlist has that.
It also writes pins named "ERROR" on a few clock-buffer nets (qrouter's RC tree lost
a tap); those lines are dropped (the clock is ideal in the STA anyway) and counted.

usage: fix_spef.py IN.spef OUT.spef [NETLIST.v]
prints "error_pins N renamed_nets M unmatched_nets K" on stdout
"""
import re
import sys

node = re.compile(r'^(\d+)_(\d+)$')


def fix_tok(t):
    m = node.match(t)
    return '*%s:%s' % (m.group(1), m.group(2)) if m else t


def netlist_names(path):
    names = set()
    conn = re.compile(r'\.\w+\(\s*([^()\s]+)\s*\)')
    inst = re.compile(r'^\s*\w+\s+(\S+)\s*\(')
    with open(path) as f:
        for line in f:
            m = inst.match(line)
            if m:
                names.add(m.group(1))
            for m in conn.finditer(line):
                names.add(m.group(1))
            if line.lstrip().startswith(('input', 'output', 'wire')):
                for t in re.split(r'[\s,;]+', line.strip())[1:]:
                    if t and not t.startswith('['):
                        names.add(t)
    return names


def main():
    src, dst = sys.argv[1], sys.argv[2]
    names = netlist_names(sys.argv[3]) if len(sys.argv) > 3 else None
    section = None
    errors = renamed = unmatched = 0
    in_map = False
    with open(src) as f, open(dst, 'w') as o:
        for line in f:
            s = line.split()
            if line.startswith('*C_UNIT'):
                o.write('*C_UNIT 1 PF\n')
                continue
            if s and s[0] in ('*CONN', '*CAP', '*RES', '*END', '*D_NET'):
                section = s[0]
            if line.startswith('*NAME_MAP'):
                in_map = True
            elif in_map and s and not re.match(r'^\*\d+$', s[0]):
                in_map = False
            if in_map and names is not None and len(s) == 2:
                n = s[1]
                if n not in names:
                    alt = re.sub(r'[.\[\]<>$]', '_', n)
                    if alt in names:
                        n = alt
                        renamed += 1
                    else:
                        unmatched += 1
                o.write('%s %s\n' % (s[0], n))
                continue
            if any('ERROR' in t for t in s):
                errors += 1
                continue
            if section in ('*CAP', '*RES') and s and s[0].isdigit():
                toks = [s[0]] + [fix_tok(t) for t in s[1:-1]] + [s[-1]]
                o.write(' '.join(toks) + '\n')
                continue
            o.write(line)
    print('error_pins %d renamed_nets %d unmatched_nets %d' % (errors, renamed, unmatched))


if __name__ == '__main__':
    main()
