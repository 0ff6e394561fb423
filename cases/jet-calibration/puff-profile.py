#!/usr/bin/python3
"""The radial profile of a CFD run's corneal pressure at its peak.

Reads a table t_ms,r_mm,p_mmHg (corneal_pressure.csv of a rigid-eye or
coupled run, or scenes/tables/puff-rigid-eye.csv), takes the time at
which the pressure on the axis (r = 0) is largest, and writes that
instant's r_mm,p_mmHg: what puff.load = "pulse" reads as puff.profile
(normalised by its value on the axis).

    cases/jet-calibration/puff-profile.py TABLE.csv PROFILE.csv
"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "python"))
from nct.puff import pressure_table  # noqa: E402


def main(source, target):
    rows = pressure_table(source)
    peak = max(rows, key=lambda t: min(rows[t])[1] if min(rows[t])[0] == 0 else -1e300)
    profile = sorted(rows[peak])
    if profile[0][0] != 0:
        sys.exit(f"{source}: no pressure on the axis (r = 0) at {peak} ms")
    with open(target, "w") as f:
        f.write("r_mm,p_mmHg\n")
        for r, p in profile:
            f.write(f"{r:.6g},{p:.6g}\n")
    print(f"{target}: the profile at t = {peak:g} ms, {profile[0][1]:.2f} mmHg on the axis, "
          f"{len(profile)} radii to {profile[-1][0]:.2f} mm")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
