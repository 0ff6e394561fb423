#!/usr/bin/python3
"""Where a run's wall time went: a row per phase from its summary.json.

Usage: scripts/profile.py RUN_DIR_OR_SUMMARY [--markdown]

The columns are python/nct/timing.py's.
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
