"""Where a run's wall time went: a row per phase from its summary.json
(`profile`), and the total.

Columns: wall time; residual assemblies (count, of them the line
search's, seconds); Jacobian assemblies; factorisations (the
preconditioner's set-up: MUMPS LU); linear solves (count, Krylov
iterations, seconds; LU back-solves under preonly); the bordered system's
extra work (its B, C assembly and solves, counted in the columns before
it too); field output; the rest of the phase (the log, the state's
bookkeeping, biomarkers).

    head, rows = phases(summary)
"""
HEAD = ["phase", "wall [s]", "steps", "Newton", "residuals (LS)", "residual [s]",
        "Jacobians", "Jacobian [s]", "factorisations", "factorise [s]",
        "solves (Krylov its)", "solve [s]", "border [s]", "output [s]", "other [s]"]


def _phases(summary):
    t = summary["timings_s"]
    yield {"phase": "set-up", "wall_s": t["mesh"] + t["setup"]}
    yield from summary.get("profile", [])


def phases(summary):
    """(HEAD, rows of text): set-up, each phase, the total."""
    table = []
    total = {}
    for p in _phases(summary):
        g = lambda k: p.get(k, 0)  # noqa: E731
        accounted = (g("residual_s") + g("jacobian_s") + g("border_assemble_s") + g("factorise_s")
                     + g("solve_s") + g("output_s"))
        other = g("wall_s") - accounted if p["phase"] != "set-up" else 0.0
        table.append([p["phase"], "%.2f" % g("wall_s"), str(g("steps")),
                      str(g("newton_iterations")),
                      "%d (%d)" % (g("residuals"), g("line_search_residuals")),
                      "%.2f" % g("residual_s"), str(g("jacobians")), "%.2f" % g("jacobian_s"),
                      str(g("factorisations")), "%.2f" % g("factorise_s"),
                      "%d (%d)" % (g("linear_solves"), g("krylov_iterations")),
                      "%.2f" % g("solve_s"), "%.2f" % g("border_s"), "%.2f" % g("output_s"),
                      "%.2f" % other])
        for k, v in p.items():
            if isinstance(v, (int, float)):
                total[k] = total.get(k, 0) + v
    wall = summary["wall_s"]
    t = lambda k: total.get(k, 0)  # noqa: E731
    table.append(["total", "%.2f" % wall, str(t("steps")), str(summary["newton_iterations"]),
                  "%d (%d)" % (t("residuals"), t("line_search_residuals")),
                  "%.2f" % t("residual_s"), str(t("jacobians")), "%.2f" % t("jacobian_s"),
                  str(t("factorisations")), "%.2f" % t("factorise_s"),
                  "%d (%d)" % (t("linear_solves"), t("krylov_iterations")),
                  "%.2f" % t("solve_s"), "%.2f" % t("border_s"), "%.2f" % t("output_s"),
                  "%.2f" % (wall - sum(float(r[1]) for r in table)
                            + sum(float(r[-1]) for r in table))])
    return HEAD, table
