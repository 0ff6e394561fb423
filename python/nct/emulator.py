"""A Gaussian-process emulator of the model's outputs, trained on a
training set (nct.training) and exported for the C++ side.

    em = train(data, share=0.999, seed=1)    # data: nct.training.read(...)
    p = em.predict([0.06, 1.2, 15.0, 0.55, 7.8])   # natural units, inside the box
    p["curves_mm"], p["curves_var_mm2"], p["readings"]["hc_time_ms"]
    export(em, "emulator.json");  Exported("emulator.json").predict(x)   # the same numbers

The inputs are mapped onto the unit cube (a log-scale input through its
logarithm). The functional outputs, the apex and whole-eye curves on the
frame clock and the profiles, are divided by the device's noise (0.02 mm
a frame), centred, and reduced by their SVD to the components that hold
`share` of the variance (Higdon et al. 2008); what the kept components
miss is carried as a variance per output, measured leave-one-out (a
run's residual after its projection onto the others' basis). A Gaussian process per kept
component and per scalar reading (scikit-learn's GaussianProcessRegressor,
Debian's python3-sklearn: a Matern 5/2 kernel with a length scale per
input times a constant, plus a white-noise nugget for the solver's
tolerance; normalised outputs; hyperparameters by maximum likelihood
with restarts from a seeded generator). scikit-learn is the only
Gaussian-process library Debian packages (GPy, GPyTorch, george are not),
and its fitted state (the Cholesky factor L, alpha) is what the C++ side
needs to reproduce its predictions exactly:

    mean = y_mean + y_std k*^T alpha,   var = y_std^2 (k(x, x) + noise - |L^-1 k*|^2)

with k*_i = c (1 + sqrt5 r + 5 r^2 / 3) exp(-sqrt5 r), r = |(x - X_i) / l|.
"""
import json
import math
import time

import numpy as np
from scipy.linalg import solve_triangular
from sklearn.gaussian_process import GaussianProcessRegressor
from sklearn.gaussian_process.kernels import ConstantKernel, Matern, WhiteKernel

from . import training

NOISE_MM = 0.02     # the device's noise a frame: the curves' and profiles' scale
CURVES = ("apex_mm", "whole_eye_mm", "profiles_mm")


class OutsideBox(ValueError):
    """An input outside the emulator's box."""


class Box:
    """The inputs' box: each input's range and scale, onto [0, 1]^d."""

    def __init__(self, box):
        self.names = [b["input"] for b in box]
        self.low = np.array([b["range"][0] for b in box], float)
        self.high = np.array([b["range"][1] for b in box], float)
        self.log = np.array([b["scale"] == "log" for b in box])
        self.keys = [list(b.get("keys", [])) for b in box]

    def _t(self, v):
        return np.where(self.log, np.log(np.where(self.log, v, 1.0)), v)

    def to_unit(self, x):
        """x (natural units) on the unit cube; OutsideBox naming the input."""
        x = np.asarray(x, float)
        for j, name in enumerate(self.names):
            v = x[..., j]
            if np.any(v < self.low[j]) or np.any(v > self.high[j]):
                raise OutsideBox(f"{name} = {np.ravel(v)[0]:g} is outside the emulator's box "
                                 f"[{self.low[j]:g}, {self.high[j]:g}]")
        return (self._t(x) - self._t(self.low)) / (self._t(self.high) - self._t(self.low))

    def unit_derivative(self, x):
        """d(unit)/dx per input at x."""
        x = np.asarray(x, float)
        span = self._t(self.high) - self._t(self.low)
        return np.where(self.log, 1.0 / (x * span), 1.0 / span)


def _gp(X, y, seed, restarts):
    d = X.shape[1]
    kernel = (ConstantKernel(1.0, (1e-3, 1e3))
              * Matern(length_scale=np.full(d, 0.5), length_scale_bounds=(1e-2, 1e2), nu=2.5)
              + WhiteKernel(1e-6, (1e-12, 1.0)))
    gp = GaussianProcessRegressor(kernel, normalize_y=True, n_restarts_optimizer=restarts,
                                  random_state=seed)
    return gp.fit(X, y)


def _truncation(Y, k):
    """What k components leave of a run they were not computed from, per
    output: each run's residual after its projection onto the basis of
    the others (leave-one-out), squared and averaged. The residuals of the
    training runs themselves understate it: the basis was fitted to them."""
    residuals = []
    for i in range(len(Y)):
        others = np.delete(Y, i, axis=0)
        mean = others.mean(axis=0)
        basis = np.linalg.svd(others - mean, full_matrices=False)[2][:k].T
        y = Y[i] - mean
        residuals.append(y - basis @ (basis.T @ y))
    return np.mean(np.square(residuals), axis=0)


def _curves(data):
    """Every run's curves and profiles, one row each, in units of the noise."""
    return np.hstack([training.arrays(data, b) for b in CURVES]) / NOISE_MM


def _learnable(y):
    ok = np.isfinite(y)
    return ok.sum() >= len(y) // 2 and np.ptp(y[ok]) > 0


class Emulator:
    """The trained emulator (see the module's text)."""

    def __init__(self, data, share, seed, restarts, progress=False):
        self.box = Box(data["box"])
        self.X = self.box.to_unit(np.array([r["inputs"] for r in data["runs"]]))
        # Where the outputs are: every run on the same frame clock and profiles.
        first = data["runs"][0]
        for r in data["runs"]:
            if not (np.allclose(r["t_ms"], first["t_ms"], rtol=0, atol=1e-9)
                    and np.allclose(r["profile_t_ms"], first["profile_t_ms"], rtol=0, atol=1e-9)):
                raise ValueError(f"{r['case']}: its frames are not the first run's")
        self.t_ms, self.profile_t_ms = list(first["t_ms"]), list(first["profile_t_ms"])
        self.profile_x_mm = list(data["profile_x_mm"])
        self.sizes = [training.arrays(data, b).shape[1] for b in CURVES]
        Y = _curves(data)
        self.mean = Y.mean(axis=0)
        U, S, Vt = np.linalg.svd(Y - self.mean, full_matrices=False)
        held = np.cumsum(S ** 2) / np.sum(S ** 2)
        self.components = int(np.searchsorted(held, share) + 1)
        self.share = float(held[self.components - 1])
        self.basis = Vt[:self.components].T                      # (outputs, k)
        W = (Y - self.mean) @ self.basis
        self.truncation = _truncation(Y, self.components)         # per output, noise units^2
        # A reading is learnt where half the runs give it and it varies.
        keys = [k for k in training.READINGS + ["iop_max_mmHg"]
                if _learnable(training.arrays(data, k)[:, 0])]
        tick = Progress(self.components + len(keys), "emulator: trained") if progress else None
        self.weights = []
        for j in range(self.components):
            self.weights.append(_gp(self.X, W[:, j], seed, restarts))
            if tick:
                tick(f"curve component {j + 1}")
        self.readings, self.reading_ranges = {}, {}
        for key in keys:
            y = training.arrays(data, key)[:, 0]
            ok = np.isfinite(y)
            self.readings[key] = (_gp(self.X[ok], y[ok], seed, restarts), ok)
            self.reading_ranges[key] = [float(y[ok].min()), float(y[ok].max())]
            if tick:
                tick(key)

    def predict(self, x):
        """Means and variances at x (natural units): curves (mm, the blocks
        apex, whole eye, profiles one after the other) and readings."""
        u = self.box.to_unit(x)[None, :]
        w, s = zip(*(gp.predict(u, return_std=True) for gp in self.weights))
        w, var = np.array(w)[:, 0], np.array(s)[:, 0] ** 2
        curves = (self.mean + self.basis @ w) * NOISE_MM
        curves_var = (self.basis ** 2 @ var + self.truncation) * NOISE_MM ** 2
        readings = {}
        for key, (gp, _) in self.readings.items():
            m, sd = gp.predict(u, return_std=True)
            readings[key] = (float(m[0]), float(sd[0] ** 2))
        return {"curves_mm": curves, "curves_var_mm2": curves_var, "readings": readings}


def train(data, share=0.999, seed=1, restarts=5, progress=True):
    """The emulator of a training set (nct.training's dict); with progress,
    a line per Gaussian process trained, with the count and the time to go."""
    return Emulator(data, share, seed, restarts, progress)


class Progress:
    """A line per piece of work done: `label name  [done/total]  elapsed,
    about ... to go` (as nct's studies, fits and cohorts print)."""

    def __init__(self, total, label):
        self.total, self.label, self.done = total, label, 0
        self.start = time.monotonic()

    def __call__(self, name):
        self.done += 1
        elapsed = time.monotonic() - self.start
        line = f"{self.label} {name}  [{self.done}/{self.total}]  {elapsed:.0f} s elapsed"
        if self.done < self.total:
            line += f", about {elapsed / self.done * (self.total - self.done):.0f} s to go"
        print(line, flush=True)


def _export_gp(gp, X):
    k = gp.kernel_
    return {"X": X.tolist(), "alpha": gp.alpha_.ravel().tolist(), "L": gp.L_.tolist(),
            "constant": float(k.k1.k1.constant_value),
            "length_scale": np.atleast_1d(k.k1.k2.length_scale).tolist(),
            "noise": float(k.k2.noise_level),
            "y_mean": float(np.ravel(gp._y_train_mean)[0]),
            "y_std": float(np.ravel(gp._y_train_std)[0])}


def export(em, path):
    """The emulator as JSON: everything its predictions need (Exported, and
    the C++ evaluation)."""
    out = {"format": "nct-emulator-1", "noise_mm": NOISE_MM, "t_ms": em.t_ms,
           "profile_t_ms": em.profile_t_ms, "profile_x_mm": em.profile_x_mm,
           "box": [{"input": n, "keys": k, "range": [float(lo), float(hi)],
                    "scale": "log" if g else "linear"}
                   for n, k, lo, hi, g in zip(em.box.names, em.box.keys, em.box.low, em.box.high,
                                              em.box.log)],
           "curves": {"blocks": [[b, n] for b, n in zip(CURVES, em.sizes)], "mean": em.mean.tolist(),
                      "basis": em.basis.tolist(), "truncation": em.truncation.tolist(),
                      "share": em.share,
                      "components": [_export_gp(gp, em.X) for gp in em.weights]},
           "readings": {key: {**_export_gp(gp, em.X[ok]), "range": em.reading_ranges[key]}
                        for key, (gp, ok) in em.readings.items()}}
    with open(path, "w") as f:
        json.dump(out, f)


class _ExportedGp:
    def __init__(self, g):
        self.X, self.alpha = np.array(g["X"]), np.array(g["alpha"])
        self.L = np.array(g["L"])
        self.c, self.l, self.noise = g["constant"], np.array(g["length_scale"]), g["noise"]
        self.y_mean, self.y_std = g["y_mean"], g["y_std"]

    def predict(self, u):
        """Mean, variance and d(mean)/du at the unit-cube point u."""
        d = (u - self.X) / self.l
        r = np.sqrt(np.sum(d ** 2, axis=1))
        e = np.exp(-math.sqrt(5) * r)
        k = self.c * (1 + math.sqrt(5) * r + 5 * r ** 2 / 3) * e
        mean = self.y_mean + self.y_std * k @ self.alpha
        v = solve_triangular(self.L, k, lower=True)
        var = self.y_std ** 2 * max(self.c + self.noise - v @ v, 0.0)
        dk = -(5 / 3) * self.c * ((1 + math.sqrt(5) * r) * e)[:, None] * d / self.l
        return mean, var, self.y_std * self.alpha @ dk


class Exported:
    """An exported emulator, evaluated from its file alone (as the C++ side
    does): predict(x) as Emulator's, and gradient(x): d(mean)/dx of the
    curves (outputs x inputs) and of each reading."""

    def __init__(self, path):
        with open(path) as f:
            e = json.load(f)
        self.box = Box(e["box"])
        c = e["curves"]
        self.noise = e["noise_mm"]
        self.mean, self.basis = np.array(c["mean"]), np.array(c["basis"])
        self.truncation = np.array(c["truncation"])
        self.components = [_ExportedGp(g) for g in c["components"]]
        self.readings = {k: _ExportedGp(g) for k, g in e["readings"].items()}

    def _evaluate(self, x):
        u = self.box.to_unit(x)
        du = self.box.unit_derivative(x)
        w = [gp.predict(u) for gp in self.components]
        m = np.array([a[0] for a in w])
        var = np.array([a[1] for a in w])
        dm = np.array([a[2] for a in w]) * du                     # (k, inputs)
        curves = (self.mean + self.basis @ m) * self.noise
        curves_var = (self.basis ** 2 @ var + self.truncation) * self.noise ** 2
        readings, gradients = {}, {}
        for key, gp in self.readings.items():
            mean, v, g = gp.predict(u)
            readings[key] = (float(mean), float(v))
            gradients[key] = g * du
        return ({"curves_mm": curves, "curves_var_mm2": curves_var, "readings": readings},
                {"curves_mm": self.basis @ dm * self.noise, "readings": gradients})

    def predict(self, x):
        return self._evaluate(x)[0]

    def gradient(self, x):
        return self._evaluate(x)[1]
