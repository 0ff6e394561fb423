"""The cornea's stiffness by age (nct.tissue) against closed forms."""
import unittest

import fixtures  # noqa: F401 (puts python/ on the path)
from nct import tissue


class Tissue(unittest.TestCase):
    def test_neo_hookean_limit(self):
        # No fibres and a vanishing pressure: the incompressible neo-Hookean
        # sheet's small-strain Young's modulus, E = 3 mu = 6 C10.
        self.assertAlmostEqual(tissue.membrane_modulus(0.05, 0.0, 100, 1e-4), 0.3, places=5)

    def test_fibres_stiffen_with_the_pressure(self):
        # sigma = 2 k1 e exp(k2 e^2) lambda^2 alone: E rises with the IOP.
        low = tissue.membrane_modulus(1e-6, 0.01, 100, 5.0)
        high = tissue.membrane_modulus(1e-6, 0.01, 100, 30.0)
        self.assertGreater(high, 1.5 * low)

    def test_age(self):
        self.assertAlmostEqual(tissue.modulus_at_age(20), 0.27)
        self.assertAlmostEqual(tissue.modulus_at_age(100), 0.52)
        s = tissue.age_scale(69)
        self.assertAlmostEqual(tissue.membrane_modulus(s * 0.05, s * 0.01, 100, 14.4),
                               tissue.modulus_at_age(69), places=9)
        self.assertAlmostEqual(s, 1.321, places=3)  # cases/real-eyes/median-eye.toml's


if __name__ == "__main__":
    unittest.main()
