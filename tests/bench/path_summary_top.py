#!/usr/bin/env python3
"""path_summary_top.py - bench_trade --path's summary with every case the walks cannot resolve at the top of its
interval: medians that bound the error from above, where the plain summary reads those cases near 0.

usage: path_summary_top.py OUT_path.csv OUT_path_summary.tsv > OUT_path_summary_top.tsv
(then tests/bench/plot_trade.sh OUT_path_summary_top.tsv PREFIX path-top)"""
import csv
import statistics
import sys

if len(sys.argv) != 3:
    sys.exit(__doc__)
cases = {}
for row in csv.DictReader(open(sys.argv[1])):
    mode = row["what"] + (" " + row["profile"] if row["profile"] else "")
    resolved = float(row["without_noise_low"]) > 0.0
    value = float(row["rel_l2_without_noise"] if resolved else row["without_noise_high"])
    cases.setdefault((row["size"], mode), []).append(value)
lines = open(sys.argv[2]).read().splitlines()
print(lines[0])
for line in lines[1:]:
    field = line.split("\t")
    field[3] = "%.6f" % statistics.median(cases[(field[0], field[1])])
    print("\t".join(field))
