#!/usr/bin/python3
"""Synthetic Corvis readings from an nct run, with measurement noise.

Usage: scripts/synthetic-readings.py RUN OUT [--seed N] [--sd-curve MM]
       [--sd-profile MM] [--every K] [--profile-times MS,MS,...]
       [--profile-x MM,MM,...]

Writes into OUT:
- apex.csv: t_ms,value_mm,sd_mm, the apex displacement (frames.csv) at
  every K-th Corvis frame, plus Gaussian noise of SD --sd-curve;
- whole-eye.csv: the same for the whole-eye motion;
- profiles.csv: t_ms,x_mm,y_mm,sd_mm, the anterior surface's axial
  displacement from its t = 0 profile at the given times and x, plus noise
  of SD --sd-profile;
- biomarkers.toml: [[observation]] tables of the run's deflection
  amplitude (SD 0.08 mm, docs/physics.md section 9) and A1 time (SD 0.2 ms),
  each with noise of its SD.
The noise defaults are the Corvis ST's precision as we read it: 0.02 mm per
frame (about one pixel of its camera) for the curves and profiles.
"""
import argparse
import csv
import json
import pathlib

import numpy as np


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
    rng = np.random.default_rng(a.seed)
    a.out.mkdir(parents=True, exist_ok=True)

    frames = list(csv.DictReader(open(a.run / "frames.csv")))
    t = np.array([float(f["t_ms"]) for f in frames])
    for column, name in (("apex_displacement_mm", "apex.csv"),
                         ("whole_eye_motion_mm", "whole-eye.csv")):
        v = np.array([float(f[column]) for f in frames])
        with open(a.out / name, "w") as out:
            out.write("t_ms,value_mm,sd_mm\n")
            for i in range(0, len(t), a.every):
                out.write("%.9g,%.6g,%.6g\n" % (t[i], v[i] + rng.normal(0, a.sd_curve),
                                                a.sd_curve))

    rows = list(csv.DictReader(open(a.run / "profiles.csv")))
    by_frame = {}
    for r in rows:
        if r["surface"] == "anterior":
            f = by_frame.setdefault(int(r["frame"]), (float(r["t_ms"]), [], []))
            f[1].append(float(r["x_mm"]))
            f[2].append(float(r["y_mm"]))
    frame_t = np.array([by_frame[k][0] for k in sorted(by_frame)])

    def y_at(k, x):
        _, xs, ys = by_frame[k]
        o = np.argsort(xs)
        return np.interp(x, np.array(xs)[o], np.array(ys)[o])

    with open(a.out / "profiles.csv", "w") as out:
        out.write("t_ms,x_mm,y_mm,sd_mm\n")
        for tm in [float(s) for s in a.profile_times.split(",")]:
            k = sorted(by_frame)[int(np.argmin(abs(frame_t - tm)))]
            for x in [float(s) for s in a.profile_x.split(",")]:
                y = y_at(k, x) - y_at(sorted(by_frame)[0], x)
                out.write("%.9g,%.6g,%.6g,%.6g\n" % (by_frame[k][0], x,
                                                     y + rng.normal(0, a.sd_profile),
                                                     a.sd_profile))

    summary = json.load(open(a.run / "summary.json"))
    with open(a.out / "biomarkers.toml", "w") as out:
        for key, sd in (("deflection_amplitude_mm", 0.08), ("a1_time_ms", 0.2)):
            out.write("[[observation]]\nbiomarker = \"%s\"\nvalue = %.6g\nsd = %g\n\n"
                      % (key, summary[key] + rng.normal(0, sd), sd))
    print("synthetic readings of %s (seed %d) in %s" % (a.run, a.seed, a.out))


if __name__ == "__main__":
    main()
