"""tables.read_csv: numeric and text columns, empty cells, masks, rows, errors."""
import math
import tempfile
import unittest

import fixtures  # noqa: F401 (puts the package on the path)
from nct.tables import read_csv, write_csv


class ReadCsv(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.path = self.dir.name + "/t.csv"

    def tearDown(self):
        self.dir.cleanup()

    def write(self, text):
        with open(self.path, "w") as f:
            f.write(text)

    def test_numbers_and_text(self):
        self.write("frame,surface,y_mm\n0,anterior,1.5\n1,posterior,\n")
        t = read_csv(self.path)
        self.assertEqual(t.columns, ["frame", "surface", "y_mm"])
        self.assertEqual(len(t), 2)
        self.assertTrue(t.numeric("frame") and not t.numeric("surface"))
        self.assertEqual(t["y_mm"][0], 1.5)
        self.assertTrue(math.isnan(t["y_mm"][1]))  # an empty cell
        self.assertEqual(list(t["surface"]), ["anterior", "posterior"])

    def test_where_and_rows(self):
        self.write("surface,x\na,1\nb,2\na,3\n")
        t = read_csv(self.path)
        a = t.where(t["surface"] == "a")
        self.assertEqual(list(a["x"]), [1.0, 3.0])
        self.assertEqual(a.rows(), [{"surface": "a", "x": 1.0}, {"surface": "a", "x": 3.0}])
        self.assertIsInstance(a.rows()[0]["surface"], str)

    def test_text_kept(self):
        self.write("t_ms,p\n0.10,1e-3\n")
        t = read_csv(self.path, numeric=False)
        self.assertEqual((t["t_ms"][0], t["p"][0]), ("0.10", "1e-3"))

    def test_ragged_row_is_an_error(self):
        self.write("a,b\n1,2\n3\n")
        with self.assertRaisesRegex(ValueError, r"t.csv:3: 1 fields, the header has 2"):
            read_csv(self.path)

    def test_a_name_twice_is_the_last_column(self):
        self.write("case,wall_s,wall_s\ncase-001,,10.5\n")  # cases.csv: a response and the wall time
        t = read_csv(self.path)
        self.assertEqual(t.columns, ["case", "wall_s"])
        self.assertEqual(t["wall_s"][0], 10.5)

    def test_header_only(self):
        self.write("a,b\n")
        self.assertEqual(len(read_csv(self.path)), 0)

    def test_write_then_read(self):
        write_csv(self.path, [{"patient": "P01", "age": 57}, {"patient": "P02", "age": 21}])
        t = read_csv(self.path)
        self.assertEqual(list(t["age"]), [57.0, 21.0])
        self.assertEqual(list(t["patient"]), ["P01", "P02"])


if __name__ == "__main__":
    unittest.main()
