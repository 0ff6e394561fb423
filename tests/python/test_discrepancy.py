"""discrepancy: the mean and covariance of paired runs' differences."""
import unittest

import numpy as np

import fixtures  # noqa: F401 (puts the package on the path)
from nct import discrepancy


def run(case, x, shift):
    t = np.linspace(0, 1, 5)
    return {"case": case, "inputs": x, "apex_mm": (x[0] * t + shift).tolist(),
            "whole_eye_mm": (0 * t + shift / 2).tolist(),
            "profiles_mm": [[shift] * 7] * 3}


class Discrepancy(unittest.TestCase):
    def test_mean_and_covariance(self):
        shifts = [0.01, 0.03, 0.02]
        base = {"runs": [run(f"c{i}", [float(i)], 0.0) for i in range(3)]}
        fine = {"runs": [run(f"c{i}", [float(i)], s) for i, s in enumerate(shifts)]}
        d = discrepancy.estimate(fine, base)
        self.assertEqual(d["runs"], 3)
        mean, F = np.array(d["mean_mm"]), np.array(d["factor_mm"])
        self.assertAlmostEqual(mean[0], 0.02, places=12)
        self.assertAlmostEqual(mean[5], 0.01, places=12)     # the whole eye's half
        var = (F @ F.T)[0, 0]
        self.assertAlmostEqual(var, np.var(shifts, ddof=1) * (1 + 1 / 3), places=12)
        held = discrepancy.without(fine, base, "c0")
        self.assertAlmostEqual(held["mean_mm"][0], 0.025, places=12)

    def test_needs_pairs(self):
        base = {"runs": [run("a", [0.0], 0.0)]}
        fine = {"runs": [run("b", [1.0], 0.1), run("c", [2.0], 0.1)]}
        with self.assertRaises(ValueError):
            discrepancy.estimate(fine, base)


if __name__ == "__main__":
    unittest.main()
