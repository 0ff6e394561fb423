#!/usr/bin/python3
"""The hard-case matrix's outcomes as a table: docs/hard-cases.md.

    scripts/hard-cases.py [--run]

--run first runs the cases (scripts/test.sh -L hard: every case on 2 ranks,
three of them also serially); then the outcome.json that tests/hard_case.py
left in each build/test-runs/hard/np<ranks>/<case> becomes a Markdown
table between the markers of docs/hard-cases.md.
"""
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RUNS = os.path.join(ROOT, "build", "test-runs", "hard")
DOC = os.path.join(ROOT, "docs", "hard-cases.md")
BEGIN, END = "<!-- hard-cases:begin -->", "<!-- hard-cases:end -->"

# What each case changes (tests/CMakeLists.txt holds the keys).
CASES = {
    "reference": "scenes/puff-gaussian.toml as shipped (kappa/mu = 50, k2 = 100, IOP 15 mmHg)",
    "bulk_1e2": "kappa/mu = 1e2 in every tissue",
    "bulk_1e3": "kappa/mu = 1e3",
    "bulk_1e4": "kappa/mu = 1e4",
    "bulk_1e4_mixed": "kappa/mu = 1e4, mixed u-p (P2/P0)",
    "k2_500": "fibre nonlinearity k2 = 500 (cornea, limbus)",
    "iop_0": "IOP 0 mmHg (unpressurised)",
    "iop_5": "IOP 5 mmHg",
    "iop_40": "IOP 40 mmHg (glaucoma)",
    "thin_0.35mm": "central thickness 0.35 mm (post-surgery)",
    "puff_x2": "puff peak x2 (130 mmHg)",
    "dt_x4": "time step x4 (2 ms)",
    "dt_div4": "time step /4 (0.125 ms)",
    "coarsest_p1": "degree 1 on the 3-layer mesh (coarsest)",
    "air_inlet_x2": "air: inlet x2 (240 m/s), coarsest air mesh",
    "air_dt_x4": "air: time step x4 (0.4 ms), coarsest air mesh",
    "section_reference": "two-way puff on the axisymmetric section (scenes/puff-fsi.toml)",
    "section_soft_5": "two-way, section: cornea and limbus 5x softer",
    "section_stiff_5": "two-way, section: cornea and limbus 5x stiffer",
    "section_iop_8": "two-way, section: IOP 8 mmHg",
    "section_iop_40": "two-way, section: IOP 40 mmHg",
    "section_thin_0.35mm": "two-way, section: central thickness 0.35 mm",
    "section_jet_x1.5": "two-way, section: the jet 1.5x faster (180 m/s)",
    "section_coarse_air": "two-way, section: coarse air mesh (0.4 / 0.26 mm)",
    "section_dt_1ms": "two-way, section: steps of 1 ms (4x)",
}


def number(outcome, key, fmt="%.3f"):
    v = outcome.get(key)
    return fmt % v if isinstance(v, (int, float)) else ""


def row(ranks, name, o):
    if o is None:
        return f"| {name} | {ranks} | {CASES.get(name, '')} | not run | | | | | | | | | |"
    converged = o["exit_code"] == 0
    outcome = "converged" if converged else "failed: " + short(o.get("error", ""))
    air = "stagnation_pressure_mmHg" in o and "deflection_amplitude_mm" not in o
    return "| " + " | ".join([
        name, str(ranks), CASES.get(name, ""), outcome,
        number(o, "newton_iterations", "%d"), number(o, "step_cuts", "%d"),
        "%.0f" % o["wall_s"],
        "" if air else number(o, "deflection_amplitude_mm"),
        "" if air else number(o, "peak_distance_mm", "%.2f"),
        number(o, "a1_time_ms", "%.2f"), number(o, "hc_time_ms", "%.2f"),
        number(o, "a2_time_ms", "%.2f"),
        number(o, "apex_pressure_max_mmHg", "%.1f") if air else number(o, "iop_max_mmHg", "%.1f"),
    ]) + " |"


def short(error):
    """The diagnosis without the residual history."""
    text = error.split("; residuals:")[0]
    return text.replace("|", "/")


def table():
    lines = ["| case | ranks | change | outcome | Newton | cuts | wall s | DA mm | PD mm "
             "| A1 ms | HC ms | A2 ms | IOP max (air: apex) mmHg |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for ranks in (2, 1):
        for name in CASES:
            path = os.path.join(RUNS, f"np{ranks}", name, "outcome.json")
            if not os.path.exists(path):
                if ranks == 2:
                    lines.append(row(ranks, name, None))
                continue
            with open(path) as f:
                lines.append(row(ranks, name, json.load(f)))
    return "\n".join(lines)


def main():
    if "--run" in sys.argv[1:]:
        subprocess.run(["sh", os.path.join(ROOT, "scripts", "test.sh"), "-L", "hard"])
    with open(DOC) as f:
        text = f.read()
    head, rest = text.split(BEGIN)
    _, tail = rest.split(END)
    with open(DOC, "w") as f:
        f.write(head + BEGIN + "\n" + table() + "\n" + END + tail)
    print(table())


main()
