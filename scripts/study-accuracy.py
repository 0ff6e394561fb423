#!/usr/bin/python3
"""What accuracy costs in time (docs/physics.md section 11) on a puff scene.

Runs a scene (scenes/default.toml unless --scene) over the knobs that trade accuracy for time, one
at a time from the default (3 layers, P2, dt 0.5 ms): elements through the
thickness (3-6), the time step (0.5, 0.25, 0.1 ms) and the element degree
(1, 2 at every layer count), plus the finest run (6 layers, P2, dt 0.1 ms)
as the reference. Writes study.csv and study.png (wall time against the
error in deflection amplitude, peak distance and HC time relative to the
reference) and prints the table.

Usage: scripts/study-accuracy.py [--scene SCENE] [--ranks N] [--out DIR] [--quick]
A finished case (its summary.json present) is not run again.
"""
import argparse
import csv
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESPONSES = [("deflection_amplitude_mm", "deflection amplitude"),
             ("peak_distance_mm", "peak distance"),
             ("hc_time_ms", "HC time")]


def cases(quick):
    """(name, layers, degree, dt) of every run; the reference first."""
    if quick:
        return [("l4-p2-dt0.25", 4, 2, 0.25), ("l3-p2-dt0.5", 3, 2, 0.5),
                ("l3-p1-dt0.5", 3, 1, 0.5)]
    runs = [("l6-p2-dt0.1", 6, 2, 0.1)]
    for layers in (3, 4, 5, 6):
        for degree in (1, 2):
            runs.append((f"l{layers}-p{degree}-dt0.5", layers, degree, 0.5))
    for dt in (0.25, 0.1):
        runs.append((f"l3-p2-dt{dt}", 3, 2, dt))
    return runs


def run(scene, out, ranks, name, layers, degree, dt):
    folder = os.path.join(out, name)
    summary = os.path.join(folder, "summary.json")
    if not os.path.exists(summary):
        cmd = ["mpirun", "-n", str(ranks), os.path.join(ROOT, "build", "nct"), "run",
               scene, "--out", folder,
               "--set", f"mesh.layers={layers}", "--set", f"fem.degree={degree}",
               "--set", f"dynamics.dt={dt}", "--set", "output.fields=false"]
        with open(folder + ".log", "w") as log:
            if subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT) != 0:
                print(f"{name} failed: see {folder}.log", file=sys.stderr)
    if not os.path.exists(summary):
        return None
    with open(summary) as f:
        s = json.load(f)
    return s if s["status"] == "converged" else None


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--scene", default=os.path.join(ROOT, "scenes", "default.toml"))
    p.add_argument("--ranks", type=int, default=2)
    p.add_argument("--out", default=os.path.join(ROOT, "runs", "study-accuracy"))
    p.add_argument("--quick", action="store_true", help="three small cases (a smoke test)")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
    os.environ["OPENBLAS_NUM_THREADS"] = "1"

    rows = []
    for name, layers, degree, dt in cases(a.quick):
        s = run(os.path.abspath(a.scene), a.out, a.ranks, name, layers, degree, dt)
        if s is None:
            if not rows:
                sys.exit(f"the reference {name} failed: no errors can be measured")
            continue
        rows.append(dict(case=name, layers=layers, degree=degree, dt_ms=dt, dofs=s["dofs"],
                         steps=len(s["steps"]), newton=s["newton_iterations"],
                         wall_s=s["wall_s"], **{k: s.get(k, float("nan"))
                                                for k, _ in RESPONSES}))
    ref = rows[0]
    for r in rows:
        for k, _ in RESPONSES:
            r["error_" + k] = abs(r[k] - ref[k]) / abs(ref[k])

    fields = list(rows[0].keys())
    with open(os.path.join(a.out, "study.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)
    head = "%-14s %7s %6s %7s %8s %9s %9s %9s %9s %9s %9s" % (
        "case", "dofs", "steps", "newton", "wall_s", "DA_mm", "PD_mm", "HC_ms",
        "err_DA", "err_PD", "err_HC")
    print(f"reference: {ref['case']} ({a.ranks} ranks)")
    print(head)
    for r in rows:
        print("%-14s %7d %6d %7d %8.1f %9.4f %9.4f %9.4f %9.2e %9.2e %9.2e" % (
            r["case"], r["dofs"], r["steps"], r["newton"], r["wall_s"],
            r["deflection_amplitude_mm"], r["peak_distance_mm"], r["hc_time_ms"],
            r["error_deflection_amplitude_mm"], r["error_peak_distance_mm"],
            r["error_hc_time_ms"]))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for ax, (key, label) in zip(axes, RESPONSES):
        for r in rows[1:]:
            marker = "o" if r["degree"] == 2 else "s"
            colour = {0.5: "C0", 0.25: "C1", 0.1: "C2"}[r["dt_ms"]]
            err = max(r["error_" + key], 1e-7)
            ax.loglog(r["wall_s"], err, marker, color=colour)
            ax.annotate(r["case"], (r["wall_s"], err), fontsize=7, xytext=(3, 3),
                        textcoords="offset points")
        ax.set_xlabel(f"wall time on {a.ranks} ranks [s]")
        ax.set_ylabel(f"relative error in {label}")
        ax.set_title(label)
        ax.grid(True, which="both", alpha=0.3)
    fig.suptitle(f"Accuracy against cost; reference {ref['case']} "
                 "(circles P2, squares P1; blue dt 0.5, orange 0.25, green 0.1 ms)")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "study.png"), dpi=120)
    print(f"wrote {a.out}/study.csv and study.png")


if __name__ == "__main__":
    main()
