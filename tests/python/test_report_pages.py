"""The report pages' content on tiny folders (the browser test,
tests/report_pages.py, renders the real ones): the sections a page holds,
the CBI against a hand computation, chi2's verdict, the player's data."""
import json
import math
import pathlib
import tempfile
import unittest

from fixtures import SUMMARY, write_ablation, write_run
from nct import clinic, report
from nct.folders import Run
from nct.report import fit as fit_page
from nct.report import run as run_page


class Pages(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.root = pathlib.Path(self.dir.name)

    def tearDown(self):
        self.dir.cleanup()

    def test_kind(self):
        self.assertEqual(report.kind(write_run(self.root / "run")), "run")
        self.assertEqual(report.kind(write_ablation(self.root / "study")), "study")
        with self.assertRaises(report.NotAReportFolder):
            report.kind(self.root)

    def test_run_page_is_one_file(self):
        folder = write_run(self.root / "run")
        path = report.write(folder)
        self.assertEqual(path, folder / "report.html")
        self.assertFalse((folder / "report.html.tmp").exists())
        text = path.read_text()
        for section in ("model", "cost", "profile", "curves", "pressures", "dcr", "cbi",
                        "solver", "files"):
            self.assertIn(f'<section id="{section}">', text)
        self.assertNotIn("<link", text)
        self.assertNotIn(' src="', text)  # nothing loaded: scripts and figures inline
        data = json.loads(text.split('id="report-data">')[1].split("</script>")[0])
        player = data["player"]
        self.assertEqual(player["t_ms"], [0.0, 1.0])
        self.assertEqual(player["apex_mm"], [0.0, -1.0])
        self.assertEqual(player["events"], {"A1": 0, "HC": 1})  # nearest frames
        x, y = player["frames"][1]["anterior"]
        self.assertEqual(x, [-2.0, -1.0, 0.0, 1.0, 2.0])  # sorted by x
        self.assertEqual(y[2], 9.0)  # 1 mm in at the centre

    def test_dcr_flags_beyond_two_sd_but_not_clock_times(self):
        folder = write_run(self.root / "run")
        # deformation 1.30 mm: z = +2.2 (real eyes), +2.5 (normal eyes); A1 velocity 0.16
        # m/s inwards: z = +1.0 and +1.0; the A1 time 0.5 ms: z = -17.6 (normal eyes), but on
        # the device's clock
        summary = dict(SUMMARY, deformation_amplitude_mm=1.30, a1_velocity_m_s=-0.16)
        (folder / "summary.json").write_text(json.dumps(summary))
        text = report.write(folder).read_text()
        dcr = text.split('<section id="dcr">')[1].split("</section>")[0]
        flagged = [row for row in dcr.split("<tr") if 'class="flag"' in row]
        self.assertEqual(len(flagged), 1)
        self.assertIn("deformation amplitude", flagged[0])
        self.assertIn("beyond 2 SD of the real eyes and the normal eyes", flagged[0])
        self.assertIn("beyond 2 SD of the normal eyes if the clocks agreed", dcr)
        self.assertIn("Within 2 SD of the real eyes: 1 of the 2 readings", dcr)

    def test_coupled_run_shows_its_energy_balance(self):
        folder = write_run(self.root / "run")
        energy = {"solid_energy_change_mJ": 0.5, "damping_dissipation_mJ": 0.1,
                  "cavity_work_mJ": 0.05, "air_traction_work_mJ": 0.56,
                  "reaction_work_mJ": 0.55, "traction_mismatch_relative": 0.018,
                  "reaction_mismatch_relative": 0.0}
        (folder / "summary.json").write_text(json.dumps(dict(SUMMARY, energy_balance=energy)))
        text = report.write(folder).read_text()
        self.assertIn('<section id="energy">', text)
        self.assertIn("<td>traction_mismatch_relative</td><td>0.018</td>", text)
        self.assertNotIn('<section id="energy">', report.write(write_run(self.root / "b"))
                         .read_text())

    def test_cbi(self):
        summary = dict(SUMMARY, a1_velocity_m_s=-0.15, sp_a1_mmHg_per_mm=100.0,
                       da_ratio_1mm=1.55, da_ratio_2mm=4.3)
        value, inputs = clinic.cbi(summary)
        self.assertIsNone(value)  # ARTh and the SD are no run's
        self.assertEqual([n for n, v, _, _ in inputs if v is None],
                         ["ARTh", "SD of the deflection amplitude"])
        value, _ = clinic.cbi(summary, {"ARTh": 500.0, "SD of the deflection amplitude": 1.0})
        b = (46.576 - 59.487 * 0.15 - 0.027 * 500.0 - 0.092 * 100.0 - 27.169 * 1.55
             + 5.472 * 4.3 - 0.599 * 1.0)
        self.assertAlmostEqual(value, math.exp(b) / (1 + math.exp(b)), places=14)

    def test_chi2_verdict(self):
        self.assertFalse(fit_page.verdict(48.0, 48)[1])
        text, flag = fit_page.verdict(150.0, 48)
        self.assertTrue(flag)
        self.assertIn("too large", text)
        self.assertIn("too small", fit_page.verdict(10.0, 48)[0])
        self.assertIn("no degrees of freedom", fit_page.verdict(0.0, 0)[0])

    def test_effects_name_the_load(self):
        scene = {"puff": {"load": "gaussian", "peak": 65.0, "peak_time": 10.0, "width_t": 3.0,
                          "width_r": 1.5, "duration": 20.0},
                 "support": {"model": "clamped"}, "cavity": {"model": "closed",
                                                             "humor_inertia": "flow"}}
        rows = dict(run_page.effects(scene, {}))
        self.assertIn("Gaussian", rows["air puff"])
        self.assertIn("flowing", rows["humor"])
        self.assertEqual(rows["support"], "clamped at the cut")

    def test_ablation_page(self):
        text = report.write(write_ablation(self.root / "study")).read_text()
        for section in ("design", "cases", "ablation", "files"):
            self.assertIn(f'<section id="{section}">', text)
        self.assertIn("<td>+50</td>", text)  # the open variant's percent
        self.assertIn('data-name="variants"', text)

    def test_folder_reader(self):
        self.assertEqual(len(Run(write_run(self.root / "run")).profiles), 2)


if __name__ == "__main__":
    unittest.main()
