"""A cohort's page: the table of patients (fitted values, intervals,
warnings), the fitted stiffness against the IOP and age, the recovery
plot where truths exist."""
from .. import cohort_figures as figures
from ..folders import Cohort
from .page import Page, links, number


def _patients(section, c):
    rows, failed = figures.fitted(c.folder)
    table = c.table
    params = figures.labels(table.columns)
    head = ["patient", "status"]
    for p in params:
        head += [p, f"{p} 95 % interval"]
        if f"truth_{p}" in table.columns:
            head += [f"{p} truth", "inside"]
    head += ["chi2 / dof", "iterations", "warnings"]
    out, flags = [], set()
    for i, r in enumerate(table.rows()):
        cells = [r["patient"], r["status"]]
        for p in params:
            cells += [number(r.get(p)), f"{number(r.get(p + '_lo'))} to {number(r.get(p + '_hi'))}"]
            if f"truth_{p}" in table.columns:
                inside = r.get(p + "_inside")
                cells += [number(r.get(f"truth_{p}")), "yes" if inside in (1, 1.0) else
                          ("no" if inside in (0, 0.0) else "-")]
        cells += [number(r.get("reduced_chi2"), 3), number(r.get("iterations"), 3),
                  r.get("warnings") if isinstance(r.get("warnings"), str) else ""]
        if r["status"] != "converged" or r["patient"] in failed:
            flags.add(i)
        out.append(cells)
    section.table(head, out, "patients", flags)
    s = c.summary
    text = f"{s.get('converged')} of {s.get('patients')} fits converged in {number(s.get('wall_s'), 3)} s"
    inside = s.get("truths_inside_ci95")
    if inside:
        text += f"; {inside['held']} of {inside['of']} truths inside their 95 % intervals"
    section.paragraph(text + ". Each patient's fit: patients/<patient> (nct report on it draws "
                      "its page); failed rows are marked.", "note")


def page(folder):
    c = Cohort(folder)
    s = c.summary
    page = Page("cohort", f"Cohort {c.folder.resolve().name}",
                f"{c.folder.resolve()}: {s.get('patients')} patients from {s.get('table')}")
    _patients(page.section("patients", "Patients"), c)
    made = dict(figures.figures(folder))
    sec = page.section("stiffness", "Fitted stiffness against IOP and age")
    for name, caption in (("cohort-iop", "Each patient's fitted stiffness (95 % interval) against "
                           "the IOP"), ("cohort-age", "The same against age")):
        if name in made:
            sec.figure(made.pop(name), caption, name)
    if not sec.parts:
        sec.paragraph("No IOP or age column to plot against.", "note")
    if "cohort-recovery" in made:
        rec = page.section("recovery", "Recovery of the truths")
        rec.figure(made.pop("cohort-recovery"), "Fitted values (95 % intervals) against the "
                   "truths; the line: fit = truth", "cohort-recovery")
    page.section("files", "Files").raw(
        f"<p>{links(c.folder, ('fit.toml', 'cohort.csv', 'cohort.json'))}</p>")
    return page
