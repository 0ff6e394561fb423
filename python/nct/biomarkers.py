"""The biomarker registry: every summary.json value studies compare and fits
read, with its unit and meaning, as `nct describe --biomarkers` exports it
(biomarkers.json beside this file; scripts/describe.sh regenerates it and a
test keeps it current).

    unit("hc_time_ms")                  # "ms"
    entry("aqueous_pressure_max_mmHg")  # the <cavity>_pressure_max_mmHg entry
"""
import json
import os

CAVITIES = ("cavity", "aqueous", "vitreous")

with open(os.path.join(os.path.dirname(__file__), "biomarkers.json")) as _f:
    REGISTRY = json.load(_f)


def entry(key):
    """The registry's entry of a summary.json key ({key, unit, meaning,
    reading}); "<cavity>" in an entry stands for a cavity's name. KeyError
    for a key it lacks."""
    for e in REGISTRY:
        if e["key"] == key:
            return e
        if e["key"].startswith("<cavity>"):
            rest = e["key"][len("<cavity>"):]
            if any(key == c + rest for c in CAVITIES):
                return e
    raise KeyError(f"{key} is not in the biomarker registry")


def unit(key):
    """A summary.json key's unit ("" for a number without one)."""
    return entry(key)["unit"]
