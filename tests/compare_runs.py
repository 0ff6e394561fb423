"""Two runs' outputs compared: summary.json (with compare_summaries), every
CSV and every XDMF time series. Used by tests/checkpoint.py, and by hand:

usage: compare_runs.py COMPARE_SUMMARIES RUN_A RUN_B [--exact]

--exact: bitwise (a 1-rank run resumed on 1 rank); else to 1e-8 relative
or 1e-9 absolute (runs on other rank counts)."""
import os
import subprocess
import sys

import h5py
import numpy as np
from lxml import etree
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python"))
from nct.folders import read_summary  # noqa: E402
from nct.tables import read_csv  # noqa: E402


def printed_unit(text):
    """The value of a unit in the last printed digit of a number."""
    mantissa, _, exponent = text.lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return 10.0 ** (int(exponent or 0) - decimals)


def rows(path):
    """A CSV's header and rows, each cell as printed."""
    t = read_csv(path, numeric=False)
    return [t.columns] + [[str(t[c][i]) for c in t.columns] for i in range(len(t))]


def agree(compare, a, b, exact):
    """summary.json and every CSV of run a's equal to run b's: bitwise
    (exact) or to 1e-8 relative or 1e-9 absolute (a CSV's number also to
    a unit in its last printed digit). `compare`: compare_summaries."""
    tol = ["0", "0"] if exact else ["1e-8", "1e-9"]
    p = subprocess.run([compare, f"{a}/summary.json", f"{b}/summary.json", *tol],
                       stdout=subprocess.PIPE, text=True)
    print(p.stdout.strip())
    assert p.returncode == 0, f"summaries differ: {a} vs {b}"
    sa, sb = (read_summary(x) for x in (a, b))
    for key in ("newton_iterations", "factorisations", "linear_solves", "step_cuts"):
        if exact:
            assert sa[key] == sb[key], f"{key}: {sa[key]} vs {sb[key]}"
    for name in sorted(f for f in os.listdir(b) if f.endswith(".csv")):
        ra, rb = rows(f"{a}/{name}"), rows(f"{b}/{name}")
        assert len(ra) == len(rb) and ra[0] == rb[0], f"{name}: rows or columns differ"
        worst = 0.0
        for x, y in zip(ra[1:], rb[1:]):
            for h, u, v in zip(ra[0], x, y):
                if h in ("newton_iterations", "residual_N", "wall_s"):
                    continue
                x_text = u
                try:
                    u, v = float(u), float(v)
                except ValueError:  # a label (the surface)
                    assert u == v, f"{name} {h}: {u} vs {v}"
                    continue
                d = abs(u - v)
                if exact:
                    assert u == v, f"{name} {h}: {u} vs {v}"
                else:  # a printed number agrees no better than its last digit
                    assert d <= max(1e-9, 1e-8 * max(abs(u), abs(v)),
                                    1.01 * printed_unit(x_text)), f"{name} {h}: {u} vs {v}"
                worst = max(worst, d)
        print(f"{name}: {len(ra) - 1} rows agree (largest difference {worst:.1e})")


XI = "{http://www.w3.org/2001/XInclude}include"


def h5_item(folder, item):
    file, path = item.text.strip().rsplit(":", 1)
    with h5py.File(os.path.join(folder, file), "r") as f:
        return f[path][...]


def series(folder, name):
    """A time series' steps (time, points, values), or None for a file of
    meshes only. Points are the nodes (or the cells' centroids) of the
    geometry each step refers to. Checks that the HDF5 file holds only
    datasets the XML refers to."""
    root = etree.parse(f"{folder}/{name}")
    domain = root.find("Domain")
    referred = {i.text.strip().rsplit(":", 1)[1] for i in root.iter("DataItem")}
    h5 = name[:-len(".xdmf")] + ".h5"
    held = []
    with h5py.File(f"{folder}/{h5}", "r") as f:
        f.visititems(lambda path, o: held.append("/" + path) if isinstance(o, h5py.Dataset) else None)
    stale = sorted(set(held) - referred)
    assert not stale, f"{folder}/{h5} holds datasets its XML does not refer to: {stale[:5]}"
    collection = [g for g in domain.findall("Grid") if g.get("CollectionType") == "Temporal"]
    if not collection:
        return None
    steps = collection[0].findall("Grid")
    out = []
    for grid in steps:
        topology, geometry = grid.find("Topology"), grid.find("Geometry")
        for include in grid.findall(XI):  # resolved as an XDMF reader does (libxml2)
            pointer = include.get("xpointer")
            assert pointer.startswith("xpointer(") and pointer.endswith(")"), pointer
            found = root.xpath(pointer[len("xpointer("):-1])
            assert found, f"{folder}/{name}: {pointer} finds nothing"
            for node in found:
                topology = node if node.tag == "Topology" else topology
                geometry = node if node.tag == "Geometry" else geometry
        attribute = grid.find("Attribute")
        x = h5_item(folder, geometry.find("DataItem"))
        if attribute.get("Center") == "Cell":
            x = x[h5_item(folder, topology.find("DataItem"))].mean(axis=1)
        out.append((grid.find("Time").get("Value"), x, h5_item(folder, attribute.find("DataItem"))))
    return out, len(root.findall(".//Topology"))


def agree_fields(a, b, exact):
    """Run a's XDMF fields equal to run b's, step by step: bitwise (exact)
    or to 1e-8 of the field's largest value at the step plus 1e-12 (a field
    near zero, e.g. at the puff's start, differs by round-off between two
    2-rank runs), at the same points (matched by position: another
    partition orders them otherwise)."""
    names = sorted(f for f in os.listdir(b) if f.endswith(".xdmf"))
    assert names == sorted(f for f in os.listdir(a) if f.endswith(".xdmf")), \
        f"the XDMF files differ: {a} vs {b}"
    for name in names:
        sa, sb = series(a, name), series(b, name)
        if sb is None:
            continue
        (sa, meshes), (sb, _) = sa, sb
        assert [t for t, _, _ in sa] == [t for t, _, _ in sb], f"{name}: the times differ"
        worst = 0.0
        for (t, xa, va), (_, xb, vb) in zip(sa, sb):
            if exact:
                assert np.array_equal(xa, xb) and np.array_equal(va, vb), f"{name} t = {t}"
                continue
            distance, match = cKDTree(xb).query(xa)
            assert distance.max() < 1e-6 and len(set(match)) == len(match), \
                f"{name} t = {t}: the points differ (by {distance.max():.1e})"
            d = np.abs(va - vb[match]).max()
            assert d <= 1e-8 * max(np.abs(va).max(), np.abs(vb).max()) + 1e-12, \
                f"{name} t = {t}: values differ by {d:.1e}"
            worst = max(worst, d)
        print(f"{name}: {len(sa)} steps agree (largest difference {worst:.1e}, "
              f"{meshes} topolog{'y' if meshes == 1 else 'ies'})")


if __name__ == "__main__":
    compare, a, b = sys.argv[1:4]
    exact = "--exact" in sys.argv[4:]
    agree(compare, a, b, exact)
    agree_fields(a, b, exact)
    print("compare_runs: ok")
