#!/usr/bin/python3
"""Plots of a puff run: apex displacement, IOP and apex air pressure against
time, and the corneal profiles at A1, HC and A2.

Usage: scripts/plot-puff.py RUN_DIR   (writes RUN_DIR/puff.png and
RUN_DIR/profiles.png from frames.csv, profiles.csv and summary.json)
"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "python"))
from nct import puff  # noqa: E402

if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    run = sys.argv[1]
    try:
        puff.plot(run)
    except ValueError as e:
        sys.exit(str(e))
    print(f"wrote {run}/puff.png and {run}/profiles.png")
