"""Readers of the folders nct writes: a run (`nct run`), a study (`nct
study`), a fit and a cohort (`nct fit`). Each file is read once, when
first asked for.

    run = Run("runs/default")
    run.summary["deflection_amplitude_mm"]      # summary.json
    run.frames["apex_displacement_mm"]          # frames.csv (tables.Table)
    run.profiles.curve(k, "anterior")           # profiles.csv: frame k's (x, y), sorted by x
    run.steps, run.forces, run.scene            # steps.csv, forces.csv, scene.toml
    Study("studies/factorial-2x5").cases        # cases.csv; .case("case-001") is a Run
    Fit("fits/synthetic").result                # fit.json; .best_run, .run("run-0001")
    Cohort("fits/synthetic-cohort").table       # cohort.csv; .patient("P01") is a Fit
"""
import functools
import json
import pathlib
import tomllib

import numpy as np

from .tables import read_csv


def read_json(path):
    with open(path) as f:
        return json.load(f)


def read_summary(path):
    """A run's summary.json, from the run's folder or the file itself."""
    path = pathlib.Path(path)
    return read_json(path / "summary.json" if path.is_dir() else path)


class Profiles:
    """profiles.csv parsed once: per frame (in time order) and surface, the
    section's x and y sorted by x."""

    def __init__(self, table):
        frame = table["frame"].astype(int)
        self.frames = sorted(set(frame.tolist()))
        self.t_ms = np.array([table["t_ms"][frame == k][0] for k in self.frames])
        self.surfaces = sorted(set(table["surface"].tolist()))
        self._curves = {}
        for surface in self.surfaces:
            on = table.where(table["surface"] == surface)
            k_on = on["frame"].astype(int)
            for k in self.frames:
                x, y = on["x_mm"][k_on == k], on["y_mm"][k_on == k]
                order = np.argsort(x, kind="stable")
                self._curves[k, surface] = (x[order], y[order])

    def __len__(self):
        return len(self.frames)

    def curve(self, index, surface="anterior"):
        """(x, y) of the index-th frame (0 = the first) on a surface."""
        return self._curves[self.frames[index], surface]

    def nearest(self, t_ms):
        """The index of the frame nearest a time."""
        return int(np.argmin(np.abs(self.t_ms - t_ms)))

    def height(self, index, x, surface="anterior"):
        """y at x of a frame's profile, linear between the points."""
        xs, ys = self.curve(index, surface)
        return np.interp(x, xs, ys)


class Run:
    """An `nct run` folder."""

    def __init__(self, folder):
        self.folder = pathlib.Path(folder)
        self.name = self.folder.name

    def has(self, name):
        return (self.folder / name).is_file()

    @property
    def finished(self):
        """Whether the run wrote its summary (converged or failed)."""
        return self.has("summary.json")

    def table(self, name):
        """Any CSV of the run (corneal_pressure.csv, probes.csv...)."""
        return read_csv(self.folder / name)

    @functools.cached_property
    def summary(self):
        return read_json(self.folder / "summary.json")

    @functools.cached_property
    def frames(self):
        return self.table("frames.csv")

    @functools.cached_property
    def profiles(self):
        return Profiles(self.table("profiles.csv"))

    @functools.cached_property
    def steps(self):
        return self.table("steps.csv")

    @functools.cached_property
    def forces(self):
        return self.table("forces.csv")

    @functools.cached_property
    def scene(self):
        """The resolved scene the run ran (scene.toml)."""
        with open(self.folder / "scene.toml", "rb") as f:
            return tomllib.load(f)

    @functools.cached_property
    def sets(self):
        """The overrides a study's case or a fit's forward run was given."""
        for name in ("case.json", "run.json"):
            if self.has(name):
                return read_json(self.folder / name).get("sets", [])
        return []


class Study:
    """An `nct study` folder."""

    def __init__(self, folder):
        self.folder = pathlib.Path(folder)

    def has(self, name):
        return (self.folder / name).is_file()

    def table(self, name):
        """A table of the study (None when it did not write it)."""
        return read_csv(self.folder / name) if self.has(name) else None

    @functools.cached_property
    def cases(self):
        return read_csv(self.folder / "cases.csv")

    @functools.cached_property
    def analysis(self):
        return read_json(self.folder / "analysis.json")

    @functools.cached_property
    def spec(self):
        """The study file as run (study.toml; {} without it)."""
        if not self.has("study.toml"):
            return {}
        with open(self.folder / "study.toml", "rb") as f:
            return tomllib.load(f)

    @property
    def factors(self):
        """The study file's factor labels."""
        return [f["label"] for f in self.spec.get("factor", [])]

    @property
    def responses(self):
        """The analysed responses (a table design: the study file's), in
        the order of cases.csv."""
        known = self.analysis.get("responses", self.spec.get("study", {}).get("responses", []))
        return [c for c in self.cases.columns if c in known]

    @functools.cached_property
    def correlation(self):
        """(names, matrix) of correlation.csv, or None."""
        table = self.table("correlation.csv")
        if table is None:
            return None
        names = table.columns[1:]
        return names, np.array([table[n] for n in names]).T

    def case(self, name):
        return Run(self.folder / "cases" / name)

    def case_names(self):
        return sorted(p.name for p in (self.folder / "cases").iterdir() if p.is_dir())


class Fit:
    """An `nct fit` folder (or a cohort's patient's)."""

    def __init__(self, folder):
        self.folder = pathlib.Path(folder)

    def has(self, name):
        return (self.folder / name).is_file()

    @functools.cached_property
    def result(self):
        return read_json(self.folder / "fit.json")

    @functools.cached_property
    def iterations(self):
        return read_csv(self.folder / "iterations.csv")

    @functools.cached_property
    def observations(self):
        return read_csv(self.folder / "observations.csv")

    def run(self, name):
        return Run(self.folder / "runs" / name)

    @property
    def best_run(self):
        """The run at the fitted values, or None."""
        best = self.result.get("best_run")
        return Run(best) if best else None


class Cohort:
    """A cohort's folder (`nct fit` on a fit file with a [cohort] table)."""

    def __init__(self, folder):
        self.folder = pathlib.Path(folder)

    @functools.cached_property
    def table(self):
        return read_csv(self.folder / "cohort.csv")

    @functools.cached_property
    def summary(self):
        return read_json(self.folder / "cohort.json")

    def patient(self, name):
        return Fit(self.folder / "patients" / name)
