#!/usr/bin/python3
"""Fuzz `nct check` with mutated scene files and junk --set overrides.

    fuzz_scenes.py NCT [--seed S] [--count N] [--case I] [--timeout T]
                       [--jobs J] [--keep DIR]

Every mutation of the shipped scenes (scenes/, tests/scenes/, tests/bad/)
must give either `ok` (exit 0: the mutation happened to stay valid) or a
clear input error: exit 2 and a message on stderr that starts with
"error: " and names the scene file or the offending argument. A timeout,
a signal, exit 1 (an unhandled exception) or any other code is a defect,
and so is exit 0 for a mutation that cannot be valid (an unknown key, a
wrong type, a value out of range, ...).

Case I of seed S is the same on every run (--case I reruns it alone).
Failing cases are written to DIR (default: ./fuzz_scenes_failures) with
their output and the command that reproduces them. Standard library only.
"""

import argparse
import os
import random
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SEED_DIRS = ["scenes", "tests/scenes", "tests/bad"]
DATA_DIRS = ["scenes/tables", "meshes"]
DATA_FILES = ["tests/bad/puff_table.csv"]

# Texts that betray a crash or an unhandled exception even under exit 2.
CRASH_TEXTS = ["terminate called", "Segmentation", "segmentation fault", "what():",
               "Aborted", "core dumped", "PETSC ERROR", "MPI_ABORT", "bad optional",
               "bad_optional", "std::", "logic_error", "is not declared", "Assertion",
               "stack smashing", "double free", "malloc()", "error (rank"]

# ----------------------------------------------------------------------------
# The declared keys, from `nct describe`


class Key:
    def __init__(self, name, default, accepted):
        self.name, self.default, self.accepted = name, default, accepted
        self.choices = re.findall(r'"([^"]*)"', accepted) if accepted.startswith("one of") else []
        self.lo = self.hi = None
        m = re.search(r"in \[([^,\]]+), ([^\]]+)\]", accepted)
        if m:
            self.lo, self.hi = float(m.group(1)), float(m.group(2))
        if accepted.startswith("one of"):
            self.kind = "choice"
        elif accepted.startswith("an integer"):
            self.kind = "integer"
        elif accepted.startswith("a number"):
            self.kind = "real"
        elif accepted.startswith("true or false"):
            self.kind = "boolean"
        elif accepted.startswith("an array of strings"):
            self.kind = "strings"
        elif accepted.startswith("an array of numbers"):
            self.kind = "reals"
        elif accepted.startswith("an array of [x, y, z]"):
            self.kind = "points"
        elif accepted.startswith("a table"):
            self.kind = "options"
        elif accepted.startswith("a string"):
            self.kind = "string"
        else:
            raise SystemExit("fuzz_scenes: cannot read the kind of %s from '%s'" % (name, accepted))

    def section(self):
        return self.name.rsplit(".", 1)[0]

    def leaf(self):
        return self.name.rsplit(".", 1)[1]


def read_keys(nct):
    out = subprocess.run([nct, "describe"], capture_output=True, text=True, timeout=60)
    if out.returncode != 0:
        raise SystemExit("fuzz_scenes: `nct describe` failed:\n" + out.stderr)
    keys, lines = [], out.stdout.splitlines()
    for i, line in enumerate(lines):
        m = re.match(r"^([A-Za-z0-9_.*]+) = (.*?)(  \[[^\]]*\])?$", line)
        if m and i + 1 < len(lines) and lines[i + 1].startswith("    "):
            accepted = lines[i + 1].strip().split(". ")[0]
            keys.append(Key(m.group(1), m.group(2), accepted))
    if len(keys) < 20:
        raise SystemExit("fuzz_scenes: `nct describe` listed only %d keys" % len(keys))
    return keys


def declared(keys, name):
    """Does a dotted name match a declared key (with its "*" segments)?"""
    parts = name.split(".")
    for k in keys:
        kp = k.name.split(".")
        if len(kp) == len(parts) and all(a == "*" or a == b for a, b in zip(kp, parts)):
            return True
    return False


# ----------------------------------------------------------------------------
# A scene file as lines, with its tables and keys


HEADER = re.compile(r"^\s*\[\s*([A-Za-z0-9_.-]+)\s*\]\s*(#.*)?$")
ENTRY = re.compile(r"^\s*([A-Za-z0-9_-]+)\s*=")


class Doc:
    def __init__(self, text):
        self.lines = text.split("\n")

    def text(self):
        return "\n".join(self.lines)

    def headers(self):
        return [(i, m.group(1)) for i, l in enumerate(self.lines) for m in [HEADER.match(l)] if m]

    def entries(self):
        """(line, section, key) of every `key = value` line."""
        out, section = [], ""
        for i, l in enumerate(self.lines):
            h = HEADER.match(l)
            if h:
                section = h.group(1)
            elif l.lstrip().startswith("["):
                section = None  # [[array of tables]] or worse: not ours
            else:
                e = ENTRY.match(l)
                if e and section is not None:
                    out.append((i, section, e.group(1)))
        return out

    def sections(self):
        return [name for _, name in self.headers()]

    def set(self, section, leaf, value):
        """Give section.leaf this TOML text, replacing it or adding it."""
        for i, s, k in self.entries():
            if s == section and k == leaf:
                self.lines[i] = "%s = %s" % (leaf, value)
                return
        if section == "":
            self.lines.insert(0, "%s = %s" % (leaf, value))
            return
        for i, name in self.headers():
            if name == section:
                self.lines.insert(i + 1, "%s = %s" % (leaf, value))
                return
        self.lines += ["", "[%s]" % section, "%s = %s" % (leaf, value)]

    def section_span(self, header_index):
        end = header_index + 1
        while end < len(self.lines) and not self.lines[end].lstrip().startswith("["):
            end += 1
        return header_index, end


# ----------------------------------------------------------------------------
# Values


TYPE_SAMPLES = {
    "string": ['"five"', '"1.0"', '""', '"true"', '"[1, 2]"'],
    "integer": ["5", "0", "-3", "1"],
    "float": ["5.5", "1e3", "0.0", "-2.5"],
    "bool": ["true", "false"],
    "array": ["[1, 2]", '["a"]', "[[1, 2, 3]]", "[true]", "[1.5]"],
    "table": ["{ a = 1 }", "{}", '{ x = "y" }'],
    "datetime": ["1979-05-27T07:32:00Z", "1979-05-27", "07:32:00", "1979-05-27T07:32:00"],
}
# The TOML types each kind of key accepts (the rest are wrong).
ACCEPTS = {
    "boolean": {"bool"},
    "integer": {"integer"},
    "real": {"integer", "float"},
    "choice": {"string"},
    "string": {"string"},
    "strings": set(),
    "reals": set(),
    "points": set(),
    "options": set(),
}
BAD_ARRAYS = {
    "strings": ["[1, 2]", '[["a"]]', '["a", 1]', "[{ a = 1 }]", "[true]", "[1979-05-27]"],
    "reals": ['["a"]', "[[1.0]]", '[1.0, "a"]', "[true]", "[{ x = 1 }]", "[nan]", "[inf]",
              "[1979-05-27]"],
    "points": ["[1, 2, 3]", "[[1, 2]]", "[[1, 2, 3, 4]]", '[["a", 0, 0]]', "[[true, 0, 0]]",
               "[[]]", "[[[1, 2, 3]]]", "[[1, 2, 3], [1, 2]]", "[{ x = 1 }]"],
    "options": ["{ a = { b = 1 } }", "{ a = [1] }", "{ a = 1979-05-27 }", "[1]", '"-ksp_type cg"'],
}


def wrong_type(rng, key):
    choices = [v for t, vs in TYPE_SAMPLES.items() if t not in ACCEPTS[key.kind] for v in vs]
    if key.kind in ("strings", "reals", "points", "options"):
        choices = [v for v in choices if v not in ("{}",) and not v.startswith(("[", "{"))]
        choices += BAD_ARRAYS[key.kind] * 2
    return rng.choice(choices)


def fmt(x):
    return repr(float(x)) if not float(x).is_integer() or abs(x) >= 1e16 else "%.1f" % x


def out_of_range(rng, key):
    """A number outside the key's range (its kind right when possible)."""
    lo, hi = key.lo, key.hi
    if lo is None:
        return None
    v = []
    if key.kind == "integer":
        v += [str(int(lo) - 1), str(int(lo) - 1000), str(int(hi) + 1), str(int(hi) * 1000 + 7),
              "9223372036854775807", "-9223372036854775808"]
        if lo > 0:
            v.append("0")
        if lo > -1:
            v.append("-1")
    else:
        span = max(1.0, abs(lo))
        v += [fmt(lo - span), fmt(hi + max(1.0, abs(hi))), "1e308", "-1e308", "1.7976931348623157e308",
              "9007199254740993", "-9007199254740993", "9223372036854775807", fmt(hi * 10 + 1)]
        if lo > 0:
            v += ["0", "0.0", "-0.0", fmt(lo / 2)]
        if lo > -1:
            v += ["-1", "-1e-300" if lo >= 0 else "-1"]
    return rng.choice(v)


NONFINITE = ["inf", "-inf", "+inf", "nan", "-nan", "+nan"]
HUGE = ["1e400", "-1e400", "1e-400", "9007199254740993", "-9223372036854775808", "99999999999999999999",
        "0x7fffffffffffffff", "0xffffffffffffffffff", "1" + "0" * 400, "0." + "0" * 5000 + "1",
        "1e99999999999", "1_000_000_000_000", "0o777", "0b" + "1" * 70, "1.0e+308"]


def bad_choice(rng, key):
    c = rng.choice(key.choices) if key.choices else "x"
    return rng.choice([
        '"%s"' % c.upper(), '"%s "' % c, '" %s"' % c, '""', '"%s_"' % c, '"%s"' % c[:-1],
        '"%s\\u0000"' % c, '"%s\\n"' % c, '"\u00fc%s"' % c, '"%s"' % (c + "x" * 100000),
        "'%s2'" % c, '"""%sX"""' % c, '"none_of_them"', '"%s,%s"' % (c, c)])


UNICODE = ["\u00fc", "\u4e2d\u6587", "\U0001F600", "\u202e", "\u200b", "\ufeff", "\u0301", "\u00e9\u00e9",
           "\u0421", "\ud7ff"]


# ----------------------------------------------------------------------------
# Mutations: each returns (content, extra args, must_fail, note)


class Ctx:
    def __init__(self, rng, keys, seed_path, text):
        self.rng, self.keys, self.seed_path, self.text = rng, keys, seed_path, text
        self.doc = Doc(text)

    def key(self, kinds=None, present_first=True):
        """A declared key (one the seed sets, half the time), '*' named."""
        rng = self.rng
        pool = [k for k in self.keys if kinds is None or k.kind in kinds]
        present = []
        for _, s, leaf in self.doc.entries():
            for k in pool:
                if declared([k], s + "." + leaf):
                    present.append((k, s, leaf))
        if present and present_first and rng.random() < 0.5:
            return rng.choice(present)
        k = rng.choice(pool)
        section = k.section()
        if "*" in section:
            parts = [s for s in self.doc.sections() if s.startswith("material.")]
            section = rng.choice(parts) if parts and rng.random() < 0.7 else \
                section.replace("*", rng.choice(["tissue", "shell", "part", "x"]))
        return k, section, k.leaf()

    def set(self, section, leaf, value):
        self.doc.set(section, leaf, value)
        return self.doc.text()


def ident(rng, n=None):
    n = n or rng.randint(1, 12)
    return "".join(rng.choice("abcdefghijklmnopqrstuvwxyz_0123456789") for _ in range(n))


def m_unknown_key(c):
    rng = c.rng
    sections = [s for s in c.doc.sections() if not s.startswith("solver.petsc")]
    known = sorted({k.section() for k in c.keys if "*" not in k.name and k.kind != "options"})
    leaf = "zz_" + ident(rng)
    value = rng.choice(["1", '"x"', "true", "[]", "{}", "1.5"])
    what = rng.randrange(5)
    if what == 0 and sections:
        s = rng.choice(sections)
    elif what == 1:
        s = rng.choice(known)
    elif what == 2:
        s = "zz_" + ident(rng)
    elif what == 3:
        s = rng.choice(known) + ".zz_" + ident(rng)
    else:
        s = ""
    if rng.random() < 0.15 and s:
        # an unknown table alone, without keys
        s = (s + ".zz_" if s else "zz_") + ident(rng)
        return c.text + "\n[%s]\n" % s, [], True, "empty unknown table [%s]" % s
    return c.set(s, leaf, value), [], True, "%s.%s = %s" % (s, leaf, value)


def misspell(rng, word):
    i = rng.randrange(len(word))
    op = rng.randrange(6)
    if op == 0 and len(word) > 1:
        return word[:i] + word[i + 1:]
    if op == 1 and i + 1 < len(word) and word[i] != word[i + 1]:
        return word[:i] + word[i + 1] + word[i] + word[i + 2:]
    if op == 2:
        return word[:i] + word[i] + word[i:]
    if op == 3:
        return word[:i] + rng.choice("abcdefghijklmnopqrstuvwxyz_-") + word[i + 1:]
    if op == 4:
        return word.upper()
    return word + rng.choice(["s", "_", "-", "2"])


def m_misspelt_key(c):
    rng = c.rng
    entries = [(i, s, k) for i, s, k in c.doc.entries() if not s.startswith("solver.petsc")]
    if entries and rng.random() < 0.8:
        i, s, k = rng.choice(entries)
        for _ in range(20):
            bad = misspell(rng, k)
            if bad != k and not declared(c.keys, s + "." + bad):
                c.doc.lines[i] = c.doc.lines[i].replace(k, bad, 1)
                return c.doc.text(), [], True, "%s.%s -> %s" % (s, k, bad)
    headers = [(i, n) for i, n in c.doc.headers() if not n.startswith("solver.petsc")]
    if headers:
        i, n = rng.choice(headers)
        first, _, rest = n.partition(".")
        for _ in range(20):
            bad = misspell(rng, first)
            name = bad + ("." + rest if rest else "")
            if bad != first and not any(k.name.startswith(bad + ".") for k in c.keys):
                c.doc.lines[i] = "[%s]" % name
                return c.doc.text(), [], True, "[%s] -> [%s]" % (n, name)
    k, s, leaf = c.key()
    return c.set(s, misspell(rng, leaf) + "zz", k.default), [], True, "misspelt new key"


def m_wrong_type(c):
    k, s, leaf = c.key()
    v = wrong_type(c.rng, k)
    return c.set(s, leaf, v), [], True, "%s.%s (%s) = %s" % (s, leaf, k.kind, v)


def m_out_of_range(c):
    k, s, leaf = c.key(kinds=("integer", "real", "reals"))
    v = out_of_range(c.rng, k)
    if k.kind == "reals":
        v = "[%s]" % v
    return c.set(s, leaf, v), [], True, "%s.%s in [%s, %s] = %s" % (s, leaf, k.lo, k.hi, v)


def m_nonfinite(c):
    rng = c.rng
    if rng.random() < 0.25:
        k, s, leaf = c.key(kinds=("points",))
        p = [rng.choice(["0", "1.5"]) for _ in range(3)]
        p[rng.randrange(3)] = rng.choice(NONFINITE)
        v = "[[%s]]" % ", ".join(p)
    else:
        k, s, leaf = c.key(kinds=("real", "integer"))
        v = rng.choice(NONFINITE)
    return c.set(s, leaf, v), [], True, "%s.%s = %s" % (s, leaf, v)


def m_huge_number(c):
    k, s, leaf = c.key(kinds=("real", "integer", "points"))
    v = c.rng.choice(HUGE)
    if k.kind == "points":
        v = "[[%s, 0, 0]]" % v
    return c.set(s, leaf, v), [], False, "%s.%s = %s" % (s, leaf, v[:60])


def m_bad_choice(c):
    k, s, leaf = c.key(kinds=("choice",))
    v = bad_choice(c.rng, k)
    return c.set(s, leaf, v), [], True, "%s.%s = %s" % (s, leaf, v[:60])


def m_bad_path(c):
    rng = c.rng
    k, s, leaf = c.key(kinds=("string",))
    ext = ".msh" if leaf == "file" else ".csv"
    v = rng.choice(['""', '"/"', '"."', '".."', '"tables"', '"no/such/file%s"' % ext,
                    '"%s%s"' % ("x" * rng.choice([255, 256, 5000, 100000]), ext),
                    '"%s%s"' % ("d/" * 3000, ext), '"\\u0000"', '"nope\\u0000%s"' % ext,
                    '"/dev/null"', '"/proc/self/mem"', '"\u00fc\U0001F600%s"' % ext, '"%s\\n"' % ext,
                    '"C:\\\\mesh%s"' % ext, "'~/x%s'" % ext])
    return c.set(s, leaf, v), [], True, "%s.%s = %s" % (s, leaf, v[:60])


def m_long_string(c):
    rng = c.rng
    n = rng.choice([1000, 10000, 100000, 1000000])
    what = rng.randrange(4)
    if what == 0:
        k, s, leaf = c.key(kinds=("choice", "real", "integer", "boolean"))
        return c.set(s, leaf, '"%s"' % ("x" * n)), [], True, "%s.%s = %d chars" % (s, leaf, n)
    if what == 1:
        s = rng.choice(c.doc.sections() or ["mesh"])
        if s.startswith("solver.petsc"):
            s = "mesh"
        return c.set(s, "k" * n, "1"), [], True, "key of %d chars in [%s]" % (n, s)
    if what == 2:
        return c.text + "\n[%s]\nx = 1\n" % ("t" * n), [], True, "table name of %d chars" % n
    # a long comment: valid
    return c.text + "\n# " + "c" * n + "\n", [], False, "comment of %d chars" % n


def m_duplicate_key(c):
    rng = c.rng
    entries = c.doc.entries()
    if not entries:
        return "[mesh]\nlayers = 3\nlayers = 4\n", [], True, "layers twice"
    i, s, k = rng.choice(entries)
    line = c.doc.lines[i]
    if rng.random() < 0.3:
        line = '"%s" = 1' % k  # the same key, quoted
    c.doc.lines.insert(i + rng.choice([1, 0]) if rng.random() < 0.5 else i + 1, line)
    return c.doc.text(), [], True, "%s.%s twice" % (s, k)


def m_duplicate_table(c):
    rng = c.rng
    headers = c.doc.headers()
    if not headers:
        return c.text + "\n[mesh]\n[mesh]\n", [], True, "[mesh] twice"
    i, n = rng.choice(headers)
    what = rng.randrange(4)
    if what == 0:
        return c.text + "\n[%s]\n" % n, [], True, "[%s] twice" % n
    if what == 1:
        a, b = c.doc.section_span(i)
        return c.text + "\n" + "\n".join(c.doc.lines[a:b]) + "\n", [], True, "[%s] and body twice" % n
    if what == 2:
        return c.text + "\n[[%s]]\n" % n, [], True, "[[%s]] after [%s]" % (n, n)
    first = n.split(".")[0]
    return c.text + "\n%s = 1\n" % first if "." in n else \
        "%s = { x = 1 }\n" % first + c.text, [], True, "%s redefined by a key" % first


def m_truncate(c):
    data = c.text.encode()
    cut = c.rng.randrange(len(data) + 1)
    return data[:cut], [], False, "cut at byte %d of %d" % (cut, len(data))


def m_byte_flip(c):
    rng = c.rng
    data = bytearray(c.text.encode())
    n = rng.choice([1, 1, 2, 4, 16])
    for _ in range(n):
        if not data:
            break
        j = rng.randrange(len(data))
        data[j] = rng.choice([rng.randrange(256), ord(rng.choice('[]"=.,{}#\n\\\'')), data[j] ^ (1 << rng.randrange(8))])
    return bytes(data), [], False, "%d byte(s) changed" % n


def m_garbage(c):
    rng = c.rng
    n = rng.choice([1, 16, 300, 4096, 65536])
    what = rng.randrange(4)
    if what == 0:
        return bytes(rng.randrange(256) for _ in range(n)), [], False, "%d random bytes" % n
    if what == 1:
        alphabet = '[]{}"\'=.,#\n\t abcxyz0123456789-+_\\'
        return "".join(rng.choice(alphabet) for _ in range(n)).encode(), [], False, "%d TOML-ish chars" % n
    data = c.text.encode()
    j = rng.randrange(len(data) + 1)
    junk = bytes(rng.randrange(256) for _ in range(min(n, 512)))
    if what == 2:
        return data[:j] + junk + data[j:], [], False, "%d random bytes inserted" % len(junk)
    return data + b"\n" + junk, [], False, "%d random bytes appended" % len(junk)


def m_empty(c):
    v = c.rng.choice([b"", b"\n", b"   \n\t\n", b"# only a comment\n", b"\xef\xbb\xbf", b"\x00",
                      b"\r\n\r\n", b"\r", b"[]", b"=", b"\"\"=", b"\xff\xfe"])
    return v, [], False, "content %r" % v


def m_delete(c):
    rng = c.rng
    headers = c.doc.headers()
    if headers and rng.random() < 0.6:
        i, n = rng.choice(headers)
        a, b = c.doc.section_span(i)
        if rng.random() < 0.5:
            b = a + 1  # the header only: its keys join the table before
        del c.doc.lines[a:b]
        return c.doc.text(), [], False, "deleted [%s]%s" % (n, "" if b > a + 1 else " header")
    if c.doc.lines:
        j = rng.randrange(len(c.doc.lines))
        line = c.doc.lines.pop(j)
        return c.doc.text(), [], False, "deleted line %d: %s" % (j + 1, line[:40])
    return c.text, [], False, "nothing to delete"


def m_delete_required(c):
    """A file mesh needs [mesh] file, materials and boundaries; a table puff its table."""
    rng = c.rng
    headers = c.doc.headers()
    required = [(i, n) for i, n in headers if n in ("mesh", "boundary") or n.startswith("material.")]
    file_scene = any(s == "mesh" and k == "file" for _, s, k in c.doc.entries())
    table_lines = [i for i, s, k in c.doc.entries() if s == "puff" and k == "table"]
    valid_seed = not c.seed_path.startswith("tests/bad/")
    if file_scene and required:
        i, n = rng.choice(required)
        a, b = c.doc.section_span(i)
        del c.doc.lines[a:b]
        return c.doc.text(), [], valid_seed, "deleted required [%s]" % n
    if table_lines:
        del c.doc.lines[table_lines[0]]
        return c.doc.text(), [], True, "deleted puff.table"
    # otherwise: the mesh file of a file scene, named in an eye scene
    return c.set("mesh", "source", '"file"'), [], True, "mesh.source = file without mesh.file"


def m_unicode(c):
    rng = c.rng
    u = rng.choice(UNICODE)
    what = rng.randrange(8)
    if what == 0:
        k, s, leaf = c.key(kinds=("choice",))
        return c.set(s, leaf, '"%s%s"' % (rng.choice(k.choices), u)), [], True, "choice + %r" % u
    if what == 1:
        s = rng.choice(c.doc.sections() or ["mesh"])
        if s.startswith("solver.petsc"):
            s = "mesh"
        return c.set(s, '"%s"' % (u + "layers"), "3"), [], True, "quoted unicode key"
    if what == 2:
        return c.text + "\n%s = 1\n" % u, [], True, "bare unicode key %r" % u
    if what == 3:
        bad = rng.choice([b"\xff", b"\xc0\xaf", b"\xed\xa0\x80", b"\xf4\x90\x80\x80", b"\xe2\x82", b"\x80"])
        return c.text.encode() + b'\n[mesh]\nfile = "x' + bad + b'"\n', [], True, "invalid UTF-8 %r" % bad
    if what == 4:
        return c.text + '\n[mesh]\nfile = "\\uD800"\n', [], True, "surrogate escape"
    if what == 5:
        return b"\xef\xbb\xbf" + c.text.encode(), [], False, "BOM"
    if what == 6:
        return c.text + "\n# %s\n" % (u * 50), [], False, "unicode comment"
    k, s, leaf = c.key(kinds=("strings",))
    return c.set(s, leaf, '["%s"]' % u), [], False, "strings [%r]" % u


def m_deep_nesting(c):
    rng = c.rng
    d = rng.choice([2, 10, 255, 256, 257, 1000, 30000, 100000])
    what = rng.randrange(5)
    if what == 0:
        k, s, leaf = c.key()
        return c.set(s, leaf, "[" * d + "]" * d), [], True, "%s.%s = array nested %d deep" % (s, leaf, d)
    if what == 1:
        k, s, leaf = c.key()
        return c.set(s, leaf, "{ a = " * d + "1" + " }" * d), [], True, "inline tables %d deep" % d
    if what == 2:
        return c.text + "\n" + ".".join(["a"] * d) + " = 1\n", [], True, "dotted key %d deep" % d
    if what == 3:
        return c.text + "\n[%s]\n" % ".".join(["a"] * d), [], True, "table header %d deep" % d
    return c.text + "\n[material.%s]\nx = 1\n" % ".".join(["m"] * d), [], True, "material table %d deep" % d


def m_table_name(c):
    """Odd part names under [material]: they become dotted paths."""
    name = c.rng.choice(['"a.b"', '"x[0]"', '"]"', '"["', '""', '" "', '"\u00fc"', '"a b"', '"[0]"',
                        '"."', '"tissue.model"', "'lit.eral'", '"*"', '"t*"'])
    key = c.rng.choice(['model = "hgo"', "c10 = 0.5", "fibre_directions = [[1.0, 0.0, 0.0]]"])
    return c.text + "\n[material.%s]\n%s\n" % (name, key), [], True, "[material.%s] %s" % (name, key)


def m_structure(c):
    """TOML that is valid but not a scene's shape."""
    rng = c.rng
    k, s, leaf = c.key()
    v = rng.choice(["[[%s]]\n%s = 1\n" % (s, leaf), "%s = 1\n" % s.split(".")[0],
                    "[%s.%s]\nx = 1\n" % (s, leaf), "%s = [{ a = 1 }]\n" % s.split(".")[0],
                    '"%s.%s" = 1\n' % (s, leaf), "%s = []\n" % s.split(".")[0]])
    if rng.random() < 0.5:
        return v + c.text, [], True, "prefixed %r" % v.strip()
    return c.text + "\n" + v, [], True, "appended %r" % v.strip()


SET_JUNK = [
    # (argument, must_fail)
    ("foo", True), ("a.b=", True), ("=1", True), ("=", True), (".=1", True), ("..=1", True),
    ("mesh.layers=1e400", True), ('mesh.source=fi"le', True), ("mesh=5", True),
    ("mesh.layers.x=1", True), ("mesh.layers=", True), ("mesh.layers=[1,2", True),
    ("mesh.layers={", True), ("puff.peak=1 2", True), ('mesh.file="', True), ("mesh.file='", True),
    ("solver.petsc={a={b=1}}", True), ("solver.petsc.ksp_type=cg", False), ("material.*.c10=1", True),
    ('material."a.b".c10=1', True), ("x" * 10000 + "=1", True), ("mesh.layers=5\nfoo = 3", True),
    ("mesh.layers=5\n[mesh]\nlayers = 6", True), ("mesh.layers=4 # comment", False),
    ("\u043a\u043b\u044e\u0447=1", True), ("mesh.layers=\x7f", True), ("mesh.source=\t", True),
    ("mesh.layers=0x10", True), ("mesh.layers=+5", False), ("mesh.layers=05", True),
    ("mesh.layers=5_000", True), ("output.probes=[[1,2,3]]", False), ("output.probes=[[1,2]]", True),
    ("inflate.iop=nan", True), ("inflate.iop=-inf", True), ("inflate.iop=9007199254740993", True),
    ("output.probes=[[9007199254740993,0,0]]", False), ("puff.load=air\n", True),
    ("mesh.source=file", False), ("mesh.source=\"eye", True), ("mesh.source='eye'", False),
    ("mesh.source=\"\"\"eye\"\"\"", False), ("mesh.source=eye\\", True), ("a.b.c.d.e.f.g=1", True),
    ("mesh.layers=" + "[" * 300, True), ("mesh.layers=" + "{a=" * 300, True),
    (".mesh.layers=3", True), ("mesh..layers=3", True), ("mesh.layers.=3", True),
    ("mesh.layers==3", True), ("mesh.layers=3=3", True), (" mesh.layers=3", True),
    ("mesh.layers =3", True), ("solver.petsc=", True), ("solver.petsc.=1", False),
]


def m_set_junk(c):
    arg, must_fail = c.rng.choice(SET_JUNK)
    args = ["--set", arg]
    if c.rng.random() < 0.3:  # before the junk: the last --set of a key wins
        args = ["--set", "inflate.steps=3"] + args
    return c.text, args, must_fail, "--set %r" % arg[:60]


def m_set_random(c):
    rng = c.rng
    k, s, leaf = c.key(present_first=False)
    gen = [wrong_type]
    if k.kind in ("integer", "real"):
        gen += [out_of_range, lambda r, k: r.choice(NONFINITE)]
    if k.kind == "choice":
        gen.append(bad_choice)
    v = rng.choice(gen)(rng, k)
    if rng.random() < 0.3:
        s = misspell(rng, s)
        if declared(c.keys, s + "." + leaf) or s.startswith("solver.petsc"):
            s = s + "zz"
    arg = "%s.%s=%s" % (s, leaf, v)
    return c.text, ["--set", arg], True, "--set %r" % arg[:60]


def m_cli_junk(c):
    """Junk on the command line itself."""
    args = c.rng.choice([["--set"], ["--set", "-x"], ["--nope"], ["--set", ""], ["extra_positional"],
                         ["--set", "--set"], ["-s"], ["--set=mesh.layers=3", "--set"],
                         ["--", "--set"], ["--set", "mesh.layers=3", "--out"]])
    return c.text, args, True, "args %r" % args


def m_scene_path(c):
    """A scene path that is not a scene file (replaces the file's path)."""
    p = c.rng.choice(["x" * 300 + ".toml", "x" * 5000 + ".toml", "no/such/dir/scene.toml", "",
                      ".", "/", "/dev/null", "scene.toml\n", "/proc/self/mem", "../" * 2000 + "a.toml"])
    return None, [p], True, "scene path %r" % p[:40]


MUTATIONS = [
    ("unknown_key", m_unknown_key), ("misspelt_key", m_misspelt_key), ("wrong_type", m_wrong_type),
    ("out_of_range", m_out_of_range), ("nonfinite", m_nonfinite), ("huge_number", m_huge_number),
    ("bad_choice", m_bad_choice), ("bad_path", m_bad_path), ("long_string", m_long_string),
    ("duplicate_key", m_duplicate_key), ("duplicate_table", m_duplicate_table),
    ("truncate", m_truncate), ("byte_flip", m_byte_flip), ("garbage", m_garbage), ("empty", m_empty),
    ("delete", m_delete), ("delete_required", m_delete_required), ("unicode", m_unicode),
    ("deep_nesting", m_deep_nesting), ("table_name", m_table_name), ("structure", m_structure),
    ("set_junk", m_set_junk), ("set_random", m_set_random), ("cli_junk", m_cli_junk),
    ("scene_path", m_scene_path),
]


# ----------------------------------------------------------------------------
# Running


class Case:
    pass


def make_case(i, seed, keys, seeds, work):
    rng = random.Random("%s:%d" % (seed, i))
    kind, mutate = MUTATIONS[i % len(MUTATIONS)]
    # Mostly the valid scenes: a mutation of a bad one is an error anyway.
    bad = [s for s in seeds if s[0].startswith("tests/bad/")]
    good = [s for s in seeds if s not in bad]
    seed_rel, text = rng.choice(bad if bad and rng.random() < 0.2 else good)
    ctx = Ctx(rng, keys, seed_rel, text)
    content, args, must_fail, note = mutate(ctx)
    case = Case()
    case.i, case.kind, case.seed_rel, case.note, case.must_fail = i, kind, seed_rel, note, must_fail
    folder = os.path.join(work, os.path.dirname(seed_rel))
    if content is None:  # the scene path itself is the mutation
        case.path, case.content = None, None
        case.argv = ["check"] + args
        case.names = [a if a else '""' for a in args]
    else:
        if isinstance(content, str):
            content = content.encode("utf-8", "surrogatepass")
        case.content = content
        case.path = os.path.join(folder, "fuzz_%04d.toml" % i)
        with open(case.path, "wb") as f:
            f.write(content)
        case.argv = ["check", case.path] + args
        case.names = [os.path.basename(case.path)] + [a for a in args if a]
    case.cwd = folder
    case.mpi_tmp = os.path.join(work, "mpi")
    return case


def judge(case, rc, out, err):
    """'' when the outcome is acceptable, else what is wrong."""
    text = out + err
    for t in CRASH_TEXTS:
        if t in text:
            return "output holds %r" % t
    if rc == 0:
        if case.must_fail:
            return "accepted (exit 0) though the mutation cannot be valid"
        if ": ok" not in out:
            return "exit 0 without ': ok'"
        return ""
    if rc != 2:
        return "exit code %d (expected 0 or 2)" % rc if rc >= 0 else "killed by signal %d" % -rc
    if not err.startswith("error: "):
        return "exit 2 but stderr does not start with 'error: '"
    message = err[len("error: "):].strip()
    if len(message) < 10:
        return "exit 2 with an empty or too short message"
    if not any(n[:200] in err for n in case.names):
        return "the message names neither the scene file nor the argument"
    return ""


def run_case(nct, case, timeout, env):
    # Singletons without a daemon share Open MPI's session folder (jf.0):
    # one each, or parallel runs remove it under each other.
    env = dict(env, OMPI_MCA_orte_tmpdir_base=os.path.join(case.mpi_tmp, str(case.i)))
    os.makedirs(env["OMPI_MCA_orte_tmpdir_base"], exist_ok=True)
    t = time.time()
    try:
        p = subprocess.run([nct] + case.argv, cwd=case.cwd, capture_output=True, timeout=timeout,
                           env=env, stdin=subprocess.DEVNULL)
        rc, out, err = p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired as e:
        rc, out, err = None, e.stdout or b"", e.stderr or b""
    case.seconds = time.time() - t
    case.out = out.decode("utf-8", "replace")
    case.err = err.decode("utf-8", "replace")
    case.rc = rc
    if rc is None:
        case.problem = "timeout after %g s" % timeout
    else:
        case.problem = judge(case, rc, case.out, case.err)
    case.outcome = "FAIL" if case.problem else ("ok" if rc == 0 else "error")
    return case


def show(data, limit=1500):
    if data is None:
        return "(no file)"
    try:
        s = data.decode("utf-8")
    except UnicodeDecodeError:
        s = repr(data)
    return s if len(s) <= limit else s[:limit] + "\n... (%d bytes in all)" % len(data)


def report_failure(case, nct, keep, seed):
    print("\n=== FAIL case %d (%s) from %s: %s" % (case.i, case.kind, case.seed_rel, case.note))
    print("problem: %s" % case.problem)
    print("command: %s %s" % (nct, " ".join(repr(a) if (" " in a or not a or "\n" in a) else a
                                           for a in case.argv)))
    print("rerun:   %s %s --seed %s --case %d" % (sys.argv[0], nct, seed, case.i))
    print("--- scene file:\n%s" % show(case.content))
    print("--- exit code %s; stdout:\n%s\n--- stderr:\n%s" % (case.rc, case.out[:2000], case.err[:2000]))
    os.makedirs(keep, exist_ok=True)
    base = os.path.join(keep, "case_%04d" % case.i)
    if case.content is not None:
        with open(base + ".toml", "wb") as f:
            f.write(case.content)
    with open(base + ".txt", "w") as f:
        f.write("kind: %s\nseed file: %s (relative paths resolve from its folder)\nmutation: %s\n"
                "problem: %s\nargs: %r\nexit code: %s\n--- stdout\n%s\n--- stderr\n%s\n"
                % (case.kind, case.seed_rel, case.note, case.problem, case.argv[2:] if case.path
                   else case.argv[1:], case.rc, case.out, case.err))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("nct", help="the nct binary")
    ap.add_argument("--seed", default="1", help="random seed (default 1)")
    ap.add_argument("--count", type=int, default=300, help="mutations (default 300)")
    ap.add_argument("--case", type=int, action="append", help="run only this case (repeatable)")
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds per `nct check` (default 20)")
    ap.add_argument("--jobs", type=int, default=1, help="parallel runs (default 1)")
    ap.add_argument("--keep", default="fuzz_scenes_failures", help="folder for failing cases")
    ap.add_argument("--verbose", action="store_true", help="print every case")
    a = ap.parse_args()
    nct = os.path.abspath(a.nct)
    if not os.access(nct, os.X_OK):
        raise SystemExit("fuzz_scenes: %s is not an executable" % nct)

    # A singleton MPI process without its daemon and UCX probing: `nct
    # check` starts in 0.2 s instead of 0.5 s. Nothing it checks uses MPI.
    env = dict(os.environ)
    env.setdefault("OMPI_MCA_ess_singleton_isolated", "1")
    env.setdefault("OMPI_MCA_pml", "ob1")
    env.setdefault("OPENBLAS_NUM_THREADS", "1")
    if os.geteuid() == 0:
        env.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
        env.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")

    keys = read_keys(nct)
    work = tempfile.mkdtemp(prefix="nct-fuzz-")
    t0 = time.time()
    try:
        # The seeds and the files they name, in the same layout.
        seeds = []
        for d in SEED_DIRS:
            os.makedirs(os.path.join(work, d), exist_ok=True)
            for name in sorted(os.listdir(os.path.join(REPO, d))):
                if name.endswith(".toml"):
                    with open(os.path.join(REPO, d, name), encoding="utf-8") as f:
                        seeds.append((os.path.join(d, name), f.read()))
        for d in DATA_DIRS:
            shutil.copytree(os.path.join(REPO, d), os.path.join(work, d), dirs_exist_ok=True)
        for f in DATA_FILES:
            shutil.copy(os.path.join(REPO, f), os.path.join(work, f))

        indices = a.case if a.case else range(a.count)
        cases = [make_case(i, a.seed, keys, seeds, work) for i in indices]
        with ThreadPoolExecutor(max(1, a.jobs)) as pool:
            done = list(pool.map(lambda c: run_case(nct, c, a.timeout, env), cases))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    elapsed = time.time() - t0

    # Summary: outcomes per mutation kind.
    kinds = [k for k, _ in MUTATIONS if any(c.kind == k for c in done)]
    print("fuzz_scenes: %d mutations of %d seed scenes, seed %s, %d keys (nct describe)"
          % (len(done), len(seeds), a.seed, len(keys)))
    print("%-16s %5s %5s %5s %5s" % ("mutation", "cases", "ok", "error", "FAIL"))
    for k in kinds:
        cs = [c for c in done if c.kind == k]
        print("%-16s %5d %5d %5d %5d" % (k, len(cs), sum(c.outcome == "ok" for c in cs),
                                         sum(c.outcome == "error" for c in cs),
                                         sum(c.outcome == "FAIL" for c in cs)))
    slowest = max(done, key=lambda c: c.seconds)
    print("%-16s %5d %5d %5d %5d" % ("total", len(done), sum(c.outcome == "ok" for c in done),
                                     sum(c.outcome == "error" for c in done),
                                     sum(c.outcome == "FAIL" for c in done)))
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    print("%.1f s in all (nct: %.1f s of CPU); slowest case %d (%s) %.2f s"
          % (elapsed, ru.ru_utime + ru.ru_stime, slowest.i, slowest.kind, slowest.seconds))
    if a.verbose:
        for c in done:
            print("case %4d %-16s %-6s rc=%s %.2fs %s | %s" % (c.i, c.kind, c.outcome, c.rc, c.seconds,
                                                              c.note[:60], (c.err or c.out).strip()[:150]))

    failed = [c for c in done if c.problem]
    for c in failed:
        report_failure(c, nct, os.path.abspath(a.keep), a.seed)
    if failed:
        print("\nfuzz_scenes: %d of %d cases FAILED (saved in %s)"
              % (len(failed), len(done), os.path.abspath(a.keep)))
        return 1
    print("fuzz_scenes: all %d cases gave ok or a clear error" % len(done))
    return 0


if __name__ == "__main__":
    sys.exit(main())
