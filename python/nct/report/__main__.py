"""python3 -m nct.report DIR [--out FILE]: DIR/report.html for a run, a
study, a fit or a cohort folder (what `nct report` runs)."""
import argparse
import pathlib
import sys

from . import NotAReportFolder, kind, write


def main():
    ap = argparse.ArgumentParser(prog="nct report", description=__doc__.split("\n")[0])
    ap.add_argument("folder", type=pathlib.Path)
    ap.add_argument("--out", type=pathlib.Path, help="the page (default: DIR/report.html)")
    a = ap.parse_args()
    if a.out and not a.out.resolve().parent.is_dir():
        print(f"error: --out {a.out}: cannot write the page: its folder "
              f"{a.out.resolve().parent} does not exist", file=sys.stderr)
        return 2
    try:
        what = kind(a.folder)
        path = write(a.folder, a.out)
    except NotAReportFolder as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except OSError as e:  # an --out that cannot be written
        print(f"error: cannot write the page: {e}", file=sys.stderr)
        return 2
    print(f"report: {path} ({what})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
