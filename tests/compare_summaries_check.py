"""compare_summaries checks every entry of summary.json: a DCR parameter,
a nested entry, a step's value, a key only one side has and a status each
make it fail; the run's measures (wall times, memory, solver effort) alone
do not.

usage: compare_summaries_check.py COMPARE_SUMMARIES DIR"""
import copy
import json
import os
import subprocess
import sys

compare, folder = sys.argv[1], sys.argv[2]
os.makedirs(folder, exist_ok=True)
base = {
    "status": "converged", "ranks": 1, "wall_s": 12.5, "newton_iterations": 40,
    "hc_time_ms": 10.1, "a2_deflection_mm": 0.31, "sp_a1_mmHg_per_mm": 87.5,
    "da_ratio_2mm": 3.9, "air": {"centreline_peak_m_s": {"2mm": 117.0}},
    "steps": [{"time": 0.1, "apex_displacement_mm": [0.0, -0.01, 0.0], "residual_N": 1e-10}],
    "timings_s": {"assemble": 1.0}, "profile": [{"phase": "puff", "wall_s": 3.0}],
}


def verdict(b):
    for name, summary in (("a", base), ("b", b)):
        json.dump(summary, open(f"{folder}/{name}.json", "w"))
    p = subprocess.run([compare, f"{folder}/a.json", f"{folder}/b.json", "1e-8", "1e-12"],
                       stdout=subprocess.PIPE, text=True)
    return p.returncode, p.stdout


def changed(edit):
    b = copy.deepcopy(base)
    edit(b)
    return b


must_fail = {
    "a DCR parameter": lambda b: b.update(a2_deflection_mm=0.31 * (1 + 1e-6)),
    "the SP-A1": lambda b: b.update(sp_a1_mmHg_per_mm=87.6),
    "a nested entry": lambda b: b["air"]["centreline_peak_m_s"].update({"2mm": 117.1}),
    "a step's value": lambda b: b["steps"][0]["apex_displacement_mm"].__setitem__(1, -0.011),
    "a key the second lacks": lambda b: b.pop("da_ratio_2mm"),
    "a key the first lacks": lambda b: b.update(iop_max_mmHg=20.0),
    "the status": lambda b: b.update(status="failed"),
}
failures = 0
for what, edit in must_fail.items():
    code, out = verdict(changed(edit))
    ok = code == 1
    failures += not ok
    print(f"{'ok  ' if ok else 'FAIL'} {what}: exit {code}")
measures = changed(lambda b: b.update(wall_s=99.0, newton_iterations=41, ranks=2,
                                      timings_s={"assemble": 7.0}, profile=[]))
measures["steps"][0]["residual_N"] = 3e-11
code, out = verdict(measures)
failures += code != 0
print(f"{'ok  ' if code == 0 else 'FAIL'} the run's measures alone: exit {code}")
sys.exit(1 if failures else 0)
