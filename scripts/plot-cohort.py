#!/usr/bin/python3
"""Plots and the recovery table of an nct cohort (a fit file with a
[cohort] table, fitted with nct fit).

Usage: /usr/bin/python3 scripts/plot-cohort.py DIR [--out PNGDIR]

DIR is the cohort's folder (its cohort.csv). Writes into PNGDIR (default
DIR) cohort-iop.png, cohort-age.png (with an age column) and
cohort-recovery.png (with truths), what each shows: python/nct/cohort.py;
prints per parameter with truths a Markdown recovery table (patient,
truth, fit, SE, interval, error, inside) and the share of truths inside
their intervals. Patients whose fit failed are left out, with a note.
"""
import argparse
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "python"))
from nct import cohort  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir", type=pathlib.Path)
    ap.add_argument("--out", type=pathlib.Path)
    a = ap.parse_args()
    if not (a.dir / "cohort.csv").exists():
        sys.exit("plot-cohort: %s not found: run nct fit on the cohort first"
                 % (a.dir / "cohort.csv"))
    rows, failed = cohort.fitted(a.dir)
    if failed:
        print("plot-cohort: no fit for %s (left out)" % ", ".join(failed))
    if not rows:
        sys.exit("plot-cohort: no patient was fitted")
    for path in cohort.plot(a.dir, a.out):
        print("wrote %s" % path)
    for table in cohort.recovery(a.dir):
        print("\n" + table)


if __name__ == "__main__":
    main()
