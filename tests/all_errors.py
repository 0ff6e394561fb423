"""Every problem of an input file at once: `nct VERB FILE` (check, or study
and fit with --dry-run) must exit 2 and name each expected problem, with
its line, in the order of the lines.

usage: all_errors.py NCT VERB FILE LINE:PATTERN... [-- EXTRA ARGS]"""
import re
import subprocess
import sys

nct, verb, path = sys.argv[1:4]
rest = sys.argv[4:]
extra = rest[rest.index("--") + 1:] if "--" in rest else []
expected = rest[:rest.index("--")] if "--" in rest else rest
p = subprocess.run([nct, verb, path, *extra], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                   text=True)
print(p.stdout)
assert p.returncode == 2, f"exit code {p.returncode}, expected 2"
lines = p.stdout.splitlines()
found = []
for item in expected:
    line, pattern = item.split(":", 1)
    where = [i for i, text in enumerate(lines)
             if re.search(rf"{re.escape(path)}:{line}: .*{pattern}", text)]
    assert where, f"no problem at line {line} matching {pattern!r}"
    found.append(where[0])
assert found == sorted(found), f"the problems are not in the order of their lines: {found}"
assert re.search(rf"{len(expected)} problems in", p.stdout), f"not {len(expected)} problems"
print(f"ok: {len(expected)} problems, each with its line, in order")
