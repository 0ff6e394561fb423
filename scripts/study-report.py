#!/usr/bin/python3
"""A study's rankings as Markdown (for the case pages).

    /usr/bin/python3 scripts/study-report.py STUDY_FOLDER [TERMS]

prints, per response, the TERMS (default 8) largest effects with their
share of the sum of squares and p (factorial), then the cases' wall time;
for an ablation, one table: per response, each variant's value and its
difference from the baseline (absolute and in percent).
"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "python"))
from nct import study  # noqa: E402

if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    print(study.report(sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 8))
