#!/usr/bin/python3
"""Where a run's wall time went: a row per phase from its summary.json.

Usage: scripts/profile.py RUN_DIR_OR_SUMMARY [--markdown]

Columns: wall time; residual assemblies (count, of them the line
search's, seconds); Jacobian assemblies; factorisations (the
preconditioner's set-up: MUMPS LU); linear solves (count, Krylov
iterations, seconds; LU back-solves under preonly); the bordered system's
extra work (its B, C assembly and solves, counted in the columns before
it too); field output; the rest of the phase (the log, the state's
bookkeeping, biomarkers).
"""
import json
import pathlib
import sys


def rows(summary):
    t = summary["timings_s"]
    yield {"phase": "set-up", "wall_s": t["mesh"] + t["setup"]}
    for p in summary.get("profile", []):
        yield p


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    markdown = "--markdown" in sys.argv
    if len(args) != 1:
        sys.exit(__doc__)
    path = pathlib.Path(args[0])
    summary = json.loads((path / "summary.json" if path.is_dir() else path).read_text())
    head = ["phase", "wall [s]", "steps", "Newton", "residuals (LS)", "residual [s]",
            "Jacobians", "Jacobian [s]", "factorisations", "factorise [s]",
            "solves (Krylov its)", "solve [s]", "border [s]", "output [s]", "other [s]"]
    table = []
    total = {}
    for p in rows(summary):
        g = lambda k: p.get(k, 0)
        accounted = (g("residual_s") + g("jacobian_s") + g("border_assemble_s") + g("factorise_s")
                     + g("solve_s") + g("output_s"))
        other = g("wall_s") - accounted if p["phase"] != "set-up" else 0.0
        table.append([p["phase"], "%.2f" % g("wall_s"), str(g("steps")), str(g("newton_iterations")),
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
    table.append(["total", "%.2f" % wall, str(total.get("steps", 0)),
                  str(summary["newton_iterations"]),
                  "%d (%d)" % (total.get("residuals", 0), total.get("line_search_residuals", 0)),
                  "%.2f" % total.get("residual_s", 0), str(total.get("jacobians", 0)),
                  "%.2f" % total.get("jacobian_s", 0), str(total.get("factorisations", 0)),
                  "%.2f" % total.get("factorise_s", 0),
                  "%d (%d)" % (total.get("linear_solves", 0), total.get("krylov_iterations", 0)),
                  "%.2f" % total.get("solve_s", 0), "%.2f" % total.get("border_s", 0),
                  "%.2f" % total.get("output_s", 0),
                  "%.2f" % (wall - sum(float(r[1]) for r in table) + sum(float(r[-1]) for r in table))])
    print("%s: %s DOFs on %s rank(s)" % (summary["scene"], summary.get("dofs"), summary["ranks"]))
    if markdown:
        print("| " + " | ".join(head) + " |")
        print("|" + "---|" * len(head))
        for r in table:
            print("| " + " | ".join(r) + " |")
    else:
        widths = [max(len(h), *(len(r[i]) for r in table)) for i, h in enumerate(head)]
        print("  ".join(h.rjust(w) for h, w in zip(head, widths)))
        for r in table:
            print("  ".join(c.rjust(w) for c, w in zip(r, widths)))


if __name__ == "__main__":
    main()
