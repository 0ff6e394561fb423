"""nct's post-processing: what reads the folders nct writes, used by the
tools in scripts/, the cases' runs in cases/ and the tests.

Modules:
- tables: the one CSV reader (read_csv -> Table: columns as float arrays,
  text where not numeric) and writer;
- folders: the folders nct writes, each file read once: Run (summary.json,
  frames.csv, profiles.csv as per-frame, per-surface curves, steps.csv,
  forces.csv, scene.toml), Study, Fit, Cohort;
- markdown: tables as Markdown or aligned text;
- clinic: the clinical norms of normal eyes and a run's z-scores;
- timing: where a run's wall time went, per phase;
- puff: a puff run's plots; the air's pressure on the cornea of any run;
- study: a study's plots and its report;
- fit: a fit's plots;
- cohort: a cohort's plots and its recovery table;
- readings: synthetic Corvis readings from a run, a synthetic cohort;
- cases: what the cases' runs share (paths, command line, running nct,
  results.md).

A script finds the package from its own place:
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "python"))
(two levels up for cases/<name>/run).
"""
