#!/usr/bin/env python3
"""Compares the run folders of two `master run --out` trees, case by case:
deflection.csv, history.csv and (where present) soil.csv must have the same
header and rows, and every column must agree to TOLERANCE relative to the
largest magnitude of that column in the first tree.

  compare_runs.py REFERENCE_DIR OTHER_DIR TOLERANCE

Prints the worst relative difference; exits 1 naming the first column over
the tolerance, or a file or case that is missing."""
import csv
import os
import sys

reference, other, tolerance = sys.argv[1], sys.argv[2], float(sys.argv[3])
worst = 0.0
cases = sorted(os.listdir(reference))
if not cases:
    sys.exit("no runs in " + reference)
for case in cases:
    for name in ("deflection.csv", "history.csv", "soil.csv"):
        path = os.path.join(reference, case, name)
        if not os.path.exists(path):
            continue
        a = list(csv.reader(open(path)))
        b = list(csv.reader(open(os.path.join(other, case, name))))
        if a[0] != b[0] or len(a) != len(b):
            sys.exit("%s/%s: header or row count differs (%d vs %d rows)" % (case, name, len(a),
                                                                            len(b)))
        for col in range(len(a[0])):
            x = [float(r[col]) for r in a[1:]]
            y = [float(r[col]) for r in b[1:]]
            scale = max(abs(v) for v in x) or 1.0
            diff = max(abs(p - q) for p, q in zip(x, y)) / scale
            worst = max(worst, diff)
            if diff > tolerance:
                sys.exit("%s/%s column %s differs by %.3g relative (tolerance %g)" %
                         (case, name, a[0][col], diff, tolerance))
print("%d cases agree: worst relative difference %.3g (tolerance %g)" % (len(cases), worst,
                                                                         tolerance))
