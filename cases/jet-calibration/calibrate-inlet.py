#!/usr/bin/python3
"""How far a rigid-eye run's apex pressure is from the measured pulse.

Reads RUN/steps.csv (t_ms, apex_pressure_mmHg) of a puff.load = "air" run
with inlet.history = "pulse", and the pulse's descriptors from its
resolved scene (RUN/scene.toml: puff.peak, rise_rate, fall_rate,
pulse_duration), and prints: the computed and measured peak, the mean
10-90 % rates of both edges of either, the largest and RMS difference over
time, and the inlet speed that would bring the computed peak onto the
measured one (the quasi-steady jet's stagnation pressure goes as the
inlet speed squared).

Usage: cases/jet-calibration/calibrate-inlet.py RUN
"""
import math
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "python"))
from nct.folders import Run  # noqa: E402


def shape(t, rise, hold, fall):
    """cpp/puff/load.h: PulseShape."""
    if t <= 0 or t >= rise + hold + fall:
        return 0.0
    if t < rise:
        return 0.5 * (1 - math.cos(math.pi * t / rise))
    if t <= rise + hold:
        return 1.0
    return 0.5 * (1 + math.cos(math.pi * (t - rise - hold) / fall))


def edges(t, p):
    """Peak, and the mean rates between 10 % and 90 % of it on either side."""
    top = max(p)
    k = p.index(top)

    def cross(level, rng):
        for i in rng:
            a, b = p[i - 1], p[i]
            if (a - level) * (b - level) <= 0 and a != b:
                return t[i - 1] + (t[i] - t[i - 1]) * (level - a) / (b - a)
        return float("nan")
    up = [cross(f * top, range(1, k + 1)) for f in (0.1, 0.9)]
    down = [cross(f * top, range(k + 1, len(p))) for f in (0.9, 0.1)]
    return top, 0.8 * top / (up[1] - up[0]), -0.8 * top / (down[1] - down[0])


def main(folder):
    run = Run(folder)
    puff, inlet = run.scene["puff"], run.scene["inlet"]
    peak = puff["peak"]
    rise, fall = peak / puff["rise_rate"], peak / puff["fall_rate"]
    hold = puff["pulse_duration"] - rise - fall
    t, p = run.steps["t_ms"].tolist(), run.steps["apex_pressure_mmHg"].tolist()
    target = [peak * shape(x, rise, hold, fall) for x in t]
    diff = [a - b for a, b in zip(p, target)]
    computed, measured = edges(t, p), edges(t, target)
    print(f"{'':24s} {'computed':>10s} {'measured':>10s}")
    for name, i in (("peak [mmHg]", 0), ("rise 10-90 [mmHg/ms]", 1), ("fall 90-10 [mmHg/ms]", 2)):
        print(f"{name:24s} {computed[i]:10.2f} {measured[i]:10.2f}")
    k = max(range(len(diff)), key=lambda i: abs(diff[i]))
    rms = math.sqrt(sum(d * d for d in diff) / len(diff))
    print(f"largest difference {diff[k]:+.2f} mmHg at {t[k]:.2f} ms; RMS {rms:.2f} mmHg "
          f"({100 * rms / peak:.1f} % of the peak)")
    u = inlet["velocity"]
    print(f"inlet {u:.1f} m/s; for the measured peak: {u * math.sqrt(peak / computed[0]):.1f} m/s")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
