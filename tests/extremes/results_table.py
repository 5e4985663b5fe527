#!/usr/bin/env python3
# Turns the extremes catalogue's recorded results (extremes-results/*.json, written by
# tests_extremes in its working folder, build/tests) into the Markdown table of
# tests/extremes/README.md:  python3 tests/extremes/results_table.py build/tests/extremes-results
import json
import pathlib
import sys

folder = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "build/tests/extremes-results")
rows = []
for path in sorted(folder.glob("*.json")):
    r = json.loads(path.read_text())
    eq = r.get("equalityPixels", {})
    equalities = ", ".join(f"{k} {v}" for k, v in sorted(eq.items())) if eq else "not asserted"
    rows.append((r["case"], len(r["techniques"]), r["referenceMaxCodes"], r["referencePixels"], equalities))
print("| case | techniques | forward exact vs reference: max codes | pixels differing | pixels the corrected culling misses |")
print("|---|---|---|---|---|")
for case, n, codes, pixels, equalities in rows:
    print(f"| {case} | {n} | {codes} | {pixels} | {equalities} |")
