"""Tiny folders as nct writes them, for the package's unit tests."""
import json
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "python"))

SUMMARY = {"status": "converged", "scene": "scene.toml", "ranks": 1, "dofs": 120, "wall_s": 3.5,
           "newton_iterations": 7, "deformation_amplitude_mm": 1.15, "deflection_amplitude_mm": 1.1,
           "a1_time_ms": 0.5, "hc_time_ms": 1.0, "a1_velocity_m_s": -0.2,
           "timings_s": {"mesh": 0.25, "setup": 0.25},
           "profile": [{"phase": "puff", "wall_s": 2.5, "steps": 2, "newton_iterations": 7,
                        "residuals": 9, "residual_s": 0.5, "factorisations": 1,
                        "factorise_s": 1.0, "linear_solves": 7, "solve_s": 0.5}]}


def write_run(folder):
    """A puff run of two frames: the cornea flat at y = 10, then pushed in
    by 1 mm at its centre (y = 10 - (1 - x^2 / 4) for |x| <= 2)."""
    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "summary.json").write_text(json.dumps(SUMMARY))
    (folder / "frames.csv").write_text(
        "t_ms,apex_displacement_mm,whole_eye_motion_mm,apex_air_pressure_mmHg,cavity_pressure_mmHg\n"
        "0,0,0,0,15\n1,-1,-0.01,60,20\n")
    lines = ["frame,t_ms,surface,x_mm,y_mm"]
    for frame, t in ((0, 0.0), (1, 1.0)):
        for surface, offset in (("anterior", 0.0), ("posterior", -0.5)):
            for x in (2.0, -2.0, 0.0, 1.0, -1.0):  # not in order, as nct's nodes
                y = 10 + offset - frame * (1 - x * x / 4)
                lines.append(f"{frame},{t},{surface},{x},{y}")
    (folder / "profiles.csv").write_text("\n".join(lines) + "\n")
    (folder / "steps.csv").write_text("t_ms,dt_ms,newton_iterations\n0,0.5,3\n0.5,0.5,4\n")
    (folder / "scene.toml").write_text('[puff]\nload = "gaussian"\npeak = 65.0\n')
    (folder / "case.json").write_text(json.dumps({"case": "case-001", "sets": ["inflate.iop=8"]}))
    return folder


def write_ablation(folder):
    """A finished ablation of two variants and one response."""
    folder = pathlib.Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "cases.csv").write_text(
        "case,status,variant,deflection_amplitude_mm,wall_s\n"
        "case-001,converged,closed,1.0,10\ncase-002,converged,open,1.5,12\n")
    (folder / "ablation.csv").write_text(
        "variant,response,value,difference,percent\n"
        "closed,deflection_amplitude_mm,1,0,0\nopen,deflection_amplitude_mm,1.5,0.5,50\n")
    variants = [{"variant": "closed", "value": 1.0, "difference": 0.0, "percent": 0.0},
                {"variant": "open", "value": 1.5, "difference": 0.5, "percent": 50.0}]
    (folder / "analysis.json").write_text(json.dumps({
        "design": "ablation", "cases": 2, "baseline": "closed",
        "variants": [{"name": "closed", "description": "the humor closed"},
                     {"name": "open", "description": ""}],
        "responses": {"deflection_amplitude_mm": {"unit": "mm", "variants": variants}}}))
    return folder
