"""A fit's page: each parameter with its interval and prior, the
correlations, the readings against the fitted model with the residuals in
SDs, chi2 / dof with its verdict, the iterations; a posterior's pair plot."""
import os

from .. import fit as figures
from .. import posterior
from ..folders import Fit
from .page import Page, escape, link, links, number


def verdict(chi2, dof):
    """(text, whether it flags): chi2 against the central 95 % of the
    chi2 distribution with dof degrees of freedom."""
    from scipy.stats import chi2 as distribution
    if not dof or dof <= 0 or chi2 is None:
        return "no degrees of freedom left: no test of the fit's quality", False
    lo, hi = distribution.ppf([0.025, 0.975], dof)
    text = (f"chi2 {chi2:.4g} for {dof} dof (chi2 / dof {chi2 / dof:.3g}); the central 95 % "
            f"for a model that explains the readings within their SDs: {lo:.4g} to {hi:.4g}: ")
    if chi2 > hi:
        return text + ("too large: the model misses the readings by more than their SDs "
                       "(a missing effect, a biased load, or SDs set too small)"), True
    if chi2 < lo:
        return text + "too small: the SDs overstate the readings' scatter", True
    return text + "consistent", False


def _parameters(section, result):
    rows, flags = [], set()
    for i, p in enumerate(result["parameters"]):
        lo, hi = p.get("ci95") or (None, None)
        prior = p.get("prior")
        if p.get("at_bound"):
            flags.add(i)
        rows.append([p["label"], ", ".join(p["keys"]), number(p["value"]), number(p.get("se"), 3),
                     f"{number(lo)} to {number(hi)}", number(p.get("start")),
                     f"{number(p.get('lower'))} to {number(p.get('upper'))}"
                     + (" (log scale)" if p.get("log") else ""),
                     f"{prior['mean']:.4g} +- {prior['sd']:.3g}" if prior
                     else "none (flat within the bounds)",
                     "at a bound" if p.get("at_bound") else ""])
    section.table(["parameter", "scene keys", "fitted", "SE", "95 % interval", "start",
                   "bounds", "prior (mean +- SD)", "flag"], rows, "parameters", flags)
    if result.get("command"):
        section.raw(f'<p class="note">The fitted eye: <code>{escape(result["command"])}</code>'
                    "</p>")
    for w in result.get("warnings", []):
        section.paragraph("warning: " + w, "warn")


def _correlations(section, result, made):
    labels = [p["label"] for p in result["parameters"]]
    c = result.get("correlation") or []
    if c:
        section.table([""] + labels, [[labels[i]] + [number(v, 3) for v in row]
                                      for i, row in enumerate(c)], "correlation")
    if "fit-correlation" in made:
        section.figure(made.pop("fit-correlation"), "The fitted parameters' correlations",
                       "fit-correlation")


def _readings(section, fit, made):
    result = fit.result
    rows = []
    for o in result.get("observations", []):
        rows.append([o["label"], o["kind"], str(o.get("points", "-")),
                     number(o.get("rms_weighted_residual"), 3)])
    if rows:
        section.table(["observation", "kind", "points", "RMS residual [SD]"], rows, "readings")
    for name, caption in (("fit-curves", "The measured curves (points, with their SDs) against "
                           "the fitted model and the start"),
                          ("fit-profiles", "The measured profiles against the fitted model"),
                          ("fit-residuals", "The residuals in SDs, the +-1 and +-2 SD bands "
                           "shaded")):
        if name in made:
            section.figure(made.pop(name), caption, name)
    text, flag = verdict(result.get("chi2"), result.get("dof"))
    section.paragraph(text, "warn" if flag else "note")


def _iterations(section, fit, made):
    result = fit.result
    section.paragraph(f"{result.get('status')} after {result.get('iterations')} iterations, "
                      f"{result.get('forward_runs')} forward runs "
                      f"({result.get('forward_runs_reused', 0)} reused), "
                      f"{number(result.get('wall_s'), 3)} s: {result.get('message', '')}", "note")
    if "fit-convergence" in made:
        section.figure(made.pop("fit-convergence"), "The cost and each parameter per iteration "
                       "(refused steps hollow; the 95 % intervals shaded)", "fit-convergence")
    if fit.has("iterations.csv"):
        t = fit.iterations
        section.table(t.columns, [[number(r[c], 6) if isinstance(r[c], float) else str(r[c])
                                   for c in t.columns] for r in t.rows()], "iterations")


def _posterior(section, fit):
    path = fit.folder / "posterior.csv"
    samples = posterior.read(path)
    rows = [[k, number(m), f"{number(lo)} to {number(hi)}", str(len(samples[k]))]
            for k, (m, lo, hi) in posterior.intervals(samples).items()]
    section.table(["parameter", "median", "95 % interval", "samples"], rows, "posterior")
    section.figure(posterior.pair_figure(path), "The posterior's samples: each pair, each "
                   "marginal with its 95 % interval (dotted)", "posterior")


def page(folder):
    fit = Fit(folder)
    r = fit.result
    name = fit.folder.resolve().name
    page = Page("fit", f"Fit {name}", f"{fit.folder.resolve()}: {r.get('status')}, "
                f"{len(r['parameters'])} parameter(s), chi2 / dof "
                f"{number(r.get('reduced_chi2'), 3)}")
    made = dict(figures.figures(folder))
    _parameters(page.section("parameters", "Parameters"), r)
    _correlations(page.section("correlations", "Correlations"), r, made)
    _readings(page.section("readings", "Readings against the fitted model"), fit, made)
    _iterations(page.section("iterations", "Iterations"), fit, made)
    if fit.has("posterior.csv"):
        _posterior(page.section("posterior", "Posterior"), fit)
    model = r.get("forward_model", {})
    files = links(fit.folder, ("fit.toml", "fit.json", "iterations.csv", "observations.csv",
                               "posterior.csv"))
    best = fit.best_run
    where = os.path.relpath(best.folder, fit.folder) if best else ""
    extra = (f" The best run: {link(where + '/', where)} "
             "(<code>nct report</code> on it draws its page)." if best else "")
    if model.get("emulator"):
        extra += f" Forward model: the emulator {escape(model['emulator'])}."
    page.section("files", "Files").raw(f"<p>{files}.{extra}</p>")
    for leftover, fig in made.items():  # a figure no section took
        page.sections[-1].figure(fig, leftover, leftover)
    return page
