"""The C++ emulator's fixture: an emulator trained with scikit-learn on the
made-up smooth model of tests/python/test_emulator.py, exported, and its
predictions and differences at a few points, for Emulator.* (tests/test_emulator.cpp).

emulator_fixture.py OUT    writes OUT/emulator.json and OUT/expected.json
"""
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "python"))
import test_emulator  # noqa: E402 (the made-up model and its training)
from nct import design, emulator  # noqa: E402

out = sys.argv[1]
os.makedirs(out, exist_ok=True)
points = design.to_box(design.maximin_hypercube(3, 30, seed=2, candidates=100), test_emulator.BOX)
em = test_emulator.quiet_train(test_emulator.data_at(points))
emulator.export(em, os.path.join(out, "emulator.json"))


def prediction(x):
    p = em.predict(x)
    return {"curves_mm": p["curves_mm"].tolist(), "curves_var_mm2": p["curves_var_mm2"].tolist(),
            "readings": p["readings"]}


cases = []
for x in ([0.05, 12.0, 0.5], [0.1, 30.0, 0.62], [0.031, 8.5, 0.46], [0.07, 20.0, 0.55]):
    x = np.array(x)
    differences = []
    for j in range(3):  # central differences of scikit-learn's mean
        h = 1e-4 * x[j]
        up, down = x.copy(), x.copy()
        up[j] += h
        down[j] -= h
        a, b = em.predict(up), em.predict(down)
        differences.append({"curves_mm": ((a["curves_mm"] - b["curves_mm"]) / (2 * h)).tolist(),
                            "readings": {k: (a["readings"][k][0] - b["readings"][k][0]) / (2 * h)
                                         for k in a["readings"]}})
    cases.append({"x": x.tolist(), "prediction": prediction(x), "differences": differences})
with open(os.path.join(out, "expected.json"), "w") as f:
    json.dump(cases, f)
print(f"emulator_fixture: {em.components} components, {len(em.readings)} readings -> {out}")
