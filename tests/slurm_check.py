"""Studies, fits and one run through a real Slurm: the single-node cluster
that scripts/slurm-cluster.sh starts (the ctest fixture slurm_cluster).

slurm_check.py NCT MODE OUT [REFERENCE]

- study: tests/studies/quick-2x2.toml as Slurm job arrays. (1) One case
  cancelled by the test (scancel) is reported failed by name with
  Slurm's state, the others finish; run again, only it is submitted, and
  every summary equals the local study's (REFERENCE, the study_resume
  test's) to 1e-10. (2) The driver interrupted (SIGINT) cancels what it
  submitted and says so, and resumes. (3) The driver killed (SIGKILL,
  as when a login session ends) leaves its tasks running; started again,
  it follows them instead of submitting them twice.
- fit: the fit_recovery fit with launcher = "slurm" gives the local
  fit's values (REFERENCE, fit_recovery's folder) to 1e-12, straight
  through, interrupted (SIGINT: it cancels what it submitted) and
  resumed, and with its driver killed (it follows its queued runs).
- cohort: the fit_cohort cohort (REFERENCE, its folder) with
  launcher = "slurm": every patient's forward runs go to the cluster as
  job arrays, and the table equals the local cohort's to 1e-12.
- run: one scene on 2 ranks under sbatch and srun --mpi=pmix equals the
  same scene under mpirun -n 2 (the README's multi-node recipe).
- bad: a Slurm launcher Slurm refuses (unknown partition, a bad time
  limit) or cannot reach (no sbatch on the PATH) is an error naming the
  key, exit 2, before anything is submitted.

Exit code 77 (skipped) when the cluster is not up.
"""
import glob
import os
import re
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from nct.folders import read_json  # noqa: E402
from nct.tables import read_csv  # noqa: E402

nct, mode, out = sys.argv[1:4]
reference = sys.argv[4] if len(sys.argv) > 4 else None
root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STUDY = os.path.join(root, "tests", "studies", "quick-2x2.toml")

if not os.environ.get("SLURM_CONF") or subprocess.run(
        ["sinfo", "-h", "-o", "%T"], capture_output=True).returncode != 0:
    print("slurm_check: no Slurm cluster up (SLURM_CONF = %r); skipped"
          % os.environ.get("SLURM_CONF"))
    sys.exit(77)

shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)


def run(args, check=None, **kw):
    r = subprocess.run(args, capture_output=True, text=True, **kw)
    print(r.stdout, r.stderr)
    if check is not None:
        assert r.returncode == check, f"{args[:3]}: exit {r.returncode}, expected {check}"
    return r


def squeue(array):
    """Task -> state of an array job, as squeue still knows it."""
    r = subprocess.run(["squeue", "-h", "-r", "-t", "all", "-j", array, "-o", "%i %T"],
                       capture_output=True, text=True)
    return dict(line.split() for line in r.stdout.splitlines() if line.strip())


def submitted(folder):
    return read_json(os.path.join(folder, "slurm", "submitted.json"))


def alive(state):
    return state in ("PENDING", "RUNNING", "CONFIGURING", "COMPLETING")


def study(folder, *more):
    return [nct, "study", STUDY, "--launcher", "slurm", "--out", folder, "--no-report", *more]


def wait_for(predicate, what, seconds=300):
    deadline = time.time() + seconds
    while not predicate():
        assert time.time() < deadline, "waited %d s for %s" % (seconds, what)
        time.sleep(0.1)


def same_summaries(folder):
    """Every physical response of the study (cases.csv's columns but the
    times and counts) equal in each case's summary."""
    names = [k for k in read_csv(os.path.join(reference, "cases.csv")).columns
             if k not in {"case", "status", "wall_s", "newton_iterations", "step_cuts"}]
    worst = 0.0
    for case in sorted(os.listdir(os.path.join(reference, "cases"))):
        x = read_json(os.path.join(reference, "cases", case, "summary.json"))
        y = read_json(os.path.join(folder, "cases", case, "summary.json"))
        for k in names:
            if k in x or k in y:
                u = x[k]
                d = abs(u - y[k])
                assert d <= max(1e-10 * abs(u), 1e-12), f"{case} {k}: local {u}, Slurm {y[k]}"
                worst = max(worst, d / max(abs(u), 1e-300))
    print("the Slurm study's summaries equal the local study's (largest relative "
          "difference %.1e)" % worst)


def summaries(folder):
    return glob.glob(os.path.join(folder, "cases", "*", "summary.json"))


if mode == "study":
    # (1) One case cancelled by the test, then resumed.
    one = os.path.join(out, "cancelled")
    p = subprocess.Popen(study(one), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wait_for(lambda: os.path.exists(os.path.join(one, "slurm", "submitted.json")), "the submission")
    tasks = submitted(one)
    array = next(iter(tasks.values())).split("_")[0]
    # A running case: Slurm keeps its record (a pending one it forgets).
    wait_for(lambda: "RUNNING" in squeue(array).values(), "a running task")
    last = next(t for t, s in squeue(array).items() if s == "RUNNING")
    last_log = next(log for log, t in tasks.items() if t == last)
    subprocess.run(["scancel", last], check=True)
    text, _ = p.communicate(timeout=600)
    print(text)
    case = os.path.basename(os.path.dirname(last_log))
    assert p.returncode == 3, f"a cancelled case: exit {p.returncode}, expected 3"
    assert re.search(case + r": nct run exited with \d+", text), "the cancelled case is not named"
    assert "ended CANCELLED" in open(last_log).read(), "its log does not say Slurm cancelled it"
    assert len(summaries(one)) == 3
    before = {s: os.stat(s).st_mtime_ns for s in summaries(one)}
    r = run(study(one), check=0)
    assert "(3 already done)" in r.stdout and "submitted 1 job(s)" in r.stdout, r.stdout
    assert all(os.stat(s).st_mtime_ns == t for s, t in before.items()), "a done case ran again"
    same_summaries(one)

    # (2) Interrupted: it cancels what it submitted, and resumes.
    two = os.path.join(out, "interrupted")
    p = subprocess.Popen(study(two), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wait_for(lambda: summaries(two), "a finished case")
    p.send_signal(signal.SIGINT)
    text, _ = p.communicate(timeout=120)
    print(text)
    assert p.returncode == 130, f"interrupted: exit {p.returncode}, expected 130"
    assert "slurm: interrupted: cancelled" in text and "the same command resumes it" in text
    arrays = {t.split("_")[0] for t in submitted(two).values()}
    for a in arrays:
        assert not any(alive(s) for s in squeue(a).values()), f"array {a} still runs: {squeue(a)}"
    r = run(study(two), check=0)
    same_summaries(two)

    # (3) The driver killed (its session ended): started again, it follows
    # its tasks still in the queue instead of submitting them again.
    three = os.path.join(out, "killed")
    p = subprocess.Popen(study(three, "--jobs", "1"), stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True)
    wait_for(lambda: os.path.exists(os.path.join(three, "slurm", "submitted.json"))
             and any(alive(s) for s in squeue(next(iter(submitted(three).values())).split("_")[0]).values()),
             "a queued task")
    p.kill()
    p.communicate()
    queued = {t for t, s in squeue(next(iter(submitted(three).values())).split("_")[0]).items()
              if alive(s)}
    assert queued, "no task left in the queue to follow"
    r = run(study(three), check=0)
    assert "followed, not submitted again" in r.stdout, r.stdout
    assert "submitted" not in r.stdout.replace("not submitted again", ""), \
        "it submitted again what was queued"
    same_summaries(three)
elif mode == "fit":
    shutil.copytree(os.path.join(reference, "data"), os.path.join(out, "data"))
    fit_text = open(os.path.join(reference, "fit.toml")).read()
    fit_text = fit_text.replace("jobs = 2", 'jobs = 2\nlauncher = "slurm"')
    path = os.path.join(out, "fit.toml")
    open(path, "w").write(fit_text)
    ref = {p["label"]: p for p in read_json(os.path.join(reference, "fit", "fit.json"))["parameters"]}

    def same_fit(folder):
        got = {p["label"]: p for p in read_json(os.path.join(folder, "fit.json"))["parameters"]}
        for label, p in got.items():
            d = abs(p["value"] - ref[label]["value"])
            print("%s: Slurm %.12g, local %.12g" % (label, p["value"], ref[label]["value"]))
            assert d <= 1e-12 * abs(ref[label]["value"]), label

    # Straight through.
    r = run([nct, "fit", path, "--out", os.path.join(out, "fit")], check=0)
    assert "slurm: submitted" in r.stdout
    same_fit(os.path.join(out, "fit"))
    # Interrupted after its fourth forward run: it cancels what it
    # submitted; the same command resumes without redoing a finished run.
    folder = os.path.join(out, "interrupted")
    p = subprocess.Popen([nct, "fit", path, "--out", folder], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True)
    wait_for(lambda: os.path.exists(os.path.join(folder, "runs", "run-0004", "summary.json")),
             "the fourth forward run")
    p.send_signal(signal.SIGINT)
    text, _ = p.communicate(timeout=120)
    print(text)
    assert p.returncode == 130, f"interrupted: exit {p.returncode}, expected 130"
    assert "slurm: interrupted: cancelled" in text
    for a in {t.split("_")[0] for t in submitted(folder).values()}:
        assert not any(alive(s) for s in squeue(a).values()), f"array {a} still runs"
    r = run([nct, "fit", path, "--out", folder], check=0)
    same_fit(folder)
    # The driver killed (its session ended) with forward runs queued:
    # started again, it follows them instead of running them twice.
    one_at_a_time = os.path.join(out, "fit-one.toml")
    open(one_at_a_time, "w").write(fit_text.replace("jobs = 2", "jobs = 1"))
    folder = os.path.join(out, "killed")
    p = subprocess.Popen([nct, "fit", one_at_a_time, "--out", folder], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True)
    record = os.path.join(folder, "slurm", "submitted.json")
    wait_for(lambda: os.path.exists(record) and any(
        alive(s) for t in submitted(folder).values() for s in squeue(t.split("_")[0]).values()),
        "a queued forward run")
    p.kill()
    p.communicate()
    r = run([nct, "fit", one_at_a_time, "--out", folder], check=0)
    assert "followed, not submitted again" in r.stdout, r.stdout
    same_fit(folder)
elif mode == "cohort":
    shutil.copytree(os.path.join(reference, "data"), os.path.join(out, "data"))
    text = open(os.path.join(reference, "cohort.toml")).read()
    path = os.path.join(out, "cohort.toml")
    open(path, "w").write(text.replace("jobs = 2", 'jobs = 2\nlauncher = "slurm"'))
    folder = os.path.join(out, "fit")
    r = run([nct, "fit", path, "--out", folder], check=0)
    local = {row["patient"]: row for row in read_csv(os.path.join(reference, "fit", "cohort.csv"), numeric=False).rows()}
    rows = read_csv(os.path.join(folder, "cohort.csv"), numeric=False).rows()
    assert sorted(local) == sorted(row["patient"] for row in rows)
    for row in rows:
        log = open(os.path.join(folder, "patients", row["patient"], "fit.log")).read()
        assert "slurm: submitted" in log, log
        for label in ("c10_cornea", "iop"):
            a, b = float(row[label]), float(local[row["patient"]][label])
            print("%s %s: Slurm %.12g, local %.12g" % (row["patient"], label, a, b))
            assert abs(a - b) <= 1e-12 * abs(b), (row["patient"], label)
elif mode == "run":
    scene = os.path.join(root, "tests", "scenes", "sphere_inflation.toml")
    local = os.path.join(out, "mpirun")
    # Linear elements: the launcher's property, in a second (P2: 20 s).
    linear = ["--set", "fem.degree=1"]
    run(["mpirun", "-n", "2", "--oversubscribe", "--allow-run-as-root", nct, "run", scene,
         *linear, "--out", local], check=0)
    slurm = os.path.join(out, "srun")
    script = os.path.join(out, "run.sh")
    open(script, "w").write("#!/bin/sh\n#SBATCH --ntasks=2\n#SBATCH --cpus-per-task=1\n"
                            "srun --mpi=pmix -n 2 %s run %s %s --out %s\n" % (nct, scene, " ".join(linear), slurm))
    job = run(["sbatch", "--parsable", "--wait", "-o", os.path.join(out, "slurm-%j.out"),
               script], check=0).stdout.strip()
    x = read_json(os.path.join(local, "summary.json"))
    y = read_json(os.path.join(slurm, "summary.json"))
    assert y["ranks"] == 2, y["ranks"]
    # The same partition and solver; the reductions' order may differ:
    # round-off, relative to each quantity's size (a probe's components
    # that vanish by symmetry carry round-off of its displacement's).
    def numbers(v):
        return [w for u in v.values() for w in u] if isinstance(v, dict) else [v]
    for k in ("probe_displacement_mm", "cavity_volume_mm3", "cavity_pressure_mmHg"):
        size = max(abs(u) for u in numbers(x[k]))
        for u, v in zip(numbers(x[k]), numbers(y[k])):
            assert abs(u - v) <= 1e-12 * size, f"{k}: mpirun {x[k]}, srun {y[k]}"
    print("job %s: the scene on 2 ranks under sbatch and srun equals mpirun -n 2" % job)
elif mode == "bad":
    def refused(args, pattern, env=None):
        r = run(args, env=env)
        assert r.returncode == 2, f"exit {r.returncode}, expected 2"
        assert re.search(pattern, r.stderr), f"no '{pattern}' in: {r.stderr}"
        assert not os.path.exists(os.path.join(out, "slurm")), "something was submitted"

    text = open(STUDY).read().replace('"../../scenes/', '"' + os.path.join(root, "scenes") + "/")
    for name, table, pattern in [
            ("partition", 'partition = "nope"', r"key 'study.slurm.partition': Slurm knows no partition 'nope'"),
            ("time", 'time_limit = "soon"', r"key 'study.slurm.time_limit': Slurm refuses")]:
        path = os.path.join(out, name + ".toml")
        open(path, "w").write(text.replace("jobs = 2", 'jobs = 2\nlauncher = "slurm"') + "\n[study.slurm]\n" + table + "\n")
        refused([nct, "study", path, "--out", out], pattern)
    refused([nct, "study", STUDY, "--launcher", "slurm", "--out", out],
            r"key 'study.launcher': \"slurm\" needs Slurm's sbatch",
            env=dict(os.environ, PATH="/nonexistent"))
else:
    sys.exit("unknown mode " + mode)
print("slurm_check %s: ok" % mode)
