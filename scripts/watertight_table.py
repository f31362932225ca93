#!/usr/bin/env python3
"""Markdown tables from the CSV of scripts/watertight_exact.sh (study watertight --csv).

  scripts/watertight_table.py wt.csv            one table per mesh: leaks / double hits per ray class
  scripts/watertight_table.py wt.csv --summary  one line per (mesh, unit): worst over the formats
"""
import csv
import os
import sys
from collections import OrderedDict


def unit(r):
    if r["tri"] == "robust":
        return "robust + tie-break" if r["tie_break"] == "1" else "robust"
    return {"exact": "**exactly-once**", "mt": "MT"}[r["tri"]]


def main():
    if len(sys.argv) < 2:
        sys.exit("usage: watertight_table.py FILE.csv [--summary]")
    rows = list(csv.DictReader(open(sys.argv[1])))
    if not rows:
        sys.exit("watertight_table.py: %s has no rows" % sys.argv[1])
    meshes = OrderedDict()
    for r in rows:
        meshes.setdefault(os.path.basename(r["scene"]), []).append(r)
    if "--summary" in sys.argv:
        print("| mesh | unit | formats | edge leaks | edge double | vertex leaks | vertex double | near-vertex leaks | near-vertex double | exact path (% of tests) |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for m, rs in meshes.items():
            by = OrderedDict()
            for r in rs:
                by.setdefault(unit(r), []).append(r)
            for u, us in by.items():
                def mx(k):
                    return max(int(r[k]) for r in us)
                slow = ""
                if us[0]["tri"] == "exact":
                    v = [100.0 * int(r["slow_tests"]) / max(1, int(r["tests"])) for r in us]
                    slow = "%.1f–%.1f" % (min(v), max(v))
                n = us[0]
                print("| %s | %s | %d | %d | %d | %d | %d | %d | %d | %s |" % (
                    m, u, len(us), mx("edge_leaks"), mx("edge_double_hits"), mx("vertex_leaks"),
                    mx("vertex_double_hits"), mx("near_vertex_leaks"), mx("near_vertex_double_hits"), slow))
        return
    for m, rs in meshes.items():
        r0 = rs[0]
        print("\n%s (scale %s): %s edge + %s vertex + %s near-vertex rays per row\n" % (
            m, r0["scale"], r0["edge_rays"], r0["vertex_rays"], r0["near_vertex_rays"]))
        print("| format | unit | edge leaks | edge double | vertex leaks | vertex double | near-vertex leaks | near-vertex double | oracle ≠ 1 | exact path % |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for r in rs:
            slow = "%.1f" % (100.0 * int(r["slow_tests"]) / max(1, int(r["tests"]))) if r["tri"] == "exact" else ""
            print("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                r["format"], unit(r), r["edge_leaks"], r["edge_double_hits"], r["vertex_leaks"],
                r["vertex_double_hits"], r["near_vertex_leaks"], r["near_vertex_double_hits"], r["oracle_not_one"], slow))


main()
