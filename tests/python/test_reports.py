"""What the tools print: the clinic's z-scores, the time profile, a study's
report, a cohort's recovery table; the synthetic readings."""
import pathlib
import tempfile
import unittest

import numpy as np

from fixtures import SUMMARY, write_ablation, write_run
from nct import clinic, cohort_figures, readings, study, timing
from nct.folders import Run
from nct.tables import read_csv


class Reports(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.root = pathlib.Path(self.dir.name)

    def tearDown(self):
        self.dir.cleanup()

    def test_clinic(self):
        rows = {name: (value, z) for name, value, _, _, z in clinic.z_scores(SUMMARY)}
        self.assertAlmostEqual(rows["deformation amplitude"][1], (1.15 - 1.05) / 0.10)
        self.assertEqual(rows["A1 velocity (+ inwards)"][0], 0.2)  # the clinic's sign
        self.assertIsNone(rows["deflection amplitude"][1])  # no verified norm
        self.assertNotIn("A2 time (device clock)", rows)  # not in the summary
        self.assertIn("| A1 to HC |", clinic.markdown(dict(SUMMARY, a1_hc_interval_ms=9.48)))

    def test_real_eyes(self):
        # The 202 eyes' statistics as their release states them (cases/real-eyes/README.md).
        norms = clinic.real_eyes()
        for key, mean, sd in (("deformation_amplitude_mm", 1.060, 0.109),
                              ("a2_velocity_m_s", -0.264, 0.035), ("hc_radius_mm", 8.06, 1.06),
                              ("da_ratio_2mm", 4.10, 0.39), ("integrated_radius_per_mm", 7.63, 1.02),
                              ("sp_a1_mmHg_per_mm", 114.2, 16.6)):
            self.assertAlmostEqual(norms[key][0], mean, delta=0.005 * abs(mean))
            self.assertAlmostEqual(norms[key][1], sd, delta=0.01 * sd + 0.001)
        # 1.15 mm: z = +0.83 against the real eyes, +1.0 against the normal eyes; the A1
        # velocity 0.2 m/s inwards: +2.8 against the real eyes.
        rows = {name: against for name, _, _, against in clinic.compare(SUMMARY)}
        self.assertAlmostEqual(rows["deformation amplitude"]["real eyes"][1],
                               (1.15 - norms["deformation_amplitude_mm"][0])
                               / norms["deformation_amplitude_mm"][1])
        self.assertEqual(clinic.within(SUMMARY), (1, 2))

    def test_timing(self):
        head, rows = timing.phases(SUMMARY)
        self.assertEqual([r[0] for r in rows], ["set-up", "puff", "total"])
        total = dict(zip(head, rows[-1]))
        self.assertEqual(total["wall [s]"], "3.50")
        self.assertEqual(total["Newton"], "7")
        self.assertEqual(dict(zip(head, rows[1]))["other [s]"], "0.50")  # 2.5 - 2.0 accounted

    def test_ablation_report(self):
        text = study.report(write_ablation(self.root / "study"))
        self.assertIn("| response | closed | open | difference | % |", text)
        self.assertIn("| deflection_amplitude_mm [mm] | 1 | 1.5 | +0.5 | +50.0 |", text)
        self.assertIn("- `closed`: the humor closed", text)
        self.assertTrue(text.endswith("2 of 2 converged; wall time per case 10 to 12 s"))
        plots = study.plot(self.root / "study")
        self.assertEqual([p.name for p in plots], ["variants.png"])

    def test_cohort_recovery(self):
        folder = self.root / "cohort"
        folder.mkdir()
        (folder / "cohort.csv").write_text(
            "patient,status,c10,c10_se,c10_lo,c10_hi,truth_c10,c10_inside\n"
            "P01,converged,0.05,0.002,0.046,0.054,0.052,1\n"
            "P02,failed,,,,,0.07,\n")
        rows, failed = cohort_figures.fitted(folder)
        self.assertEqual((len(rows), failed), (1, ["P02"]))
        table = cohort_figures.recovery(folder)[0]
        self.assertIn("| P01 | 0.052 | 0.05 | 0.002 | 0.046 - 0.054 | -3.8 % | yes |", table)
        self.assertTrue(table.endswith("c10: 1 of 1 truths inside their 95 % intervals"))

    def test_synthetic_readings_without_noise(self):
        run = Run(write_run(self.root / "run"))
        readings.synthetic(run, self.root / "data", sd_curve=0.0, sd_profile=0.0, every=1,
                           profile_times=[1.0], profile_x=[0.0, 1.0])
        apex = read_csv(self.root / "data" / "apex.csv")
        self.assertEqual(list(apex["value_mm"]), [0.0, -1.0])
        profiles = read_csv(self.root / "data" / "profiles.csv")
        np.testing.assert_allclose(profiles["y_mm"], [-1.0, -0.75])
        self.assertRegex((self.root / "data" / "biomarkers.toml").read_text(),
                         r'biomarker = "deflection_amplitude_mm"\nvalue = [0-9.]+\nsd = 0.08\n')


if __name__ == "__main__":
    unittest.main()
