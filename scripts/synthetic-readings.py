#!/usr/bin/python3
"""Synthetic Corvis readings from an nct run, with measurement noise.

Usage: scripts/synthetic-readings.py RUN OUT [--seed N] [--sd-curve MM]
       [--sd-profile MM] [--every K] [--profile-times MS,MS,...]
       [--profile-x MM,MM,...]

Writes into OUT apex.csv and whole-eye.csv (the apex displacement and the
whole-eye motion at every K-th Corvis frame, with noise of SD --sd-curve),
profiles.csv (the anterior surface's axial displacement from its t = 0
profile at the given times and x, with noise of SD --sd-profile) and
biomarkers.toml (the deflection amplitude and A1 time with their noise);
python/nct/readings.py says how. The noise defaults are the Corvis ST's
precision as we read it: 0.02 mm per frame (about one pixel of its camera).
"""
import argparse
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "python"))
from nct import readings  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run", type=pathlib.Path)
    ap.add_argument("out", type=pathlib.Path)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--sd-curve", type=float, default=0.02)
    ap.add_argument("--sd-profile", type=float, default=0.02)
    ap.add_argument("--every", type=int, default=4)
    ap.add_argument("--profile-times", default="5,10,15")
    ap.add_argument("--profile-x", default="-3,-2,-1,0,1,2,3")
    a = ap.parse_args()
    readings.synthetic(a.run, a.out, a.seed, a.sd_curve, a.sd_profile, a.every,
                       [float(s) for s in a.profile_times.split(",")],
                       [float(s) for s in a.profile_x.split(",")])
    print("synthetic readings of %s (seed %d) in %s" % (a.run, a.seed, a.out))


if __name__ == "__main__":
    main()
