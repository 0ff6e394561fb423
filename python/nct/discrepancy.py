"""A model discrepancy measured, not assumed (Kennedy and O'Hagan 2001):
the curves of a more faithful model (a finer mesh, the 3D eye) less those
of the emulated model at the same points.

    d = estimate(training.read("fine-data.json"), training.read("base-data.json"))
    write(d, "discrepancy.json")       # [fit] discrepancy = "discrepancy.json"

Per curve output of the emulator (the apex and whole-eye curves on the
frame clock, the profiles) the runs' differences delta_i give the mean
and a factor F (outputs x runs) with F F^T their covariance, inflated by
1 + 1/n for the mean's own uncertainty: the predictive covariance of a
new eye's discrepancy under a Gaussian model of the n runs. A fit adds
the mean to the emulator's and F F^T to its likelihood's covariance.
"""
import json

import numpy as np

from . import emulator


def estimate(fine, base):
    """The discrepancy of `fine` from `base` (nct.training dicts of the
    same design: their runs paired by their inputs)."""
    index = {tuple(np.round(r["inputs"], 9)): r for r in base["runs"]}
    deltas = []
    for r in fine["runs"]:
        b = index.get(tuple(np.round(r["inputs"], 9)))
        if b is None:
            continue
        curves = [np.ravel(r[k]) - np.ravel(b[k]) for k in emulator.CURVES]
        deltas.append(np.concatenate(curves))
    n = len(deltas)
    if n < 2:
        raise ValueError(f"{n} paired runs: a discrepancy needs at least 2")
    D = np.array(deltas)
    mean = D.mean(axis=0)
    factor = (D - mean).T / np.sqrt(n - 1) * np.sqrt(1 + 1 / n)
    return {"format": "nct-discrepancy-1", "runs": n, "mean_mm": mean.tolist(),
            "factor_mm": factor.tolist()}


def write(d, path):
    with open(path, "w") as f:
        json.dump(d, f)


def without(fine, base, case):
    """The discrepancy estimated without one of the fine runs (its case
    name): to test on that run."""
    return estimate(dict(fine, runs=[r for r in fine["runs"] if r["case"] != case]), base)


