"""A run's Corvis parameters against two populations of measured eyes.

- REAL_EYES: 202 eyes of 194 cataract patients (age 69 +- 9), each
  measured once by a Corvis ST whose software reports the DCR parameters,
  the CBI and the SSI (so 2019 or later): cases/real-eyes/all_eyes.csv,
  from the public de-identified cohort of GitHub
  Usama1002/corneal-biomechanical-prediction-model (CC-BY-4.0; see
  cases/real-eyes/README.md). Its mean and SD per column.
- NORMAL_EYES: 1,304 healthy eyes of refractive-surgery candidates (age
  28 +- 5; PMC7001013, IOP 16.8 +- 2.9 mmHg), software not stated; the
  whole-eye movement's time from 68 healthy eyes
  (doi:10.21203/rs.3.rs-9226844/v1). Times are on the device's clock,
  whose zero lies an unknown time before a run's pulse onset; the
  intervals' SDs are taken from the two times' SDs as if independent (an
  upper bound).

The two disagree beyond their SDs on the A2 velocity and the applanation
lengths: their software's definitions differ (docs/physics.md section 9).

    rows = z_scores(summary)      # (name, value, unit, (mean, SD) or None, z or None)
    rows = compare(summary)       # (name, value, unit, {population: (norm, z)})
    print(markdown(summary))
    value, inputs = cbi(summary)  # the Corvis Biomechanical Index, or None and why

Units are the biomarker registry's (nct.biomarkers).
"""
import csv
import math
import pathlib

from . import biomarkers

REAL_EYES_CSV = pathlib.Path(__file__).resolve().parents[2] / "cases" / "real-eyes" / "all_eyes.csv"

A1, HC, A2 = (7.36, 0.39), (16.84, 0.64), (20.13, 0.48)
# Normal eyes' mean times [ms] (device clock).
NORMAL_TIMES = {"A1": A1[0], "HC": HC[0], "A2": A2[0]}


def interval(a, b):
    """The norm of the time from a to b: (mean, SD) as if independent."""
    return (b[0] - a[0], math.hypot(a[1], b[1]))


# (key, name, clinical (mean, SD) or None, scale of the run's value)
ROWS = [
    ("deformation_amplitude_mm", "deformation amplitude", (1.05, 0.10), 1),
    ("deflection_amplitude_mm", "deflection amplitude", None, 1),
    ("a1_time_ms", "A1 time (device clock)", A1, 1),
    ("hc_time_ms", "HC time (device clock)", HC, 1),
    ("a2_time_ms", "A2 time (device clock)", A2, 1),
    ("a1_hc_interval_ms", "A1 to HC", interval(A1, HC), 1),
    ("a1_a2_interval_ms", "A1 to A2", interval(A1, A2), 1),
    ("a1_length_mm", "A1 length", (1.82, 0.22), 1),
    ("a2_length_mm", "A2 length", (1.34, 0.55), 1),
    # The clinic signs velocities + inwards; ours + outwards.
    ("a1_velocity_m_s", "A1 velocity (+ inwards)", (0.12, 0.04), -1),
    ("a2_velocity_m_s", "A2 velocity (+ inwards)", (-0.67, 0.17), -1),
    ("peak_distance_mm", "peak distance", (4.60, 1.01), 1),
    ("hc_radius_mm", "HC radius", (7.35, 1.39), 1),
    ("whole_eye_movement_max_mm", "whole-eye movement, max", None, 1),
    ("whole_eye_movement_time_ms", "whole-eye movement, time (device clock)",
     (21.07, 0.51), 1),
    ("da_ratio_1mm", "DA ratio 1 mm", None, 1),
    ("da_ratio_2mm", "DA ratio 2 mm", None, 1),
    ("max_inverse_radius_per_mm", "max inverse concave radius", None, 1),
    ("integrated_radius_per_mm", "integrated radius", None, 1),
    ("a1_deflection_mm", "deflection amplitude at A1", None, 1),
    ("sp_a1_mmHg_per_mm", "SP-A1", None, 1),
    ("iop_max_mmHg", "IOP, max under the puff", None, 1),
]


NAMES = {key: name for key, name, _, _ in ROWS}

# The real eyes' columns (cases/real-eyes/README.md) for the summary's keys.
REAL_EYES_COLUMNS = {
    "deformation_amplitude_mm": "HCDA", "a1_length_mm": "AL1", "a1_velocity_m_s": "AV1",
    "a2_length_mm": "AL2", "a2_velocity_m_s": "AV2", "peak_distance_mm": "PD",
    "hc_radius_mm": "HCR", "da_ratio_2mm": "DA_Ratio", "integrated_radius_per_mm": "IR",
    "sp_a1_mmHg_per_mm": "SPA1"}

# The clinic signs velocities + inwards; a run + outwards.
_SIGN = {"a1_velocity_m_s": -1, "a2_velocity_m_s": -1}

# The ten readings the real eyes hold that are not times on the device's clock.
SHAPE_AND_SPEED = list(REAL_EYES_COLUMNS)

# What each population's value is, where its definition is known to differ.
SOURCES = {
    "a1_length_mm": "real eyes 2.36 against 1.82 in PMC7001013: the flatness rule differs "
                    "between software versions (early software reported a 'maximum' length)",
    "a2_length_mm": "real eyes 2.31 against 1.34: as the A1 length",
    "a2_velocity_m_s": "real eyes -0.264 against -0.67: the older software detects A2 earlier, "
                       "while the apex still returns fast",
    "hc_radius_mm": "a fit region neither publishes; 11.1 mm in 2014 software (Valbon et al., "
                    "J. Refract. Surg. 30 (2014) 468)",
    "integrated_radius_per_mm": "the device's unit: time counted in frames",
}


def real_eyes(path=REAL_EYES_CSV):
    """{summary key: (mean, SD)} of the real eyes, on the clinic's sign."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    norms = {}
    for key, column in REAL_EYES_COLUMNS.items():
        v = [float(r[column]) for r in rows if r[column] not in ("", "nan")]
        mean = sum(v) / len(v)
        norms[key] = (mean, math.sqrt(sum((x - mean) ** 2 for x in v) / (len(v) - 1)))
    return norms


_REAL_EYES = None


def _real_eyes():
    global _REAL_EYES
    if _REAL_EYES is None:
        _REAL_EYES = real_eyes()
    return _REAL_EYES


def compare(summary):
    """Per parameter the run has: (name, value on the clinic's sign, unit,
    {"real eyes": ((mean, SD), z) or None, "normal eyes": ... or None})."""
    rows = []
    for key, name, norm, scale in ROWS:
        if key in summary:
            value = scale * summary[key]
            real = _real_eyes().get(key)
            rows.append((name, value, biomarkers.unit(key), {
                "real eyes": (real, (value - real[0]) / real[1]) if real else None,
                "normal eyes": (norm, (value - norm[0]) / norm[1]) if norm else None}))
    return rows


def z_scores(summary, population="normal eyes"):
    """Per parameter the run has: (name, value on the clinic's sign, unit,
    the population's norm (mean, SD) or None, z = (value - mean) / SD or
    None); population "real eyes" or "normal eyes"."""
    return [(name, value, unit, *(against[population] or (None, None)))
            for name, value, unit, against in compare(summary)]


def within(summary, sds=2.0):
    """The ten shape and speed readings against the real eyes: (within
    `sds` SD, of how many the run has)."""
    real = _real_eyes()
    inside = [key for key in SHAPE_AND_SPEED if key in summary
              and abs(_SIGN.get(key, 1) * summary[key] - real[key][0]) <= sds * real[key][1]]
    return len(inside), sum(key in summary for key in SHAPE_AND_SPEED)


def markdown(summary):
    """The table: parameter, run, the real eyes (mean +- SD) and z, normal
    eyes (mean +- SD) and z."""
    lines = ["| parameter | run | 202 real eyes (mean +- SD) | z | normal eyes, PMC7001013 "
             "(mean +- SD) | z |", "|---|---|---|---|---|---|"]
    for name, value, unit, against in compare(summary):
        u = f" {unit}" if unit else ""
        cells = []
        for population in ("real eyes", "normal eyes"):
            if against[population]:
                (mean, sd), z = against[population]
                cells += [f"{mean:.4g} +- {sd:.2g}{u}", f"{z:+.1f}"]
            else:
                cells += ["-", ""]
        lines.append(f"| {name} | {value:.4g}{u} | " + " | ".join(cells) + " |")
    n, of = within(summary)
    lines += ["", f"Within 2 SD of the real eyes: {n} of the {of} shape and speed readings."]
    return "\n".join(lines)


# The Corvis Biomechanical Index (Vinciguerra et al. 2016, J Refract Surg
# 32(12):803-810; coefficients as reprinted in Sci. Rep. (2021),
# doi:10.1038/s41598-020-80915-9, Table 4): CBI = e^b / (1 + e^b),
# b = B7 + sum of B_i x_i. (input, coefficient B_i, unit, summary key or
# None when a run cannot give it, why not).
CBI_INTERCEPT = 46.576
CBI_INPUTS = [
    ("A1 velocity (+ inwards)", -59.487, "m/s", "a1_velocity_m_s", None),
    ("ARTh", -0.027, "um", None,
     "Ambrosio's relational thickness (horizontal): the thinnest pachymetry over its "
     "progression, from the device's thickness profile; not a simulated reading"),
    ("SP-A1", -0.092, "mmHg/mm", "sp_a1_mmHg_per_mm", None),
    ("DA ratio 1 mm", -27.169, "", "da_ratio_1mm", None),
    ("DA ratio 2 mm", 5.472, "", "da_ratio_2mm", None),
    ("SD of the deflection amplitude", -0.599, "", None,
     "the device's statistic over its deflection-amplitude curve, whose definition is not "
     "published with the coefficients; not computed"),
]
# The clinic signs velocities + inwards; a run + outwards.
_CBI_SCALE = {"a1_velocity_m_s": -1}


def cbi(summary, measured=None):
    """The CBI where every input exists: (value or None, [(input, value or
    None, unit, where it came from or why it is missing)]). `measured`
    gives inputs a run cannot ({"ARTh": 520.0, ...}), e.g. the patient's."""
    measured = measured or {}
    inputs, b = [], CBI_INTERCEPT
    for name, coefficient, unit, key, missing in CBI_INPUTS:
        if name in measured:
            value, source = float(measured[name]), "measured"
        elif key is not None and key in summary:
            value, source = _CBI_SCALE.get(key, 1) * summary[key], f"run ({key})"
        else:
            value, source = None, missing or f"the run has no {key}"
        inputs.append((name, value, unit, source))
        b = None if value is None or b is None else b + coefficient * value
    return (None if b is None else 1.0 / (1.0 + math.exp(-b))), inputs
