"""nct's post-processing: what reads the folders nct writes, used by the
tools in scripts/, the cases' runs in cases/ and the tests.

Modules:
- tables: the one CSV reader (read_csv -> Table: columns as float arrays,
  text where not numeric) and writer;
- folders: the folders nct writes, each file read once: Run (summary.json,
  frames.csv, profiles.csv as per-frame, per-surface curves, steps.csv,
  forces.csv, scene.toml), Study, Fit, Cohort;
- markdown: tables as Markdown or aligned text;
- clinic: the clinical norms of normal eyes, a run's z-scores, the CBI;
- timing: where a run's wall time went, per phase;
- figures: matplotlib figures as PNG files or inline SVG;
- puff: a puff run's figures; the air's pressure on the cornea of any run;
- study: a study's figures and its Markdown report;
- fit: a fit's figures;
- cohort: a cohort's figures and its recovery table;
- posterior: a sampled posterior's pair figure and intervals;
- report: the web pages (`nct report DIR`: DIR/report.html);
- readings: synthetic Corvis readings from a run, a synthetic cohort;
- cases: what the cases' runs share (paths, command line, running nct,
  results.md).

A script finds the package from its own place:
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "python"))
(two levels up for cases/<name>/run).
"""
