"""training.collect: a table-design study's converged cases as a training set."""
import tempfile
import unittest
from pathlib import Path

import fixtures
from nct import training


class Collect(unittest.TestCase):
    def test_converged_cases_inputs_box_and_outputs(self):
        with tempfile.TemporaryDirectory() as d:
            study = Path(d)
            (study / "study.toml").write_text(
                '[study]\ndesign = "table"\ncases = "x.csv"\n'
                '[[factor]]\nlabel = "iop"\nkey = "inflate.iop"\nrange = [8.0, 35.0]\n')
            (study / "cases.csv").write_text(
                "case,status,iop,deflection_amplitude_mm,wall_s\n"
                "case-001,converged,12.5,1.1,3.5\ncase-002,failed,30,nan,2\n")
            fixtures.write_run(study / "cases" / "case-001")
            data = training.collect(study)
            self.assertEqual(data["inputs"], ["iop"])
            self.assertEqual(data["box"][0]["range"], [8.0, 35.0])
            self.assertEqual(len(data["runs"]), 1)  # the failed case is left out
            run = data["runs"][0]
            self.assertEqual((run["case"], run["inputs"]), ("case-001", [12.5]))
            self.assertEqual(run["apex_mm"], [0.0, -1.0])
            # Two frames: every profile time's nearest is the pushed one;
            # the surface moved by -(1 - x^2 / 4) within |x| <= 2.
            self.assertEqual(run["profile_t_ms"], [1.0, 1.0, 1.0])
            self.assertAlmostEqual(run["profiles_mm"][0][3], -1.0)     # x = 0
            self.assertAlmostEqual(run["profiles_mm"][0][2], -0.75)    # x = -1
            self.assertEqual(run["readings"]["a1_time_ms"], 0.5)
            self.assertIsNone(run["readings"]["a2_time_ms"])           # not in the summary
            path = study / "training.json"
            training.write(data, path)
            self.assertEqual(training.arrays(training.read(path), "apex_mm").shape, (1, 2))


if __name__ == "__main__":
    unittest.main()
