#!/usr/bin/python3
"""A space-filling design for a table-design study (its cases' CSV).

    /usr/bin/python3 scripts/design.py STUDY N [--seed S] [--out CSV]

Reads the [[factor]] tables of STUDY (design = "table"; each with a
range and optionally scale = "log"), draws N points by a maximin Latin
hypercube (python/nct/design.py) and writes them as STUDY's cases file
(study.cases, or --out). The same seed gives the same design.
"""
import argparse
import pathlib
import sys
import tomllib

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "python"))
from nct import design  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("study")
    parser.add_argument("n", type=int)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out")
    args = parser.parse_args()
    factors = design.read_factors(args.study)
    if args.out:
        out = pathlib.Path(args.out)
    else:
        with open(args.study, "rb") as f:
            out = pathlib.Path(args.study).parent / tomllib.load(f)["study"]["cases"]
    rows = design.to_box(design.maximin_hypercube(len(factors), args.n, args.seed), factors)
    design.write_design(out, rows, factors)
    print(f"design: {args.n} points of {', '.join(f.label for f in factors)} (seed {args.seed}) "
          f"-> {out}")


if __name__ == "__main__":
    main()
