"""A run's page: what the scene simulates and what it cost, the cornea
through the puff on the device's frame clock, the curves, the DCR
parameters against measured eyes, the CBI, the energy balance and the
solver's profile, the files for ParaView."""
import pathlib

import numpy as np

from .. import clinic, puff, timing
from ..figures import plt  # the Agg backend chosen there
from ..folders import Run
from .page import Page, link, links, number

MMHG = "mmHg"


def _v(table, key):
    """A scene value as text ('?' where the scene lacks it)."""
    v = table.get(key, "?")
    return f"{v:g}" if isinstance(v, float) else str(v)


def _material(m):
    model = m.get("model", "?")
    if model == "hgo":
        text = (f"HGO (Holzapfel, Gasser and Ogden 2000): C10 {_v(m, 'c10')} MPa, "
                f"k1 {_v(m, 'k1')} MPa, k2 {_v(m, 'k2')}, kappa {_v(m, 'kappa')} MPa")
        if m.get("dispersion"):
            text += f", fibre dispersion {_v(m, 'dispersion')} (Gasser et al. 2006)"
    elif model == "neo_hookean":
        text = f"neo-Hookean, nearly incompressible: C10 {_v(m, 'c10')} MPa, kappa {_v(m, 'kappa')} MPa"
    elif model in ("compressible_neo_hookean", "saint_venant_kirchhoff"):
        text = f"{model.replace('_', ' ')}: E {_v(m, 'youngs_modulus')} MPa, nu {_v(m, 'poisson_ratio')}"
    else:
        text = model.replace("_", " ")
    visco = m.get("viscoelasticity", {})
    if visco.get("relative_moduli"):
        text += ("; viscoelastic (Prony series: relative moduli %s, relaxation times %s ms)"
                 % (visco["relative_moduli"], visco["relaxation_times"]))
    return text


def effects(scene, summary):
    """[(effect, what the scene sets)]: what the run simulates, from its
    resolved scene.toml, with the sources of the shipped inputs."""
    mesh, rows = scene.get("mesh", {}), []
    dimension = mesh.get("dimension", "3d")
    model = {"3d": "3D", "axisymmetric": "axisymmetric section (the eye's meridian)",
             "plane": "plane section"}.get(dimension, dimension)
    if mesh.get("source") == "file":
        rows.append(("geometry", f"{model}; the mesh file {mesh.get('file')}"))
    else:
        g = scene.get("geometry", {})
        factor = summary.get("symmetry_factor")
        part = f" (1/{factor:g} of it by symmetry)" if dimension == "3d" and factor and factor > 1 \
            else ""
        rows.append(("geometry", f"{model}{part}: the idealised eye, cornea radii "
                     f"{g.get('cornea_anterior_radius')} / {g.get('cornea_posterior_radius')} mm, "
                     f"central thickness {g.get('cornea_central_thickness')} mm, sclera radius "
                     f"{g.get('sclera_outer_radius')} mm"
                     + ("; lens, zonule and vitreous membrane" if g.get("internal_structures")
                        else "")))
    fem = scene.get("fem", {})
    rows.append(("discretisation", f"degree {fem.get('degree')} ({fem.get('formulation')}), "
                 f"{summary.get('cells', '?')} cells, {summary.get('dofs', '?')} DOFs"
                 + (f"; air {summary['air_cells']} cells, {summary['air_dofs']} DOFs"
                    if "air_dofs" in summary else "")))
    zp = scene.get("zero_pressure", {})
    rows.append(("zero pressure", "the mesh is the eye imaged at the IOP: its stress-free "
                 "geometry found first (backward displacement)" if zp.get("enabled")
                 else "the mesh taken as stress-free"))
    for part in ("cornea", "limbus", "sclera"):
        if part in scene.get("material", {}):
            rows.append((part, _material(scene["material"][part])))
    cavity = scene.get("cavity", {})
    iop = scene.get("inflate", {}).get("iop")
    humor = {"none": "massless", "translation": "its mass moving with its centroid",
             "flow": "flowing (potential flow of its mass)",
             "navier_stokes": "flowing (ALE Navier-Stokes)"}.get(cavity.get("humor_inertia"),
                                                                cavity.get("humor_inertia"))
    rows.append(("humor", (f"closed: each cavity keeps its volume, its pressure an unknown; {humor}"
                           if cavity.get("model") == "closed"
                           else "open: the pressure stays at the IOP") + f"; IOP {iop} mmHg"))
    support = scene.get("support", {})
    rows.append(("support", "clamped at the cut" if support.get("model") == "clamped" else
                 f"the orbit's springs and dashpots (Kling et al. 2014): stiffness "
                 f"{support.get('stiffness')}, damping {support.get('damping')}"))
    p = scene.get("puff", {})
    load = p.get("load", "none")
    if load == "pulse":
        text = (f"the measured Corvis ST pulse (Oehring et al. 2021): {_v(p, 'peak')} mmHg at the "
                f"apex, rising {_v(p, 'rise_rate')} and falling {_v(p, 'fall_rate')} mmHg/ms over "
                f"{_v(p, 'pulse_duration')} ms" + (f"; radial profile {p['profile']}"
                                                 if p.get("profile") else ""))
    elif load == "gaussian":
        text = (f"an assumed Gaussian pressure: {_v(p, 'peak')} mmHg at {_v(p, 'peak_time')} ms, "
                f"{_v(p, 'width_t')} ms and {_v(p, 'width_r')} mm wide")
    elif load == "table":
        text = f"a table of the air's pressure on the cornea p(r, t): {p.get('table')}"
    elif load == "air":
        text = "the jet computed by ALE Navier-Stokes on the rigid eye (one-way)"
    elif load == "fsi":
        text = ("two-way coupled: the jet by stabilised ALE Navier-Stokes, the air mesh's motion "
                "and the eye in one Newton system per step")
    else:
        text = "none"
    rows.append(("air puff", text))
    if load != "none":
        d = scene.get("dynamics", {})
        rows.append(("time", f"{p.get('duration')} ms of puff, step {d.get('dt')} ms "
                     f"(generalised alpha, rho_inf {d.get('rho_inf')}), mass damping "
                     f"{d.get('damping')} 1/ms; profiles at {p.get('frame_rate', 4330):g} "
                     "frames/s"))
    return rows


def cost_rows(summary):
    """[(quantity, value)]: ranks, DOFs, steps, Newton iterations, cuts,
    wall time, memory."""
    t = summary.get("timings_s", {})
    steps = summary.get("steps")
    rows = [("ranks", summary.get("ranks")), ("DOFs", summary.get("dofs")),
            ("steps", len(steps) if isinstance(steps, list) else steps),
            ("Newton iterations", summary.get("newton_iterations")),
            ("step cuts", summary.get("step_cuts")),
            ("wall time", "%.1f s" % summary["wall_s"] if "wall_s" in summary else "-")]
    if t:
        rows.append(("of it assembly / linear solves",
                     "%.1f s / %.1f s" % (t.get("assemble", 0), t.get("linear_solve", 0))))
    if "memory_peak_total_mb" in summary:
        rows.append(("peak memory, all ranks", "%.0f MB" % summary["memory_peak_total_mb"]))
    return [(k, "-" if v is None else str(v)) for k, v in rows]


def player_data(run):
    """The profile player's data: each frame's section (anterior and
    posterior x, y), its time, the apex curve at the frames, the frames of
    A1, HC and A2, the drawing's extent."""
    prof = run.profiles
    surfaces = [s for s in ("anterior", "posterior") if s in prof.surfaces]
    frames, lo, hi = [], np.array([np.inf, np.inf]), np.array([-np.inf, -np.inf])
    for k in range(len(prof)):
        f = {}
        for s in surfaces:
            x, y = prof.curve(k, s)
            f[s] = [np.round(x, 4).tolist(), np.round(y, 4).tolist()]
            lo = np.minimum(lo, [x.min(), y.min()])
            hi = np.maximum(hi, [x.max(), y.max()])
        frames.append(f)
    fr = run.frames
    apex = np.interp(prof.t_ms, fr["t_ms"], fr["apex_displacement_mm"])
    events = {name.upper(): prof.nearest(t) for name, t in puff.events(run.summary)}
    margin = 0.08 * (hi - lo)
    return {"t_ms": np.round(prof.t_ms, 4).tolist(), "apex_mm": np.round(apex, 5).tolist(),
            "frames": frames, "events": events,
            "extent": [lo[0] - margin[0], hi[0] + margin[0], lo[1] - margin[1], hi[1] + margin[1]]}


def _player(page, section, run):
    data = player_data(run)
    page.data["player"] = data
    page.script("player")
    x0, x1, y0, y1 = data["extent"]
    width = 760
    height = int(min(420, max(160, width * (y1 - y0) / (x1 - x0) + 40)))
    buttons = "".join(f'<button type="button" data-frame="{k}">{name}</button>'
                      for name, k in data["events"].items())
    ticks = "".join(f'<option value="{k}" label="{name}"></option>'
                    for name, k in data["events"].items())
    section.raw(
        '<div class="player"><div>'
        f'<svg id="profile-view" width="{width}" height="{height}" role="img" '
        'aria-label="the corneal section at the chosen frame over the undeformed one"></svg>'
        '<div class="controls"><input type="range" id="frame" min="0" '
        f'max="{len(data["t_ms"]) - 1}" step="1" value="0" list="events">'
        f'<datalist id="events">{ticks}</datalist></div>'
        f'<div class="controls"><button type="button" id="play">Play</button>{buttons}'
        '<span class="readout" id="readout"></span></div>'
        f'<svg id="apex-chart" width="{width}" height="200" role="img" '
        'aria-label="the apex displacement against time"></svg></div></div>')
    rate = run.scene.get("puff", {}).get("frame_rate", 4330)
    section.paragraph(
        f"The cornea's horizontal section at {rate:g} frames/s, as the Corvis ST images it; "
        "drawn to scale (1 mm bar), over its undeformed section (dashed, the frame at the "
        "puff's onset). The slider picks the frame; A1, HC and A2 jump to the applanations "
        "and the highest concavity. Below: the apex's axial displacement (+ outwards), the "
        "cursor at the frame shown. Times are from the puff's onset; the device's clock "
        "starts an unknown time before it.", "note")


def _dcr(section, summary):
    rows, flags = [], set()
    for i, (name, value, unit, against) in enumerate(clinic.compare(summary)):
        u = f" {unit}" if unit else ""
        clock = "(device clock)" in name  # its zero is not the run's
        cells, beyond = [], []
        for population in ("real eyes", "normal eyes"):
            if against[population]:
                (mean, sd), z = against[population]
                cells += [f"{mean:.4g} +- {sd:.2g}{u}", number(z, 2, "+")]
                if abs(z) > 2:
                    beyond.append(population)
            else:
                cells += ["-", ""]
        if beyond and not clock:
            flags.add(i)
        rows.append([name, f"{value:.4g}{u}", *cells,
                     ("beyond 2 SD of the " + " and the ".join(beyond)
                      + (" if the clocks agreed" if clock else "")) if beyond else ""])
    section.table(["parameter", "this run", "202 real eyes (mean +- SD)", "z",
                   "normal eyes, PMC7001013 (mean +- SD)", "z", "flag"], rows, "dcr", flags)
    n, of = clinic.within(summary)
    section.paragraph(
        f"Within 2 SD of the real eyes: {n} of the {of} readings that are not times on the "
        "device's clock.", "note")
    section.paragraph(
        "Real eyes: 202 eyes of 194 cataract patients (age 69 +- 9) measured by a Corvis ST "
        "whose software reports the DCR parameters, the CBI and the SSI (a public de-identified "
        "cohort, CC-BY-4.0: cases/real-eyes). Normal eyes: 1,304 healthy eyes of "
        "refractive-surgery candidates (age 28 +- 5; PMC7001013, software not stated); the "
        "whole-eye movement's time: 68 healthy eyes (doi:10.21203/rs.3.rs-9226844/v1). Where "
        "the two disagree, their software's definitions differ: " + "; ".join(
            f"{clinic.NAMES[k]}: {v}" for k, v in clinic.SOURCES.items()) + ". Velocities on the clinic's "
        "sign (+ inwards). The device's times run on its clock, whose zero lies an unknown "
        "time before the pulse's onset, from which the run counts: compare the intervals, not "
        "the times (their rows are not marked). Rows beyond 2 SD are marked.", "note")


def _cbi(section, summary):
    value, inputs = clinic.cbi(summary)
    section.table(["input", "value", "unit", "source"],
                  [[n, number(v), u, s] for n, v, u, s in inputs], "cbi")
    missing = [n for n, v, _, _ in inputs if v is None]
    if value is None:
        section.paragraph("CBI not computed: the run lacks " + ", ".join(missing) + ". "
                          "With them (a patient's measured values), nct.clinic.cbi gives it.",
                          "note")
    else:
        section.paragraph(f"CBI = {value:.3f} (above 0.5: the published cut-off for "
                          "keratoconus)", "note")
    section.paragraph("The Corvis Biomechanical Index (Vinciguerra et al., J. Refract. Surg. 32 "
                      "(2016) 803-810): a logistic regression, CBI = 1 / (1 + exp(-b)), b = "
                      "46.576 - 59.487 A1 velocity - 0.027 ARTh - 0.092 SP-A1 - 27.169 DA ratio "
                      "1 mm + 5.472 DA ratio 2 mm - 0.599 SD deflection amplitude (coefficients "
                      "as reprinted in Sci. Rep. (2021), doi:10.1038/s41598-020-80915-9, "
                      "table 4).", "note")


def _energy(section, summary):
    e = summary["energy_balance"]
    rows = [[k, number(v)] for k, v in e.items()]
    flags = {i for i, (k, v) in enumerate(e.items())
             if k == "reaction_mismatch_relative" and abs(v) > 0.1}
    section.table(["term", "value"], rows, "energy", flags)
    section.paragraph(
        "What the eye took over the puff (its energy change, the damping's dissipation, the "
        "cavities' work) against two measures of the air's work on it: the coupling's reaction "
        "(the consistent interface force the coupled system uses; its mismatch is the time "
        "integration's, first order in the step, marked above 10 %) and the air's stress "
        "integrated over the interface (a first-order flux on the interface mesh: its "
        "mismatch falls as that mesh is refined, docs/verification.md, "
        "Fsi.AirStressWorkConvergesToTheSolidsEnergy). Mismatches relative to the eye's "
        "share.", "note")
    rows = [[k, number(summary[k])] for k in ("air_mesh_jacobian_min",
                                              "interface_power_mismatch_max_W",
                                              "interface_power_max_W") if k in summary]
    if rows:
        section.table(["coupling check", "value"], rows, "energy")


def _solver(section, run):
    s = run.summary
    if "profile" in s and "timings_s" in s:
        head, rows = timing.phases(s)
        section.table(head, rows, "profile")
    if run.has("steps.csv"):
        st = run.steps
        if len(st):
            residual = "residual_N" in st.columns
            fig, ax = plt.subplots(1, 1 + residual, figsize=(6 + 6 * residual, 3.2),
                                   squeeze=False)
            ax = ax[0]
            ax[0].plot(st["t_ms"], st["newton_iterations"], ".-")
            ax[0].set_ylabel("Newton iterations")
            if residual:
                ax[1].semilogy(st["t_ms"], np.maximum(np.abs(st["residual_N"]), 1e-30), ".")
                ax[1].set_ylabel("final residual [N]")
            for a in ax:
                a.set_xlabel("time [ms] (negative: before the puff)")
                a.grid(alpha=0.3)
            fig.tight_layout()
            section.figure(fig, "Newton iterations and the converged residual per step "
                           "(steps.csv)", "solver")


def _files(section, run):
    xdmf = "".join(f"<li>{link(p.name)}</li>" for p in sorted(run.folder.glob("*.xdmf")))
    section.raw("<p>Fields for ParaView (File, Open, the .xdmf; its .h5 beside it):</p>"
                + (f"<ul class=\"xdmf\">{xdmf}</ul>" if xdmf else
                   "<p class=\"note\">none written (output.fields = false)</p>"))
    section.raw("<p>Tables: " + links(run.folder, ("summary.json", "frames.csv", "profiles.csv",
                                                   "steps.csv", "probes.csv", "forces.csv",
                                                   "scene.toml", "run.log")) + "</p>")


def page(folder):
    """The run's page (a Page)."""
    run = Run(folder)
    s = run.summary
    name = pathlib.Path(s.get("scene", run.folder.name)).stem
    status = s.get("status", "?")
    page = Page("run", f"Run {name}",
                f"{run.folder.resolve()}: {status}, {s.get('ranks', '?')} rank(s), "
                f"{number(s.get('wall_s'), 3)} s")
    model = page.section("model", "What it simulates")
    model.table(["effect", "in this run"], effects(run.scene, s), "effects")
    model.paragraph(f"Scene: {s.get('scene', '?')} (resolved, with every default: scene.toml)",
                    "note")
    page.section("cost", "Cost").table(["quantity", "value"], cost_rows(s), "cost")
    if status != "converged":
        page.sections[0].paragraph(f"The run stopped: status {status}. What it wrote is shown.",
                                   "warn")
    pufffigs = dict(puff.figures(run))
    if pufffigs and run.has("profiles.csv"):
        sec = page.section("profile", "The cornea through the puff")
        _player(page, sec, run)
        sec.figure(pufffigs.pop("profiles"), "The corneal section (anterior solid, posterior "
                   "dashed) at the onset, A1, HC and A2", "profiles")
    if pufffigs:
        sec = page.section("curves", "Deformation, deflection and whole-eye movement")
        sec.figure(pufffigs["deformation"], "The apex's axial displacement (deformation) and "
                   "deflection (less the whole eye's movement); the whole-eye movement, the "
                   "cornea 4 mm from the axis; A1, HC and A2 marked", "deformation")
        sec = page.section("pressures", "Air pressure at the apex and IOP")
        sec.figure(pufffigs["pressures"], "The air's pressure at the apex and the IOP (the "
                   "closed cavities' pressure) against time", "pressures")
        _dcr(page.section("dcr", "DCR parameters against measured eyes"), s)
        _cbi(page.section("cbi", "Corvis Biomechanical Index"), s)
    if "energy_balance" in s:
        _energy(page.section("energy", "Energy balance of the coupling"), s)
    _solver(page.section("solver", "Solver profile"), run)
    _files(page.section("files", "Files"), run)
    return page
