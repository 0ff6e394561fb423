"""A study interrupted and resumed: nothing finished is redone.

study_resume.py NCT STUDY OUT

Starts `nct study` on a 2^2 study of the default scene's section, interrupts it
(SIGINT) once a case has finished, and checks that it stopped its runs
(exit 130, no nct left behind) with the finished cases on disk. Run again,
it must run only the rest (the finished summaries untouched) and analyse
every response; a third run must run nothing; a different study must not
write into the same folder.
"""
import glob
import os
import shutil
import subprocess
import sys
import time

from study_interrupt import interrupt_after_first_case

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from nct.folders import read_json  # noqa: E402
from nct.tables import read_csv  # noqa: E402

nct, study, out = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(out, ignore_errors=True)


def study_run(args=(), check=None):
    r = subprocess.run([nct, "study", study, "--out", out, *args], capture_output=True, text=True)
    print(r.stdout, r.stderr)
    if check is not None:
        assert r.returncode == check, f"nct study exited with {r.returncode}, expected {check}"
    return r


def left_behind():
    """Processes whose command line names the study folder (from /proc)."""
    found = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            cmd = open(f"/proc/{pid}/cmdline", "rb").read().replace(b"\0", b" ").decode()
        except OSError:
            continue
        if out in cmd and int(pid) != os.getpid():
            found.append(f"{pid}: {cmd}")
    return found


# 1. Interrupt once a case has finished.
interrupt_after_first_case(nct, study, out)
time.sleep(0.5)
assert not left_behind(), f"processes left running: {left_behind()}"
done = {f: os.stat(f).st_mtime_ns for f in glob.glob(os.path.join(out, "cases", "*", "summary.json"))}
assert 1 <= len(done) < 4, f"{len(done)} cases finished before the interruption"
status = [row["status"] for row in read_csv(os.path.join(out, "cases.csv"), numeric=False).rows()]
assert status.count("converged") == len(done) and status.count("pending") == 4 - len(done), status

# 2. Resume: only the rest runs.
r = study_run(check=0)
assert f"4 cases ({len(done)} already done)" in r.stdout
for f, mtime in done.items():
    assert os.stat(f).st_mtime_ns == mtime, f"{f} was redone"
rows = read_csv(os.path.join(out, "cases.csv"), numeric=False).rows()
assert [row["status"] for row in rows] == ["converged"] * 4
# Every response the study file may name is in some run's summary (the
# applanations need not happen: the stiff eye at 18 mmHg does not flatten).
summaries = [read_json(f) for f in glob.glob(os.path.join(out, "cases", "*", "summary.json"))]
analysis = read_json(os.path.join(out, "analysis.json"))
for name in analysis["responses"]:
    assert any(isinstance(s.get(name), (int, float)) for s in summaries), f"no run gave {name}"

# 3. Nothing left to run: the analysis alone.
summaries_at = {f: os.stat(f).st_mtime_ns
                for f in glob.glob(os.path.join(out, "cases", "*", "summary.json"))}
r = study_run(["--no-report"], check=0)
assert "4 cases (4 already done)" in r.stdout
assert {f: os.stat(f).st_mtime_ns for f in summaries_at} == summaries_at, "a case was redone"

# 4. Another study must not mix into this folder.
other = os.path.join(out, "other.toml")
open(other, "w").write(open(study).read().replace("12.0, 18.0", "10.0, 18.0")
                       .replace('"../../scenes/', '"' + os.path.dirname(os.path.abspath(study)) + "/../../scenes/"))
r = subprocess.run([nct, "study", other, "--out", out], capture_output=True, text=True)
print(r.stdout, r.stderr)
assert r.returncode == 2 and "holds another study" in r.stderr
print("study_resume: interrupted, resumed without redoing", len(done), "finished case(s)")
