#!/usr/bin/python3
"""A run's Corvis parameters against the clinical norms of normal eyes.

Prints a Markdown table: every DCR parameter of RUN/summary.json with the
normal mean and SD and the run's z-score, (run - mean) / SD. The norms and
their sources: python/nct/clinic.py (docs/physics.md section 9).

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
