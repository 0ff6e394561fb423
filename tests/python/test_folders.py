"""folders.Run: summary, frames, profiles parsed into sorted curves, steps,
scene, overrides; read_summary."""
import pathlib
import tempfile
import unittest

import numpy as np

from fixtures import write_run
from nct.folders import Run, read_summary


class RunFolder(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.run = Run(write_run(pathlib.Path(self.dir.name) / "run"))

    def tearDown(self):
        self.dir.cleanup()

    def test_summary_and_tables(self):
        self.assertEqual(self.run.summary["dofs"], 120)
        self.assertEqual(read_summary(self.run.folder)["dofs"], 120)
        self.assertEqual(read_summary(self.run.folder / "summary.json")["dofs"], 120)
        self.assertEqual(list(self.run.frames["apex_displacement_mm"]), [0.0, -1.0])
        self.assertEqual(list(self.run.steps["newton_iterations"]), [3.0, 4.0])
        self.assertEqual(self.run.scene["puff"]["peak"], 65.0)
        self.assertEqual(self.run.sets, ["inflate.iop=8"])
        self.assertTrue(self.run.finished)

    def test_profiles_per_frame_and_surface(self):
        p = self.run.profiles
        self.assertEqual(p.frames, [0, 1])
        self.assertEqual(list(p.t_ms), [0.0, 1.0])
        self.assertEqual(p.surfaces, ["anterior", "posterior"])
        x, y = p.curve(1, "anterior")
        self.assertEqual(list(x), [-2.0, -1.0, 0.0, 1.0, 2.0])  # sorted by x
        np.testing.assert_allclose(y, 9 + x * x / 4)
        self.assertEqual(p.curve(0, "posterior")[1][0], 9.5)
        self.assertEqual(p.nearest(0.8), 1)
        self.assertAlmostEqual(p.height(1, 0.5) - p.height(0, 0.5), -0.875)  # linear in between

    def test_missing_file(self):
        with self.assertRaises(FileNotFoundError):
            self.run.forces


if __name__ == "__main__":
    unittest.main()
