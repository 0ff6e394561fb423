#!/usr/bin/python3
"""Train an emulator on a training set, export it, validate it on held-out runs.

    /usr/bin/python3 scripts/emulator.py train DATA.json --out EMULATOR.json [--share S] [--seed N]
    /usr/bin/python3 scripts/emulator.py validate DATA.json HELD.json [--first N] [--share S]
    /usr/bin/python3 scripts/emulator.py sizes DATA.json HELD.json --sizes 20,40,60 [--plot PNG]

DATA.json and HELD.json are training sets (python/nct/training.py, as
cases/emulator-faithful-section/run writes them). `validate` trains on
DATA (its first N runs with --first) and prints the held-out report
(python/nct/validation.py) as Markdown; `sizes` does so for emulators
trained on the first n runs of a nested space-filling order of DATA
(farthest-point) for each n, as a table (and a plot).
"""
import argparse
import pathlib
import sys
import time
import warnings

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "python"))
from nct import emulator, training, validation  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("command", choices=["train", "validate", "sizes"])
    p.add_argument("data")
    p.add_argument("held", nargs="?")
    p.add_argument("--out")
    p.add_argument("--share", type=float, default=0.999)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--first", type=int)
    p.add_argument("--sizes")
    p.add_argument("--plot")
    a = p.parse_args()
    data = training.read(a.data)
    if a.command == "sizes":
        if not (a.held and a.sizes):
            p.error("sizes needs HELD.json and --sizes")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rows = validation.size_curve(data, training.read(a.held),
                                         [int(n) for n in a.sizes.split(",")], a.share, a.seed)
        print(validation.size_markdown(rows))
        if a.plot:
            validation.plot_size_curve(rows, a.plot)
        return
    if a.first:
        data["runs"] = data["runs"][:a.first]
    start = time.time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # hyperparameters at their bounds: in the report
        em = emulator.train(data, share=a.share, seed=a.seed)
    print(f"trained on {len(data['runs'])} runs in {time.time() - start:.1f} s: "
          f"{em.components} components, {len(em.readings)} readings", file=sys.stderr)
    if a.command == "train":
        if not a.out:
            p.error("train needs --out")
        emulator.export(em, a.out)
        print(f"emulator -> {a.out}", file=sys.stderr)
    else:
        if not a.held:
            p.error("validate needs HELD.json")
        print(validation.markdown(validation.validate(em, training.read(a.held))))


if __name__ == "__main__":
    main()
