"""Space-filling designs for a study of design = "table" (an emulator's
training runs): points in the box its [[factor]] tables declare.

    factors = read_factors("training.toml")      # label, keys, range, scale of each
    unit = maximin_hypercube(len(factors), 60, seed=1)   # (60, d) in [0, 1]
    rows = to_box(unit, factors)                 # natural units (a log scale: geometric)
    write_design("design.csv", rows, factors)

A Latin hypercube puts one point in each of n equal slices of every
input; of many random hypercubes (scipy.stats.qmc.LatinHypercube,
centred on the slices' middles) the one whose closest pair of points is
farthest apart is kept (maximin, Morris and Mitchell 1995): scipy 1.10
has no maximin optimisation of its own. The same seed gives the same
design.
"""
import math
import tomllib
from pathlib import Path

import numpy as np
from scipy.stats import qmc
from scipy.spatial.distance import pdist

from .tables import write_csv


class Factor:
    """A table design's input: its column `label`, the scene `keys` it
    sets, its `range` [low, high] and `scale` ("linear" or "log")."""

    def __init__(self, label, keys, low, high, scale):
        self.label, self.keys, self.low, self.high, self.scale = label, keys, low, high, scale


def read_factors(study_file):
    """The [[factor]] tables of a table-design study file, each with a range."""
    with open(study_file, "rb") as f:
        text = tomllib.load(f)
    if text.get("study", {}).get("design") != "table":
        raise ValueError(f"{study_file}: study.design is not \"table\"")
    factors = []
    for i, t in enumerate(text.get("factor", []), 1):
        keys = t["key"] if isinstance(t["key"], list) else [t["key"]]
        if "range" not in t:
            raise ValueError(f"{study_file}: factor[{i}] ({t.get('label', keys[0])}) has no range")
        factors.append(Factor(t.get("label", keys[0]), keys, float(t["range"][0]),
                              float(t["range"][1]), t.get("scale", "linear")))
    return factors


def maximin_hypercube(d, n, seed, candidates=500):
    """Of `candidates` centred Latin hypercubes of n points in [0, 1]^d, the
    one whose smallest distance between two points is largest."""
    rng = np.random.default_rng(seed)
    best, best_distance = None, -1.0
    for _ in range(candidates):
        sample = qmc.LatinHypercube(d, scramble=False, seed=rng).random(n)
        distance = pdist(sample).min() if n > 1 else math.inf
        if distance > best_distance:
            best, best_distance = sample, distance
    return best


def to_box(unit, factors):
    """Points of [0, 1]^d in the factors' ranges (a log scale geometrically)."""
    out = np.empty_like(unit)
    for j, f in enumerate(factors):
        if f.scale == "log":
            out[:, j] = np.exp(np.log(f.low) + unit[:, j] * (np.log(f.high) - np.log(f.low)))
        else:
            out[:, j] = f.low + unit[:, j] * (f.high - f.low)
    return out


def write_design(path, rows, factors, digits=6):
    """The design as the study's CSV: a column per factor's label; values
    rounded to `digits` significant digits, kept inside their ranges."""
    records = []
    for row in rows:
        record = {}
        for f, v in zip(factors, row):
            r = float(f"{v:.{digits}g}")
            record[f.label] = min(max(r, f.low), f.high)
        records.append(record)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    write_csv(path, records, [f.label for f in factors])


def least_sure(em, region, n, seed, candidates=4000, exclusion=0.15):
    """A later wave's n points: where the emulator `em` (nct.emulator) is
    least sure of the apex curve within `region` ({input: (low, high)},
    the box's part patients occupy; inputs not named span the box).
    Candidates are a Latin hypercube of the region; each pick is the
    candidate whose apex variance (summed over the frames) is largest,
    the candidates within `exclusion` of it on the unit cube dropped
    (so that the wave spreads rather than piling where one run would
    settle the doubt)."""
    box = em.box
    low = np.array([region.get(name, (lo, hi))[0] for name, lo, hi
                    in zip(box.names, box.low, box.high)], float)
    high = np.array([region.get(name, (lo, hi))[1] for name, lo, hi
                     in zip(box.names, box.low, box.high)], float)
    u = qmc.LatinHypercube(len(low), seed=np.random.default_rng(seed)).random(candidates)
    # Across the region on each input's own scale (log where the box's is).
    t = lambda v: np.where(box.log, np.log(np.where(box.log, v, 1.0)), v)  # noqa: E731
    inv = lambda v: np.where(box.log, np.exp(v), v)  # noqa: E731
    x = inv(t(low) + u * (t(high) - t(low)))
    apex = em.sizes[0]
    score = np.array([np.sum(em.predict(xi)["curves_var_mm2"][:apex]) for xi in x])
    unit = box.to_unit(x)
    picked = []
    for _ in range(n):
        k = int(np.argmax(score))
        picked.append(x[k])
        score[np.sum((unit - unit[k]) ** 2, axis=1) < exclusion ** 2] = -np.inf
    return np.array(picked)
