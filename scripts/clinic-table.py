#!/usr/bin/python3
"""A run's Corvis parameters against two populations of measured eyes.

Prints a Markdown table: every DCR parameter of RUN/summary.json with the
mean and SD of the 202 real eyes (cases/real-eyes) and of the normal eyes
of PMC7001013, the run's z-scores, (run - mean) / SD, and how many of the
ten shape and speed readings lie within 2 SD of the real eyes. The
populations and their sources: python/nct/clinic.py (docs/physics.md
section 9).

Usage: scripts/clinic-table.py RUN
"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "python"))
from nct import clinic  # noqa: E402
from nct.folders import Run  # noqa: E402

if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    print(clinic.markdown(Run(sys.argv[1]).summary))
