"""Matplotlib figures out: as PNG files, or as SVG text to inline in a
web page (text kept as text, so that the page is searchable and small).

    save_png([("puff", fig)], folder)     # folder/puff.png; returns the paths
    svg(fig)                              # "<svg ...>...</svg>"; closes fig
"""
import io
import pathlib
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def save_png(figures, folder, dpi=120):
    """Each (name, figure) as folder/name.png; returns the paths."""
    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, fig in figures:
        path = folder / f"{name}.png"
        fig.savefig(path, dpi=dpi, bbox_inches="tight")
        plt.close(fig)
        paths.append(path)
    return paths


def svg(fig):
    """The figure as an inline <svg> element (no XML prolog, no DOCTYPE),
    its fonts the page's; closes the figure."""
    out = io.StringIO()
    with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": "nct",
                                "font.family": "sans-serif"}):
        fig.savefig(out, format="svg", metadata={"Date": None}, bbox_inches="tight")
    plt.close(fig)
    text = out.getvalue()
    text = re.sub(r"<metadata>.*?</metadata>", "", text, flags=re.S)  # RDF: author, format
    return text[re.search(r"<svg\b", text).start():]
