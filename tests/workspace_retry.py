"""MUMPS short of workspace (INFOG(1) = -8, -9, ...: its analysis's
estimate falls short when pivoting delays more pivots than planned, which
on several ranks depends on round-off): Newton raises ICNTL(14) and
factorises the same matrix again instead of failing the step. MUMPS cannot
be made to fall short at will, so the test forces two such retries on good
factorisations (NCT_TEST_MUMPS_RETRY=2) of a short puff on 2 ranks: each
is said (20 -> 40 -> 80 %), costs one factorisation more, and the run ends
as the one without: every number to 1e-8 relative or, for the values that
pass through zero (the whole eye's motion, 5e-4 mm), 1e-9 absolute (mm,
mmHg, ms), the footprint of the Newton tolerance, as ranks_agree_puff;
two runs on 2 ranks differ at round-off since the assembly's
contributions arrive in a varying order. MUMPS does fall short on its own
now and then on this very run (INFOG(1) = -9 at the first factorisation,
seen in CI and here): such a real retry is said too, doubles the same
allowance, and counts among the factorisations; the test allows for it
in either run and says when it met one.

workspace_retry.py NCT COMPARE_SUMMARIES SCENE OUT
"""
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from nct.folders import read_json  # noqa: E402

nct, compare, scene, out = sys.argv[1:5]
shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)


def run(folder, env):
    p = subprocess.run(["mpirun", "-n", "2", "--allow-run-as-root", "--oversubscribe", nct, "run",
                        scene, "--set", "mesh.layers=2", "--set", "puff.duration=2.0", "--out",
                        folder, "--no-report"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       env={**os.environ, **env})
    print(p.stdout)
    assert p.returncode == 0, f"exit {p.returncode}"
    return p.stdout, read_json(os.path.join(folder, "summary.json"))


def retries(text):
    """The workspace lines' (from, to) allowances [%], and how many of them were forced."""
    lines = [l for l in text.splitlines() if "MUMPS ran short of workspace" in l]
    steps = [tuple(int(v) for v in re.search(r"from (\d+) to (\d+) %", l).groups())
             for l in lines]
    return steps, sum("(a test's retry)" in l for l in lines)


text, retried = run(os.path.join(out, "retried"), {"NCT_TEST_MUMPS_RETRY": "2"})
plain_text, plain = run(os.path.join(out, "plain"), {})
steps, forced = retries(text)
plain_steps, _ = retries(plain_text)
real, plain_real = len(steps) - forced, len(plain_steps)
assert forced == 2, f"{forced} forced retries said, expected 2"
expected = [(20 * 2**i, 40 * 2**i) for i in range(len(steps))]
assert steps == expected, f"allowances {steps}, expected each doubled from 20 %: {expected}"
assert plain_steps == expected[:len(plain_steps)], plain_steps
assert retried["factorisations"] - len(steps) == plain["factorisations"] - len(plain_steps), (
    retried["factorisations"], len(steps), plain["factorisations"], len(plain_steps))
if real or plain_real:
    print(f"MUMPS fell short on its own too: {real} time(s) in the forced run, {plain_real} in the "
          "plain one; each retried as the forced ones")
subprocess.run([compare, os.path.join(out, "retried", "summary.json"),
                os.path.join(out, "plain", "summary.json"), "1e-8", "1e-9"], check=True)
print("workspace retry: OK")
