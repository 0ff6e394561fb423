#!/usr/bin/python3
"""Plots of a study's analysis (the tables `nct study` writes).

    /usr/bin/python3 scripts/plot-study.py STUDY_FOLDER

writes into STUDY_FOLDER/plots correlation.png, main_effects.png and
pareto.png (a factorial or one-factor-at-a-time study), correlation.png (a
table design) or variants.png (an ablation); what each shows:
python/nct/study.py.
"""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "python"))
from nct import study  # noqa: E402
from nct.folders import Study  # noqa: E402


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    folder = Study(sys.argv[1])
    if not folder.has("analysis.json"):
        sys.exit(f"plot-study: {sys.argv[1]} has no analysis.json: "
                 "run `nct study` to the end first")
    study.plot(folder.folder)
    print(f"plot-study: {folder.analysis['design']}, {folder.analysis['cases']} cases -> "
          f"{folder.folder / 'plots'}")


if __name__ == "__main__":
    main()
