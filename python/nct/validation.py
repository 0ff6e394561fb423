"""An emulator against runs it never saw (Bastos and O'Hagan 2009).

    report = validate(em, held)      # em: nct.emulator.Emulator; held: nct.training's dict
    print(markdown(report))

- the RMS error of the apex curve and of the profiles, in um, against the
  device's 20 um noise a frame;
- each reading's RMS error, in its unit;
- the standardised errors (truth - mean) / sd of every curve output and
  reading, and the share of them within +-2 (about 95 % when the stated
  variances are right);
- the Mahalanobis distance of each Gaussian process over the held-out
  points, D^2 = (y - m)^T V^-1 (y - m) with their joint predictive
  covariance V, against its expected value (the number of points) and
  the scaled F distribution's 95 % range (Bastos and O'Hagan 2009,
  Technometrics 51:425): a GP whose D^2 is far above states too small a
  variance, far below too large a one.
"""
import numpy as np
from scipy import stats

from . import biomarkers, emulator, training
from .markdown import table


def _mahalanobis(gp, U, y, n_train):
    m, V = gp.predict(U, return_cov=True)
    r = y - m
    d2 = float(r @ np.linalg.solve(V + 1e-12 * np.eye(len(y)) * np.trace(V) / len(y), r))
    k, q = len(y), 1    # points; the constant mean's one parameter (normalize_y)
    dof = n_train - q
    # (n - q) D^2 / (k (n - q - 2)) ~ F(k, n - q) (Bastos and O'Hagan 2009):
    # E D^2 = k.
    scale = k * (dof - 2) / dof
    lo, hi = stats.f.ppf([0.025, 0.975], k, dof) * scale
    return {"d2": d2, "expected": float(k), "range": [float(lo), float(hi)]}


def validate(em, held):
    """The held-out runs' errors and diagnostics (see the module's text)."""
    X = np.array([r["inputs"] for r in held["runs"]])
    U = em.box.to_unit(X)
    truth = np.hstack([training.arrays(held, b) for b in emulator.CURVES])
    pred = [em.predict(x) for x in X]
    mean = np.array([p["curves_mm"] for p in pred])
    var = np.array([p["curves_var_mm2"] for p in pred])
    na, nw = em.sizes[0], em.sizes[1]
    err = mean - truth
    # Outputs the model fixes (the curves at t = 0) have no error and no variance.
    fixed = (var == 0) & (err == 0)
    z_curves = np.where(fixed, 0.0, err / np.sqrt(np.where(fixed, 1.0, var)))
    report = {"runs": len(X), "train_runs": len(em.X), "components": em.components,
              "share": em.share,
              "apex_rms_um": 1000 * float(np.sqrt(np.mean(err[:, :na] ** 2))),
              "apex_max_um": 1000 * float(np.max(np.abs(err[:, :na]))),
              "whole_eye_rms_um": 1000 * float(np.sqrt(np.mean(err[:, na:na + nw] ** 2))),
              "profiles_rms_um": 1000 * float(np.sqrt(np.mean(err[:, na + nw:] ** 2))),
              "curves_within_2": float(np.mean(np.abs(z_curves) < 2)),
              "readings": {}, "mahalanobis": {}}
    W = (truth / emulator.NOISE_MM - em.mean) @ em.basis
    for j, gp in enumerate(em.weights):
        report["mahalanobis"][f"component {j + 1}"] = _mahalanobis(gp, U, W[:, j], len(em.X))
    for key, (gp, ok) in em.readings.items():
        y = training.arrays(held, key)[:, 0]
        have = np.isfinite(y)
        m = np.array([p["readings"][key][0] for p in pred])
        s = np.sqrt(np.array([p["readings"][key][1] for p in pred]))
        e = (m - y)[have]
        report["readings"][key] = {"unit": biomarkers.entry(key)["unit"],
                                   "rms": float(np.sqrt(np.mean(e ** 2))),
                                   "spread": float(np.std(y[have])),
                                   "within_2": float(np.mean(np.abs(e / s[have]) < 2))}
        report["mahalanobis"][key] = _mahalanobis(gp, U[have], y[have], int(ok.sum()))
    return report


def nested_order(U):
    """An order of the training points whose every prefix fills the box:
    the point nearest the centre first, then each time the point farthest
    from those taken (farthest-point, or maximin, ordering). The first
    rows of a maximin design are not space-filling: its points are spread
    as a whole."""
    U = np.asarray(U)
    order = [int(np.argmin(np.sum((U - 0.5) ** 2, axis=1)))]
    distance = np.sum((U - U[order[0]]) ** 2, axis=1)
    while len(order) < len(U):
        k = int(np.argmax(distance))
        order.append(k)
        distance = np.minimum(distance, np.sum((U - U[k]) ** 2, axis=1))
    return order


def size_curve(data, held, sizes, share=0.999, seed=1):
    """How the held-out error falls with the training size: for each n in
    `sizes` an emulator trained on the first n runs of the nested
    space-filling order of `data` (nested_order), validated on `held`.
    Rows: n, apex RMS [um], profiles RMS [um], the share of curve errors
    within +-2, training time [s]."""
    import time

    box = emulator.Box(data["box"])
    order = nested_order(box.to_unit(np.array([r["inputs"] for r in data["runs"]])))
    rows = []
    for n in sizes:
        part = dict(data, runs=[data["runs"][i] for i in order[:n]])
        start = time.time()
        em = emulator.train(part, share=share, seed=seed, progress=False)
        wall = time.time() - start
        report = validate(em, held)
        rows.append({"runs": n, "apex_rms_um": report["apex_rms_um"],
                     "profiles_rms_um": report["profiles_rms_um"],
                     "curves_within_2": report["curves_within_2"], "train_s": wall})
    return rows


def size_markdown(rows):
    """The size curve as a Markdown table."""
    return table(["training runs", "apex RMS [um]", "profiles RMS [um]",
                  "curve errors within +-2", "training [s]"],
                 [[str(r["runs"]), f"{r['apex_rms_um']:.1f}", f"{r['profiles_rms_um']:.1f}",
                   f"{100 * r['curves_within_2']:.0f} %", f"{r['train_s']:.1f}"] for r in rows])


def plot_size_curve(rows, path):
    """The size curve on log-log axes against the device's noise."""
    import matplotlib
    import matplotlib.ticker

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = [r["runs"] for r in rows]
    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.loglog(n, [r["apex_rms_um"] for r in rows], "o-", label="apex curve")
    ax.loglog(n, [r["profiles_rms_um"] for r in rows], "s-", label="profiles")
    ax.axhline(20, color="grey", ls="--", label="device noise (20 um)")
    ax.axhline(10, color="grey", ls=":", label="target (10 um)")
    ax.set_xticks(n)
    ax.xaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.set_xlabel("training runs")
    ax.set_ylabel("held-out RMS error [um]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)


def markdown(report):
    """The report as Markdown tables."""
    head = (f"{report['runs']} held-out runs, an emulator of {report['train_runs']} runs "
            f"({report['components']} components holding {100 * report['share']:.2f} % of the "
            f"curves' variance)\n\n")
    curves = table(["output", "RMS error [um]", "largest [um]"],
                   [["apex curve", f"{report['apex_rms_um']:.2f}", f"{report['apex_max_um']:.1f}"],
                    ["whole-eye curve", f"{report['whole_eye_rms_um']:.2f}", ""],
                    ["profiles", f"{report['profiles_rms_um']:.2f}", ""]])
    share = (f"\n\nstandardised errors within +-2: curves {100 * report['curves_within_2']:.0f} %\n\n")
    readings = table(["reading", "unit", "RMS error", "spread over the runs", "within +-2"],
                     [[k, r["unit"], f"{r['rms']:.4g}", f"{r['spread']:.4g}",
                       f"{100 * r['within_2']:.0f} %"] for k, r in report["readings"].items()])
    maha = table(["process", "D^2", "expected", "95 % range"],
                 [[k, f"{m['d2']:.1f}", f"{m['expected']:.0f}",
                   f"{m['range'][0]:.1f} to {m['range'][1]:.1f}"]
                  for k, m in report["mahalanobis"].items()])
    return head + curves + share + readings + "\n\n" + maha
