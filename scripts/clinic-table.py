#!/usr/bin/python3
"""A run's Corvis parameters against the clinical norms of normal eyes.

Prints a Markdown table: every DCR parameter of RUN/summary.json with the
normal mean and SD and the run's z-score, (run - mean) / SD.

Sources (docs/physics.md section 9): 1,304 normal eyes, Corvis ST (PMC7001013;
IOP 16.8 +- 2.9 mmHg); the whole-eye movement's time: 68 healthy eyes
(doi:10.21203/rs.3.rs-9226844/v1). Times are on the device's clock, whose
zero lies an unknown time before a run's pulse onset; the intervals'
SDs are taken from the two times' SDs as if independent (an upper bound).

Usage: scripts/clinic-table.py RUN
"""
import json
import math
import os
import sys

A1, HC, A2 = (7.36, 0.39), (16.84, 0.64), (20.13, 0.48)


def interval(a, b):
    return (b[0] - a[0], math.hypot(a[1], b[1]))


# (key, name, unit, clinical (mean, SD) or None, scale of the run's value)
ROWS = [
    ("deformation_amplitude_mm", "deformation amplitude", "mm", (1.05, 0.10), 1),
    ("deflection_amplitude_mm", "deflection amplitude", "mm", None, 1),
    ("a1_time_ms", "A1 time (device clock)", "ms", A1, 1),
    ("hc_time_ms", "HC time (device clock)", "ms", HC, 1),
    ("a2_time_ms", "A2 time (device clock)", "ms", A2, 1),
    ("a1_hc_interval_ms", "A1 to HC", "ms", interval(A1, HC), 1),
    ("a1_a2_interval_ms", "A1 to A2", "ms", interval(A1, A2), 1),
    ("a1_length_mm", "A1 length", "mm", (1.82, 0.22), 1),
    ("a2_length_mm", "A2 length", "mm", (1.34, 0.55), 1),
    # The clinic signs velocities + inwards; ours + outwards.
    ("a1_velocity_m_s", "A1 velocity (+ inwards)", "m/s", (0.12, 0.04), -1),
    ("a2_velocity_m_s", "A2 velocity (+ inwards)", "m/s", (-0.67, 0.17), -1),
    ("peak_distance_mm", "peak distance", "mm", (4.60, 1.01), 1),
    ("hc_radius_mm", "HC radius", "mm", (7.35, 1.39), 1),
    ("whole_eye_movement_max_mm", "whole-eye movement, max", "mm", None, 1),
    ("whole_eye_movement_time_ms", "whole-eye movement, time (device clock)", "ms",
     (21.07, 0.51), 1),
    ("da_ratio_1mm", "DA ratio 1 mm", "", None, 1),
    ("da_ratio_2mm", "DA ratio 2 mm", "", None, 1),
    ("max_inverse_radius_per_mm", "max inverse concave radius", "1/mm", None, 1),
    ("integrated_inverse_radius_ms_per_mm", "integrated inverse radius", "ms/mm", None, 1),
    ("a1_deflection_mm", "deflection amplitude at A1", "mm", None, 1),
    ("sp_a1_mmHg_per_mm", "SP-A1", "mmHg/mm", None, 1),
    ("iop_max_mmHg", "IOP, max under the puff", "mmHg", None, 1),
]


def main(run):
    with open(os.path.join(run, "summary.json")) as f:
        s = json.load(f)
    print("| parameter | run | normal eyes (mean +- SD) | z |")
    print("|---|---|---|---|")
    for key, name, unit, clinic, scale in ROWS:
        if key not in s:
            continue
        v = scale * s[key]
        u = f" {unit}" if unit else ""
        if clinic:
            z = (v - clinic[0]) / clinic[1]
            print(f"| {name} | {v:.4g}{u} | {clinic[0]:.4g} +- {clinic[1]:.2g}{u} | {z:+.1f} |")
        else:
            print(f"| {name} | {v:.4g}{u} | no verified norm | |")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
