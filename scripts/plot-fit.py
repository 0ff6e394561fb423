#!/usr/bin/python3
"""Plots of an nct fit: the readings against the start and the fit, the
convergence, the correlations.

Usage: /usr/bin/python3 scripts/plot-fit.py DIR [--out PNGDIR]

DIR is a fit folder (nct fit FIT --out DIR). Writes into PNGDIR (default
DIR) fit-curves.png, fit-profiles.png, fit-convergence.png and
fit-correlation.png; what each shows: python/nct/fit.py. A figure whose
inputs are absent is skipped with a note.
"""
import argparse
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "python"))
from nct import fit  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir", type=pathlib.Path)
    ap.add_argument("--out", type=pathlib.Path, help="folder of the PNGs (default DIR)")
    a = ap.parse_args()
    if not (a.dir / "fit.json").is_file():
        print("plot-fit: %s has no fit.json (not an nct fit folder)" % a.dir, file=sys.stderr)
        sys.exit(2)
    fit.plot(a.dir, a.out)


if __name__ == "__main__":
    main()
