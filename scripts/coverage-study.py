#!/usr/bin/python3
"""Do a fit's 95 % intervals hold the truth 95 % of the time? A coverage
study of nct fit: one truth, many noise seeds, one fit per seed.

Usage: scripts/coverage-study.py OUT [--nct build/nct] [--seeds 20]
       [--scene scenes/default.toml] [--truth-set KEY=VALUE ...]
       [--fit-set KEY=VALUE ...] [--label NAME] [--jobs 2]

The fit: corneal (and limbal) C10 and the IOP, from the apex curve and the
anterior profiles (scripts/synthetic-readings.py: 0.02 mm per point), the
IOP also measured by a tonometer with an SD of 1.5 mmHg. For each seed
the readings' noise is drawn anew, and so is the tonometer's reading
(truth + 1.5 N(0, 1)): a prior centred on the truth would make the
intervals look better than they are.

The truth's run takes the scene with --truth-set, the fits the scene with
--fit-set; the same sets for both make readings and model the same (the
noise is then the only error), a finer --truth-set (fem.degree=2 against
the fit's fem.degree=1, say) adds the model's discretisation error.

Writes OUT/truth (the truth's run), OUT/seed-NNN (readings, fit file, fit)
and OUT/coverage.csv (per seed and parameter: value, SE, interval, inside,
chi2 per dof), and prints per parameter the share of intervals holding the
truth with its 95 % Clopper-Pearson interval, the same with each interval
widened by sqrt(chi2 per dof) (the usual correction for unmodelled error),
the mean error in SEs, and the mean chi2 per dof. A seed whose fit is
already in OUT is not run again.
"""
import argparse
import csv
import json
import math
import pathlib
import subprocess
import sys
import time

import numpy as np
from scipy import stats

ROOT = pathlib.Path(__file__).resolve().parent.parent
TRUTH = {"c10_cornea": 0.07, "iop": 15.0}
IOP_SD = 1.5  # mmHg: the tonometer's SD


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if p.returncode not in (0, 3):
        sys.exit("coverage: %s exited %d:\n%s" % (" ".join(map(str, cmd)), p.returncode,
                                                  p.stdout[-2000:]))
    return p.returncode


def fit_file(scene, sets, jobs, prior_mean):
    text = "[fit]\nscene = %s\nset = %s\njobs = %d\n\n" % (
        json.dumps(str(scene)), json.dumps(sets), jobs)
    text += ('[[parameter]]\nlabel = "c10_cornea"\nkey = ["material.cornea.c10", '
             '"material.limbus.c10"]\nstart = 0.05\nbounds = [0.01, 0.5]\n\n')
    text += ('[[parameter]]\nlabel = "iop"\nkey = "inflate.iop"\nstart = 18.0\n'
             'bounds = [5.0, 40.0]\nprior = {mean = %.6g, sd = %g}\n\n' % (prior_mean, IOP_SD))
    text += '[[observation]]\ncurve = "data/apex.csv"\n\n'
    text += '[[observation]]\nprofile = "data/profiles.csv"\n'
    return text


def clopper_pearson(k, n):
    lo = stats.beta.ppf(0.025, k, n - k + 1) if k > 0 else 0.0
    hi = stats.beta.ppf(0.975, k + 1, n - k) if k < n else 1.0
    return lo, hi


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out", type=pathlib.Path)
    ap.add_argument("--nct", type=pathlib.Path, default=ROOT / "build" / "nct")
    ap.add_argument("--scene", type=pathlib.Path, default=ROOT / "scenes" / "default.toml")
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--truth-set", action="append", default=[])
    ap.add_argument("--fit-set", action="append", default=[])
    ap.add_argument("--label", default="")
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    if a.seeds < 2:
        sys.exit("coverage: --seeds must be at least 2")
    a.out.mkdir(parents=True, exist_ok=True)
    start = time.time()

    truth = a.out / "truth"
    if not (truth / "summary.json").exists():
        sets = ["output.fields=false", "material.cornea.c10=%g" % TRUTH["c10_cornea"],
                "material.limbus.c10=%g" % TRUTH["c10_cornea"],
                "inflate.iop=%g" % TRUTH["iop"]] + a.truth_set
        run([a.nct, "run", a.scene.resolve(), "--out", truth]
            + [w for s in sets for w in ("--set", s)])
    truth_s = json.load(open(truth / "summary.json"))["wall_s"]
    print("coverage %s: truth run %.0f s (%s)" % (a.label, truth_s, " ".join(a.truth_set)),
          flush=True)

    rows = []
    for seed in range(1, a.seeds + 1):
        folder = a.out / ("seed-%03d" % seed)
        result = folder / "fit" / "fit.json"
        if not result.exists():
            folder.mkdir(exist_ok=True)
            subprocess.run(["/usr/bin/python3", ROOT / "scripts" / "synthetic-readings.py",
                            truth, folder / "data", "--seed", str(seed)], check=True,
                           stdout=subprocess.DEVNULL)
            # The tonometer's reading: its own stream, independent of the readings'.
            prior = TRUTH["iop"] + IOP_SD * np.random.default_rng(10_000 + seed).normal()
            (folder / "fit.toml").write_text(fit_file(a.scene.resolve(), a.fit_set, a.jobs, prior))
            run([a.nct, "fit", folder / "fit.toml", "--out", folder / "fit"])
        r = json.load(open(result))
        reduced = r["reduced_chi2"]
        for p in r["parameters"]:
            lo, hi = p["ci95"]
            se = p["se"]
            # The interval widened by sqrt(chi2/dof), on the fitted scale.
            w = math.sqrt(max(reduced, 1.0))
            if p["log"]:
                half = math.log(hi / p["value"]) * w
                wlo, whi = p["value"] * math.exp(-half), p["value"] * math.exp(half)
            else:
                half = (hi - p["value"]) * w
                wlo, whi = p["value"] - half, p["value"] + half
            t = TRUTH[p["label"]]
            rows.append({"seed": seed, "parameter": p["label"], "truth": t,
                         "value": p["value"], "se": se, "ci95_lo": lo, "ci95_hi": hi,
                         "inside": int(lo <= t <= hi), "inside_widened": int(wlo <= t <= whi),
                         "error_in_se": (p["value"] - t) / se, "reduced_chi2": reduced,
                         "status": r["status"], "forward_runs": r["forward_runs"],
                         "wall_s": r["wall_s"]})
        last = [x for x in rows if x["seed"] == seed]
        print("seed %3d: %s; chi2/dof %.3f; %d runs, %.0f s" % (
            seed, ", ".join("%s %.5g [%.5g, %.5g]%s" % (x["parameter"], x["value"],
                                                         x["ci95_lo"], x["ci95_hi"],
                                                         "" if x["inside"] else " MISSES")
                            for x in last),
            reduced, last[0]["forward_runs"], last[0]["wall_s"]), flush=True)

    with open(a.out / "coverage.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    n = a.seeds
    chi = [x["reduced_chi2"] for x in rows if x["parameter"] == "c10_cornea"]
    print("\ncoverage %s: %d seeds; chi2 per dof %.3f mean (%.3f to %.3f)"
          % (a.label, n, np.mean(chi), min(chi), max(chi)))
    print("| parameter | truth | held | share [95 % CP] | widened by sqrt(chi2/dof) "
          "| mean error [SE] | SD of error [SE] |")
    print("|---|---|---|---|---|---|---|")
    summary = {"label": a.label, "seeds": n, "truth_set": a.truth_set, "fit_set": a.fit_set,
               "reduced_chi2_mean": float(np.mean(chi)), "parameters": {}}
    for label in TRUTH:
        xs = [x for x in rows if x["parameter"] == label]
        k, kw = sum(x["inside"] for x in xs), sum(x["inside_widened"] for x in xs)
        lo, hi = clopper_pearson(k, n)
        lw, hw = clopper_pearson(kw, n)
        e = np.array([x["error_in_se"] for x in xs])
        print("| %s | %g | %d / %d | %.2f [%.2f, %.2f] | %.2f [%.2f, %.2f] | %+.2f | %.2f |"
              % (label, TRUTH[label], k, n, k / n, lo, hi, kw / n, lw, hw, e.mean(),
                 e.std(ddof=1)))
        summary["parameters"][label] = {"held": k, "share": k / n, "cp95": [lo, hi],
                                        "held_widened": kw, "cp95_widened": [lw, hw],
                                        "mean_error_se": float(e.mean()),
                                        "sd_error_se": float(e.std(ddof=1))}
    runs = sum(x["forward_runs"] for x in rows if x["parameter"] == "c10_cornea")
    wall = sum(x["wall_s"] for x in rows if x["parameter"] == "c10_cornea")
    summary.update({"forward_runs": runs, "fits_wall_s": wall, "truth_wall_s": truth_s})
    print("%d forward runs in %.0f s of fits (%.1f runs and %.0f s a fit); this call %.0f s"
          % (runs, wall, runs / n, wall / n, time.time() - start))
    (a.out / "coverage.json").write_text(json.dumps(summary, indent=2) + "\n")


if __name__ == "__main__":
    main()
