#!/usr/bin/env python3
"""How much of `rayunits study tri`'s error is the rounding of the *inputs* alone.

For a stride subsample of a trace's tri records, every input (a, d, p0, p1, p2) is rounded to
M fraction bits (round to nearest even, no exponent limit), and the exact volumes of the rounded
inputs (Python Fractions, no arithmetic rounding) are compared with the exact volumes of the
trace's own (double) inputs: the average relative error of V, Va and V0..2 that no formulation
can avoid. Compare it with the lowest error of `study tri` (inputs and every operation rounded).
Also counts the records whose ray origin lies on the triangle's plane (distance < 1e-9 x the
largest coordinate of the record: shadow rays tested against the triangle they start on), whose
exact Va is ~0, so their relative error of Va is huge, and the median over records of (largest
|coordinate| of the triangle) / (its shortest edge), which scales the error of rounding the vertices.

  scripts/study_tri_input_rounding.py TRACE [N=2000] [M ...]    (default M: 8 10 12 16 20 22 23)
"""
import math
import struct
import sys
from fractions import Fraction


def read_tris(path):
    b = open(path, 'rb').read()
    if len(b) < 32 or b[:8] != b'RUTRACE\0':
        sys.exit(f'{path}: not a rayunits trace (bad magic or shorter than the 32-byte header)')
    off, tris = 32, []
    while off < len(b):
        if len(b) - off < 8:
            sys.exit(f'{path}: byte {off}: truncated record header')
        kind = struct.unpack_from('<I', b, off)[0]
        size = {1: 144, 2: 120}.get(kind)
        if size is None:
            sys.exit(f'{path}: byte {off}: unknown record kind {kind}')
        if len(b) - off < size:
            sys.exit(f'{path}: byte {off}: truncated record')
        if kind == 1:
            tris.append(struct.unpack_from('<15d', b, off + 8))
        off += size
    return tris


def rnd(x, m):
    """x rounded to m stored fraction bits (RNE), unbounded exponent."""
    if x == 0 or not math.isfinite(x):
        return x
    f, e = math.frexp(x)              # x = f * 2^e, 0.5 <= |f| < 1
    return math.ldexp(round(math.ldexp(f, m + 1)), e - m - 1)   # round(): ties to even, exact


def sub(u, v): return [u[0] - v[0], u[1] - v[1], u[2] - v[2]]
def cross(u, v): return [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
def dot(u, v): return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def volumes(r):
    a, d, p0, p1, p2 = (list(map(Fraction, r[3 * i:3 * i + 3])) for i in range(5))
    V = dot(cross(sub(p2, p0), sub(p1, p2)), d)                       # Eq. 3.3 (any form is exact here)
    Va = dot(cross(sub(p2, p0), sub(p2, p1)), sub(a, p2))             # Eq. 3.4
    p = [p0, p1, p2]
    Vk = [dot(cross(sub(a, p[(k + 1) % 3]), d), sub(p[(k + 1) % 3], p[(k + 2) % 3])) for k in range(3)]
    return [V, Va] + Vk


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    tris = read_tris(sys.argv[1])
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 2000
    ms = [int(x) for x in sys.argv[3:]] or [8, 10, 12, 16, 20, 22, 23]
    if not tris:
        sys.exit(f'{sys.argv[1]}: no ray-triangle records')
    pick = [tris[i * len(tris) // n] for i in range(n)] if len(tris) > n else tris
    exact = [volumes(r) for r in pick]
    on_plane, ratio = 0, []
    for r in pick:
        q = [r[6:9], r[9:12], r[12:15]]
        edge = min(math.dist(q[0], q[1]), math.dist(q[1], q[2]), math.dist(q[2], q[0]))
        ratio.append(max(abs(x) for x in r[6:15]) / edge if edge > 0 else math.inf)
        a, p0, p1, p2 = (list(map(Fraction, r[3 * i:3 * i + 3])) for i in (0, 2, 3, 4))
        nrm = cross(sub(p2, p0), sub(p2, p1))
        dist = abs(float(dot(nrm, sub(a, p2)))) / math.sqrt(float(dot(nrm, nrm)))
        on_plane += dist < 1e-9 * max(abs(x) for x in r[0:3] + r[6:15])
    print(f'# {sys.argv[1]}: {len(pick)} of {len(tris)} tri records (stride subsample); '
          f'input rounding only, exact arithmetic; origin on the triangle plane: {on_plane}; '
          f'median largest coordinate / shortest edge: {sorted(ratio)[len(ratio) // 2]:.3g}')
    print('M,V,Va,V012')
    for m in ms:
        s, c = [0.0, 0.0, 0.0], [0, 0, 0]
        for r, ex in zip(pick, exact):
            vr = volumes([rnd(x, m) for x in r])
            for j in range(5):
                if ex[j] == 0:
                    continue
                k = min(j, 2)
                s[k] += float(abs(vr[j] - ex[j]) / abs(ex[j]))
                c[k] += 1
        print(f'{m},' + ','.join(f'{s[k] / c[k]:.3g}' if c[k] else '' for k in range(3)))


if __name__ == '__main__':
    main()
