"""Reports as web pages: `nct report DIR` (python3 -m nct.report DIR)
writes DIR/report.html, one self-contained page (style, script and figures
inline; no network) for a run, a study, a fit or a cohort.

    path = write("runs/default")          # the kind from the folder's files
    kind("fits/synthetic")                # "run", "study", "fit" or "cohort"

Modules: page (the page, its sections, tables and inline SVG figures),
run, study, fit, cohort (each kind's page; the figures come from
nct.puff, nct.study, nct.fit, nct.cohort_figures and nct.posterior).
"""
import pathlib


class NotAReportFolder(ValueError):
    """The folder holds none of the files nct writes."""


def kind(folder):
    """What nct wrote into the folder: cohort (cohort.csv), fit (fit.json),
    study (analysis.json or cases.csv), run (summary.json)."""
    folder = pathlib.Path(folder)
    for name, what in (("cohort.csv", "cohort"), ("fit.json", "fit"),
                       ("analysis.json", "study"), ("cases.csv", "study"),
                       ("summary.json", "run")):
        if (folder / name).is_file():
            return what
    raise NotAReportFolder(f"{folder}: no summary.json, cases.csv, fit.json or cohort.csv "
                           "(not a run, study, fit or cohort folder nct wrote)")


def write(folder, out=None):
    """The folder's page into out (default DIR/report.html); returns its path."""
    from . import cohort, fit, run, study
    folder = pathlib.Path(folder)
    module = {"run": run, "study": study, "fit": fit, "cohort": cohort}[kind(folder)]
    return module.page(folder).write(out or folder / "report.html")
