"""design: the maximin Latin hypercube, its box, the study's factors."""
import tempfile
import unittest

import numpy as np
from scipy.spatial.distance import pdist
from scipy.stats import qmc

import fixtures  # noqa: F401 (puts the package on the path)
from nct import design
from nct.tables import read_csv


class Hypercube(unittest.TestCase):
    def test_one_point_per_slice_and_maximin(self):
        n, d = 20, 5
        x = design.maximin_hypercube(d, n, seed=3, candidates=200)
        self.assertEqual(x.shape, (n, d))
        for j in range(d):  # a Latin hypercube: each slice of each input once
            self.assertEqual(sorted(np.floor(x[:, j] * n).astype(int)), list(range(n)))
        # At least as spread as a typical single hypercube (the median of 200).
        typical = np.median([pdist(qmc.LatinHypercube(d, scramble=False, seed=s).random(n)).min()
                             for s in range(200)])
        self.assertGreater(pdist(x).min(), typical)

    def test_seed_repeats(self):
        a = design.maximin_hypercube(3, 10, seed=7, candidates=50)
        b = design.maximin_hypercube(3, 10, seed=7, candidates=50)
        c = design.maximin_hypercube(3, 10, seed=8, candidates=50)
        self.assertTrue(np.array_equal(a, b))
        self.assertFalse(np.array_equal(a, c))


class Box(unittest.TestCase):
    def test_linear_and_log(self):
        f = [design.Factor("iop", ["inflate.iop"], 8, 35, "linear"),
             design.Factor("c10", ["material.cornea.c10"], 0.01, 1.0, "log")]
        x = design.to_box(np.array([[0.0, 0.0], [0.5, 0.5], [1.0, 1.0]]), f)
        np.testing.assert_allclose(x[:, 0], [8, 21.5, 35])
        np.testing.assert_allclose(x[:, 1], [0.01, 0.1, 1.0])  # geometric: the middle is 0.1

    def test_written_inside_the_box(self):
        f = [design.Factor("c10", ["material.cornea.c10"], 0.03, 0.12, "log")]
        with tempfile.TemporaryDirectory() as d:
            design.write_design(d + "/x.csv", np.array([[0.0300000004], [0.119999999]]), f)
            t = read_csv(d + "/x.csv")
            self.assertEqual(list(t["c10"]), [0.03, 0.12])


class Factors(unittest.TestCase):
    def test_read_and_refuse(self):
        with tempfile.TemporaryDirectory() as d:
            path = d + "/s.toml"
            with open(path, "w") as out:
                out.write('[study]\ndesign = "table"\ncases = "x.csv"\n'
                          '[[factor]]\nlabel = "C10"\nkey = ["a.b", "c.d"]\nrange = [0.03, 0.12]\n'
                          'scale = "log"\n[[factor]]\nkey = "inflate.iop"\nrange = [8, 35]\n')
            f = design.read_factors(path)
            self.assertEqual([x.label for x in f], ["C10", "inflate.iop"])
            self.assertEqual((f[0].keys, f[0].scale, f[1].scale), (["a.b", "c.d"], "log", "linear"))
            with open(path, "w") as out:
                out.write('[study]\ndesign = "table"\n[[factor]]\nkey = "inflate.iop"\n')
            with self.assertRaisesRegex(ValueError, "factor\\[1\\] \\(inflate.iop\\) has no range"):
                design.read_factors(path)


if __name__ == "__main__":
    unittest.main()
