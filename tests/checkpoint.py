"""Checkpoint and restart (issue 21): a run killed (SIGKILL) at a random step
and resumed from its last checkpoint, on the same or another rank count,
ends as the uninterrupted run does; a kill while a checkpoint is being
written leaves the previous one usable; foreign and damaged checkpoints are
refused, and so is a damaged field file, whose series starts anew once it
is moved aside.

usage: checkpoint.py NCT COMPARE_SUMMARIES OUT RANKS_FIRST RANKS_RESUME SCENE
                     [KEY=VALUE...]

On 1 rank resumed on 1: every number of summary.json and every CSV equal,
bitwise (checkpoint boundaries drop the kept factorisation in both runs,
and a serial run is reproducible). Otherwise to 1e-8 relative or 1e-9
absolute, the tolerance the 1- and 2-rank runs agree to (with
solver.atol = 1e-11 N): on 2 ranks even two uninterrupted runs differ at
round-off (MUMPS' parallel factorisation sums in the order messages
arrive), which the Newton tolerance turns into about 1e-10.
The XDMF fields (output.fields) are compared step by step: the same
times, and at each the same values at the same points (nodes, or cells'
centroids, matched by position across rank counts); every dataset of their
HDF5 files is one the XML refers to (a resumed run deletes what it wrote
after its checkpoint). The comparisons are tests/compare_runs.py's, which
also compares two runs by hand.
NCT_TEST_SEED fixes the random step."""
import os
import random
import re
import shutil
import subprocess
import sys

import h5py

from compare_runs import agree, agree_fields, rows

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from nct.folders import read_json  # noqa: E402

nct, compare, out, ranks_first, ranks_resume, scene = sys.argv[1:7]
sets = [a for kv in sys.argv[7:] for a in ("--set", kv)]
ranks_first, ranks_resume = int(ranks_first), int(ranks_resume)
same = ranks_first == ranks_resume
exact = same and ranks_first == 1
shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)
seed = int(os.environ.get("NCT_TEST_SEED", random.randrange(1 << 30)))
rng = random.Random(seed)
print(f"seed {seed} (NCT_TEST_SEED reproduces this run)")


def nct_run(ranks, folder, *extra, env=None, expect=0, resume=False):
    # A failed rank takes the others down at once (Open MPI waits 2 s by
    # default); one rank runs without mpirun.
    launcher = ["mpirun", "-n", str(ranks), "--allow-run-as-root", "--oversubscribe",
                "--mca", "odls_base_sigkill_timeout", "0"]
    cmd = (launcher if ranks > 1 else []) + [nct, "run", scene, *sets, *extra,
                                             "--no-report",
                                             "--resume" if resume else "--out", folder]
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       env={**os.environ, **(env or {})})
    ok = p.returncode == expect if expect is not None else p.returncode != 0
    if not ok:
        print(p.stdout)
        sys.exit(f"FAIL: {' '.join(cmd)} exited {p.returncode}")
    return p.stdout


def error_line(text):
    return next(line for line in text.splitlines() if line.startswith("error"))


# The uninterrupted run, with checkpoints on (their boundaries are part of
# the run: each drops the kept factorisation).
ref = f"{out}/uninterrupted"
nct_run(ranks_first, ref)
steps_total = len(rows(f"{ref}/steps.csv")) - 1
written = sorted(f for f in os.listdir(f"{ref}/checkpoint") if f.endswith(".h5"))
print(f"uninterrupted: {steps_total} dynamic steps, checkpoints kept {written}")

# Killed at a random step after the first checkpoint, resumed.
# Killed after the first checkpoint (a march's boundary: the rest may hold
# none): its step in the run's numbering less the quasi-static steps.
recorded = read_json(f"{ref}/summary.json")["steps"]
quasi_static = len(recorded) - steps_total
first = int(re.search(r"^checkpoint: step (\d+)", open(f"{ref}/run.log").read(), re.M)[1])
kill = rng.randrange(first - quasi_static + 1, steps_total)
killed = f"{out}/killed"
text = nct_run(ranks_first, killed, env={"NCT_TEST_KILL_AT_STEP": str(kill)}, expect=None)
if os.path.exists(f"{killed}/summary.json"):
    print(text)
    sys.exit(f"FAIL: the run to be killed at dynamic step {kill} wrote a summary (status "
             + read_json(f"{killed}/summary.json").get("status", "?") + ")")
print(f"killed at dynamic step {kill} on {ranks_first} rank(s); latest checkpoint: "
      + open(f"{killed}/checkpoint/latest").read().strip())
text = nct_run(ranks_resume, killed, resume=True)
assert "resume:" in text
print(f"resumed on {ranks_resume} rank(s)")
agree(compare, killed, ref, exact)
agree_fields(killed, ref, exact)

# Killed while writing its second checkpoint: the first stays the latest.
torn = f"{out}/killed_writing"
nct_run(ranks_first, torn, env={"NCT_TEST_KILL_IN_CHECKPOINT": "2"}, expect=None)
tmp = [f for f in os.listdir(f"{torn}/checkpoint") if f.endswith(".tmp")]
assert tmp, "the kill during the write left no temporary file"
first = open(f"{torn}/checkpoint/latest").read().strip()
print(f"killed while writing {tmp[0]}; latest: {first}")
nct_run(ranks_resume, torn, resume=True)
assert not [f for f in os.listdir(f"{torn}/checkpoint") if f.endswith(".tmp")], \
    "the temporary file of the cut write is still there"
agree(compare, torn, ref, exact)
agree_fields(torn, ref, exact)

if same:
    # Refused: another scene, other PETSc options, no checkpoint, a damaged
    # and a truncated file (exit code 2, the reason named).
    for extra, why in [(["--set", "solver.rtol=3.3e-9"], "another scene"),
                       (["--petsc", "-mat_mumps_icntl_14 40"], "other --petsc")]:
        text = nct_run(ranks_resume, ref, *extra, expect=2, resume=True)
        assert why in text, text
        print(f"refused ({why}): " + error_line(text))
    os.makedirs(f"{out}/empty")
    text = nct_run(ranks_resume, f"{out}/empty", expect=2, resume=True)
    assert "no checkpoint to resume from" in text, text
    latest = open(f"{ref}/checkpoint/latest").read().strip()
    for damage in ("flip", "truncate"):
        bad = f"{out}/{damage}"
        shutil.copytree(ref, bad)
        path = f"{bad}/checkpoint/{latest}"
        data = bytearray(open(path, "rb").read())
        if damage == "flip":
            # A bit of the displacement's values (a stored byte, not padding).
            with h5py.File(path, "r") as f:
                u = f["fields/solid/u/values" if "fields/solid" in f else "fields/air/up/values"]
                i = u.id.get_offset() + rng.randrange(u.id.get_storage_size())
            data[i] ^= 0x10
        else:
            data = data[: len(data) // 2]
        open(path, "wb").write(bytes(data))
        text = nct_run(ranks_resume, bad, expect=2, resume=True)
        assert "is damaged" in text, text
        print(f"refused ({damage}): " + error_line(text))

    # A field file a kill left unreadable: the resume refuses it, naming it;
    # with its series moved aside, the series starts anew at the checkpoint
    # (the older of the two kept: steps are left to write).
    xdmf = sorted(f for f in os.listdir(ref) if f.endswith(".xdmf") and "geometry" not in f
                  and not f.startswith("fibre"))
    if xdmf:
        bad = f"{out}/damaged_fields"
        shutil.copytree(ref, bad)
        os.remove(f"{bad}/summary.json")
        older = sorted(f for f in os.listdir(f"{bad}/checkpoint") if f.endswith(".h5"))[0]
        open(f"{bad}/checkpoint/latest", "w").write(older + "\n")
        h5 = f"{bad}/{xdmf[0][:-len('.xdmf')]}.h5"
        data = open(h5, "rb").read()
        open(h5, "wb").write(data[: len(data) // 3])
        text = nct_run(ranks_resume, bad, expect=2, resume=True)
        assert "cannot continue the fields file" in text and xdmf[0] in text, text
        print("refused (a damaged field file): " + error_line(text))
        os.remove(h5)
        os.remove(f"{bad}/{xdmf[0]}")
        nct_run(ranks_resume, bad, resume=True)
        times = [float(t) for t in re.findall(r'<Time Value="([^"]+)"', open(f"{bad}/{xdmf[0]}").read())]
        march = read_json(f"{bad}/summary.json")["resumed"]
        assert times and min(times) > 0, f"{xdmf[0]} did not start anew: {times[:3]}"
        print(f"{xdmf[0]} moved aside: starts anew at t = {min(times)} ms "
              f"({len(times)} steps; resumed from {march['file']})")
print("checkpoint: ok")
