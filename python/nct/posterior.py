"""A fit's sampled posterior (posterior.csv of a fit on an emulator):
its pair plot and marginal intervals.

    samples = read("fits/three/posterior.csv")          # {label: array}
    pair_figure("fits/three/posterior.csv", truths={"iop": 15.0})   # a matplotlib figure
    pair_plot("fits/three/posterior.csv", "posterior.png", truths={"iop": 15.0})
"""
import pathlib

import numpy as np

from .tables import read_csv


def read(path):
    """The samples per parameter (log_posterior apart)."""
    t = read_csv(path)
    return {name: np.asarray(t[name]) for name in t.columns if name != "log_posterior"}


def intervals(samples, level=0.95):
    """Per parameter: median and the central interval of the samples."""
    a = (1 - level) / 2
    return {k: (float(np.median(v)), float(np.quantile(v, a)), float(np.quantile(v, 1 - a)))
            for k, v in samples.items()}


def pair_figure(path, truths=None, title=None):
    """Each pair's samples as a scatter, each parameter's marginal as a
    histogram with its 95 % interval, the truths marked (a figure)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    samples = read(path)
    names = list(samples)
    n = len(names)
    fig, axes = plt.subplots(n, n, figsize=(2.6 * n, 2.6 * n), squeeze=False)
    bounds = intervals(samples)
    for i, a in enumerate(names):
        for j, b in enumerate(names):
            ax = axes[i][j]
            if j > i:
                ax.axis("off")
                continue
            if i == j:
                ax.hist(samples[a], bins=40, color="0.6")
                for x in bounds[a][1:]:
                    ax.axvline(x, color="k", ls=":")
                if truths and a in truths:
                    ax.axvline(truths[a], color="C3")
            else:
                ax.plot(samples[b], samples[a], ".", ms=1, alpha=0.3, color="C0")
                if truths and a in truths and b in truths:
                    ax.plot(truths[b], truths[a], "x", color="C3", ms=8, mew=2)
            if i == n - 1:
                ax.set_xlabel(b)
            if j == 0 and i > 0:
                ax.set_ylabel(a)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def pair_plot(path, png, truths=None, title=None):
    """The pair figure as a PNG."""
    from .figures import save_png
    png = pathlib.Path(png)
    save_png([(png.stem, pair_figure(path, truths, title))], png.parent)
