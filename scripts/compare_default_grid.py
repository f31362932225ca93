#!/usr/bin/env python3
"""Compare the default grid's rows (sweeps/results/default/results.jsonl, `rayunits sweep
sweeps/default.toml`) with the checked-in cell-flow end points (synth/results/cell/*.ends.jsonl,
default parameters only): how many are identical, the range and median of the area and STA Fmax
ratios, and the largest moves.

usage: scripts/compare_default_grid.py [SWEEP_DIR] [CELL_DIR]
"""
import glob
import json
import os
import statistics
import sys


def main():
    sweep = sys.argv[1] if len(sys.argv) > 1 else "sweeps/results/default"
    cell = sys.argv[2] if len(sys.argv) > 2 else "synth/results/cell"
    new = {}
    with open(os.path.join(sweep, "results.jsonl")) as f:
        for line in f:
            r = json.loads(line)
            for row in r.get("result") or []:
                new[(row["unit"], row["format"], row["stages"], row["target_clock_ps"])] = row
    same, da, df, moves = 0, [], [], []
    for path in sorted(glob.glob(os.path.join(cell, "*.ends.jsonl"))):
        with open(path) as f:
            for line in f:
                row = json.loads(line)
                if sorted(row.get("params", {})) != ["ExpW", "FracW", "Round", "Stages", "Subnormals"]:
                    continue
                k = (row["unit"], row["format"], row["stages"], row["target_clock_ps"])
                if k not in new:
                    continue
                n = new[k]
                if (n["area_um2"], n["fmax_mhz"]) == (row["area_um2"], row["fmax_mhz"]):
                    same += 1
                a = n["area_um2"] / row["area_um2"] - 1
                m = n["fmax_mhz"] / row["fmax_mhz"] - 1
                da.append(a)
                df.append(m)
                moves.append((abs(a) + abs(m), k, row["area_um2"], n["area_um2"], row["fmax_mhz"], n["fmax_mhz"]))
    if not da:
        sys.exit("compare_default_grid.py: no common points")
    print("%d common end points, %d identical" % (len(da), same))
    print("area: %+.1f %% .. %+.1f %%, median %+.2f %%" % (100 * min(da), 100 * max(da), 100 * statistics.median(da)))
    print("STA Fmax: %+.1f %% .. %+.1f %%, median %+.2f %%" % (100 * min(df), 100 * max(df),
                                                            100 * statistics.median(df)))
    for _, k, a0, a1, f0, f1 in sorted(moves, reverse=True)[:5]:
        print("  %s %s Stages %d at %g ps: %.0f -> %.0f um2, %.1f -> %.1f MHz" % (k + (a0, a1, f0, f1)))


if __name__ == "__main__":
    main()
