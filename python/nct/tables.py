"""The one CSV reader (and writer) of the project's Python: every table nct
writes (frames.csv, profiles.csv, steps.csv, cases.csv, cohort.csv...) and
every table of readings.

    table = read_csv("RUN/frames.csv")
    table["t_ms"]                  # a column: a float array, or str where not numeric
    table.columns                  # the header, in order
    len(table), table.rows()       # the rows, as dicts of Python values
    table.where(table["surface"] == "anterior")   # the rows of a mask

A column is numeric when every cell is a number (an empty cell is NaN);
otherwise it keeps its text (profiles.csv's `surface`, cases.csv's
`status`). `numeric=False` keeps every cell's text (to compare printed
digits).
"""
import csv

import numpy as np


class Table:
    """Columns of one CSV file, by name, all of one length."""

    def __init__(self, columns, data):
        self.columns = list(columns)
        self._data = {name: data[name] for name in self.columns}

    def __getitem__(self, name):
        return self._data[name]

    def __contains__(self, name):
        return name in self._data

    def __len__(self):
        return len(self._data[self.columns[0]]) if self.columns else 0

    def get(self, name, default=None):
        return self._data.get(name, default)

    def numeric(self, name):
        """Whether a column holds numbers."""
        return self._data[name].dtype.kind == "f"

    def where(self, mask):
        """The rows where mask (a boolean array) holds, as a Table."""
        return Table(self.columns, {c: self._data[c][mask] for c in self.columns})

    def rows(self):
        """Every row as a dict column -> float or str."""
        return [{c: self._data[c][i].item() for c in self.columns} for i in range(len(self))]


def _column(cells):
    try:
        return np.array([float(c) if c.strip() else np.nan for c in cells], dtype=float)
    except ValueError:
        return np.array(cells, dtype=str)


def read_csv(path, numeric=True):
    """The table in a CSV file with a header line; a row of another
    length than the header is an error naming the file and line."""
    with open(path, newline="") as f:
        lines = list(csv.reader(f))
    if not lines:
        raise ValueError(f"{path} is empty: no header")
    header = lines[0]
    for n, row in enumerate(lines[1:], start=2):
        if len(row) != len(header):
            raise ValueError(f"{path}:{n}: {len(row)} fields, the header has {len(header)}")
    # A name twice in the header is one column, the last, as
    # csv.DictReader reads it.
    cells = {name: [row[i] for row in lines[1:]] for i, name in enumerate(header)}
    convert = _column if numeric else (lambda c: np.array(c, dtype=str))
    names = list(dict.fromkeys(header))
    return Table(names, {name: convert(cells[name]) for name in names})


def write_csv(path, rows, columns=None):
    """Rows (dicts) as a CSV file, columns in the first row's order unless
    given; numbers as Python prints them."""
    columns = columns or list(rows[0])
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)
