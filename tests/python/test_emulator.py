"""emulator: trained on a smooth function of three inputs, its exported
file's predictions are scikit-learn's, its gradient the differences', a
rebuild from the same data and seed the same file, an input outside the
box refused, and held-out points predicted within their stated error."""
import json
import tempfile
import unittest
import warnings

import numpy as np

import fixtures  # noqa: F401 (puts the package on the path)
from nct import design, emulator, training, validation

BOX = [design.Factor("c10", ["material.cornea.c10"], 0.03, 0.12, "log"),
       design.Factor("iop", ["inflate.iop"], 8.0, 35.0, "linear"),
       design.Factor("cct", ["geometry.cornea_central_thickness"], 0.45, 0.65, "linear")]
T = np.linspace(0, 20, 40)   # the frame clock [ms]


def model(x):
    """Curves, profiles and two readings of a made-up eye, smooth in x."""
    c10, iop, cct = x
    depth = 1.2 * (0.06 / c10) ** 0.5 * (15 / iop) ** 0.3 * (0.55 / cct)
    apex = -depth * np.sin(np.pi * T / 20) ** 2
    whole = 0.1 * apex * (iop / 15)
    profiles = [[-depth * s * (1 - xx ** 2 / 16) for xx in (-3, -2, -1, 0, 1, 2, 3)]
                for s in (0.5, 1.0, 0.5)]
    readings = {k: None for k in training.READINGS + ["iop_max_mmHg"]}
    readings["deformation_amplitude_mm"] = depth
    readings["hc_time_ms"] = 10 + 2 * (c10 - 0.06) / 0.06 - 0.01 * iop
    return {"t_ms": T.tolist(), "profile_t_ms": [5.0, 10.0, 15.0],
            "apex_mm": apex.tolist(), "whole_eye_mm": whole.tolist(),
            "profiles_mm": profiles, "readings": readings}


def data_at(points):
    box = [{"input": f.label, "keys": f.keys, "range": [f.low, f.high], "scale": f.scale}
           for f in BOX]
    runs = [{"case": f"case-{i:03d}", "inputs": list(map(float, x)), **model(x)}
            for i, x in enumerate(points, 1)]
    return {"inputs": [f.label for f in BOX], "box": box, "profile_x_mm": [-3, -2, -1, 0, 1, 2, 3],
            "runs": runs}


def quiet_train(data):
    """The emulator; the smooth made-up model drives some hyperparameters
    to their bounds, which scikit-learn warns of."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return emulator.train(data, seed=1, restarts=2)


class Emulator(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.points = design.to_box(design.maximin_hypercube(3, 30, seed=2, candidates=100), BOX)
        cls.data = data_at(cls.points)
        cls.em = quiet_train(cls.data)
        cls.dir = tempfile.TemporaryDirectory()
        cls.path = cls.dir.name + "/em.json"
        emulator.export(cls.em, cls.path)
        cls.exported = emulator.Exported(cls.path)

    @classmethod
    def tearDownClass(cls):
        cls.dir.cleanup()

    def test_next_wave_where_least_sure(self):
        region = {"c10": (0.04, 0.10), "iop": (10.0, 25.0)}
        points = design.least_sure(self.em, region, 5, seed=1, candidates=300)
        self.assertEqual(points.shape, (5, 3))
        self.assertTrue(np.all(points[:, 0] >= 0.04) and np.all(points[:, 0] <= 0.10))
        self.assertTrue(np.all(points[:, 1] >= 10.0) and np.all(points[:, 1] <= 25.0))
        unit = self.em.box.to_unit(points)
        gaps = [np.linalg.norm(unit[i] - unit[j]) for i in range(5) for j in range(i)]
        self.assertGreaterEqual(min(gaps), 0.15)
        # The first pick is the most uncertain candidate: no other beats it.
        var = lambda x: np.sum(self.em.predict(x)["curves_var_mm2"][:self.em.sizes[0]])  # noqa
        self.assertGreaterEqual(var(points[0]), var(points[1]))

    def test_exported_equals_sklearn(self):
        for x in ([0.05, 12.0, 0.5], [0.1, 30.0, 0.62]):
            a, b = self.em.predict(x), self.exported.predict(x)
            np.testing.assert_allclose(b["curves_mm"], a["curves_mm"], rtol=0, atol=1e-10)
            # The variance is c + noise - |L^-1 k*|^2: its last digits cancel.
            np.testing.assert_allclose(b["curves_var_mm2"], a["curves_var_mm2"], rtol=0,
                                       atol=1e-12)
            for key, (m, v) in a["readings"].items():
                self.assertAlmostEqual(b["readings"][key][0], m, delta=1e-10)
                self.assertAlmostEqual(b["readings"][key][1], v, delta=1e-12)

    def test_gradient_matches_differences(self):
        x = np.array([0.07, 20.0, 0.55])
        g = self.exported.gradient(x)
        # Central differences, their step large enough that the GP's
        # cancellation (large alpha of both signs) stays below the error.
        for j in range(3):
            h = 1e-4 * x[j]
            up, down = x.copy(), x.copy()
            up[j] += h
            down[j] -= h
            fd = (self.exported.predict(up)["curves_mm"]
                  - self.exported.predict(down)["curves_mm"]) / (2 * h)
            scale = np.max(np.abs(fd)) + 1e-12
            self.assertLess(np.max(np.abs(g["curves_mm"][:, j] - fd)) / scale, 1e-5)
            fd = (self.exported.predict(up)["readings"]["hc_time_ms"][0]
                  - self.exported.predict(down)["readings"]["hc_time_ms"][0]) / (2 * h)
            self.assertAlmostEqual(g["readings"]["hc_time_ms"][j], fd,
                                   delta=1e-5 * max(1.0, abs(fd)))

    def test_same_seed_same_file(self):
        again = quiet_train(self.data)
        path = self.dir.name + "/again.json"
        emulator.export(again, path)
        with open(self.path) as a, open(path) as b:
            self.assertEqual(json.load(a), json.load(b))

    def test_outside_the_box(self):
        with self.assertRaisesRegex(emulator.OutsideBox, r"iop = 40 is outside .*\[8, 35\]"):
            self.exported.predict([0.06, 40.0, 0.55])

    def test_held_out_within_stated_error(self):
        held = design.to_box(design.maximin_hypercube(3, 20, seed=9, candidates=50), BOX)
        z, rms = [], []
        for x in held:
            truth = np.hstack([model(x)["apex_mm"], model(x)["whole_eye_mm"],
                               np.ravel(model(x)["profiles_mm"])])
            p = self.exported.predict(x)
            e = p["curves_mm"] - truth
            rms.append(np.sqrt(np.mean(e ** 2)))
            z.append(e[len(T) // 2] / np.sqrt(p["curves_var_mm2"][len(T) // 2]))  # mid-puff apex
        self.assertLess(np.mean(rms), 0.01)            # half the device's noise
        self.assertGreaterEqual(np.mean(np.abs(z) < 2), 0.8)

    def test_validation_report(self):
        held = design.to_box(design.maximin_hypercube(3, 12, seed=9, candidates=50), BOX)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = validation.validate(self.em, data_at(held))
        self.assertEqual((r["runs"], r["train_runs"]), (12, 30))
        self.assertLess(r["apex_rms_um"], 10)
        self.assertGreaterEqual(r["curves_within_2"], 0.8)
        m = r["mahalanobis"]["component 1"]
        self.assertEqual(m["expected"], 12)
        self.assertLess(m["range"][0], 12)
        self.assertGreater(m["range"][1], 12)
        self.assertIn("| apex curve |", validation.markdown(r))

    def test_error_falls_with_training_size(self):
        held = design.to_box(design.maximin_hypercube(3, 8, seed=9, candidates=50), BOX)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rows = validation.size_curve(self.data, data_at(held), [8, 30])
        self.assertEqual([r["runs"] for r in rows], [8, 30])
        self.assertLess(rows[1]["apex_rms_um"], rows[0]["apex_rms_um"])


if __name__ == "__main__":
    unittest.main()
