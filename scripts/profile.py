#!/usr/bin/python3
"""Where a run's wall time went: a row per phase from its summary.json.

Usage: scripts/profile.py RUN_DIR_OR_SUMMARY [--markdown]

Columns: wall time; residual assemblies (count, of them the line
search's, seconds); Jacobian assemblies; factorisations (the
preconditioner's set-up: MUMPS LU); linear solves (count, Krylov
iterations, seconds; LU back-solves under preonly); the bordered system's
extra work (its B, C assembly and solves, counted in the columns before
it too); field output; the rest of the phase (the log, the state's
bookkeeping, biomarkers).
"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "python"))
from nct import markdown, timing  # noqa: E402
from nct.folders import read_summary  # noqa: E402


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) != 1:
        sys.exit(__doc__)
    summary = read_summary(args[0])
    head, rows = timing.phases(summary)
    print("%s: %s DOFs on %s rank(s)" % (summary["scene"], summary.get("dofs"), summary["ranks"]))
    print(markdown.table(head, rows) if "--markdown" in sys.argv else markdown.aligned(head, rows))


if __name__ == "__main__":
    main()
