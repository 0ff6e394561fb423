"""What every case's `run` shares (cases/<name>/run): the repository's
paths, the command line, running nct, and the results page.

    args = cases.arguments("benchmark-air", __doc__, ranks=2)   # --out DIR [--ranks N]
    run = cases.nct_run("scenes/default.toml", args.out / "l3", ["mesh.layers=3"], ranks=2)
    study = cases.nct_study("cases/factorial/factorial-2x5.toml", args.out / "factorial-2x5")
    results = cases.Results(args.out)   # results.add(text) prints it and keeps it
    results.add(cases.study_section("cases/ablation-cavity/ablation-cavity.toml", args.out / "s"))
    results.write()                     # DIR/results.md

A run, study or fit whose folder already holds its result is not run
again (a study or fit resumes where it stopped), so a case interrupted
reruns only what is missing.
"""
import argparse
import os
import pathlib
import subprocess
import sys

from .folders import Fit, Run, Study

ROOT = pathlib.Path(__file__).resolve().parents[2]
# The nct that cases run: build/nct, or NCT_PROGRAM's (a copy, so that a
# rebuild while a long case runs does not pull the program from under it).
NCT = pathlib.Path(os.environ.get("NCT_PROGRAM", ROOT / "build" / "nct"))


def environment():
    """The scripts' environment (scripts/env.sh): MPI as root, one BLAS
    thread per rank, the Debian python3 first."""
    env = dict(os.environ)
    env["PATH"] = "/usr/bin:" + env.get("PATH", "")
    env["OPENBLAS_NUM_THREADS"] = "1"
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    return env


def arguments(name, doc, ranks=None, parts=None, extra=None):
    """The case's command line: --out DIR (default runs/cases/NAME),
    --ranks N when the case runs scenes itself (default `ranks`), the
    parts to rerun when the case has several (default all); `extra`
    adds the case's own options to the parser."""
    p = argparse.ArgumentParser(description=doc.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=doc.split("\n\n", 1)[1] if "\n\n" in doc else None)
    p.add_argument("--out", type=pathlib.Path, default=ROOT / "runs" / "cases" / name,
                   help="the runs and results.md (default runs/cases/%s)" % name)
    if ranks is not None:
        p.add_argument("--ranks", type=int, default=ranks, help="MPI ranks per run (default %d)"
                       % ranks)
    if parts:
        p.add_argument("parts", nargs="*", metavar="PART",
                       help="what to rerun: %s (default all)" % ", ".join(parts))
    if extra:
        extra(p)
    args = p.parse_args()
    if parts:
        unknown = [x for x in args.parts if x not in parts]
        if unknown:
            p.error("unknown part %s: one of %s" % (", ".join(unknown), ", ".join(parts)))
        args.parts = args.parts or parts
    args.out = args.out.resolve()
    args.out.mkdir(parents=True, exist_ok=True)
    return args


def _call(command, log):
    with open(log, "w") as f:
        return subprocess.call([str(c) for c in command], stdout=f, stderr=subprocess.STDOUT,
                               env=environment(), cwd=ROOT)


def nct_run(scene, out, sets=(), ranks=1, petsc=None, nct=NCT):
    """`nct run` of a scene (relative to the repository or absolute) into
    out, on `ranks` ranks, with --set overrides and PETSc options; its
    output in out.log. Kept when out has its summary. Returns the Run
    (whose summary is missing when nct stopped before writing one)."""
    out = pathlib.Path(out)
    if not (out / "summary.json").exists():
        print("running %s ..." % out.name, file=sys.stderr, flush=True)
        command = ["mpirun", "-n", ranks, nct, "run", ROOT / scene, "--out", out]
        command += [w for s in sets for w in ("--set", s)]
        command += ["--petsc", petsc] if petsc else []
        out.parent.mkdir(parents=True, exist_ok=True)
        _call(command, out.parent / (out.name + ".log"))
    return Run(out)


def nct_study(study_file, out, jobs=None):
    """`nct study` (resumed where it stopped) into out; its output in
    out.log. Returns the Study."""
    out = pathlib.Path(out)
    print("study %s ..." % out.name, file=sys.stderr, flush=True)
    command = [NCT, "study", ROOT / study_file, "--out", out]
    command += ["--jobs", jobs] if jobs else []
    out.parent.mkdir(parents=True, exist_ok=True)
    _call(command, out.parent / (out.name + ".log"))
    return Study(out)


def nct_fit(fit_file, out):
    """`nct fit` (resumed where it stopped) into out; its output in
    out.log. Returns the Fit (or cohort's folder as a Fit)."""
    out = pathlib.Path(out)
    print("fit %s ..." % out.name, file=sys.stderr, flush=True)
    out.parent.mkdir(parents=True, exist_ok=True)
    _call([NCT, "fit", ROOT / fit_file, "--out", out], out.parent / (out.name + ".log"))
    return Fit(out)


class Results:
    """The case's tables: printed as they come, then DIR/results.md."""

    def __init__(self, out, title=None):
        self.path = pathlib.Path(out) / "results.md"
        self.parts = ["# " + title] if title else []

    def add(self, text):
        print(text + "\n", flush=True)
        self.parts.append(text)

    def write(self):
        self.path.write_text("\n\n".join(self.parts) + "\n")
        print("wrote %s" % self.path)


def study_section(study_file, out, terms=8):
    """Run (or resume) a study into out, plot it (out/plots) and return its
    report as a Markdown section named after the study file."""
    from . import study  # matplotlib only where a case plots

    name = pathlib.Path(study_file).stem
    folder = nct_study(study_file, out)
    if not folder.has("analysis.json"):
        return "## %s\n\nno analysis.json: see %s.log" % (name, out)
    study.plot(out)
    report = study.report(out, terms)
    return "## %s\n\n%s\n\nplots: %s" % (name, report, pathlib.Path(out) / "plots")
