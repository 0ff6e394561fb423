"""The manual stands on its own: every relative link of README.md,
docs/*.md, the cases' pages (cases/README.md, cases/*/README.md),
scripts/README.md and python/README.md leads to a file of the repository
(and a #section to a heading there), every docs/<name>.md the sources
name exists, and no file of the repository cites one outside it. The
run folder's summary.json tables (docs/run-folder.md) hold every entry of the biomarker registry
(python/nct/biomarkers.json) with its unit.

usage: docs_check.py SOURCE_DIR"""
import json
import os
import re
import subprocess
import sys

root = sys.argv[1]
docs = (["README.md", "cases/README.md", "scripts/README.md", "python/README.md"]
        + sorted("docs/" + f for f in os.listdir(f"{root}/docs") if f.endswith(".md"))
        + sorted(f"cases/{c}/README.md" for c in os.listdir(f"{root}/cases")
                 if os.path.isfile(f"{root}/cases/{c}/README.md")))
problems = []


def slug(heading):
    """GitHub's anchor of a heading."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower().replace("`", ""))
    return text.replace(" ", "-")


def anchors(path):
    return {slug(m) for m in re.findall(r"^#+ (.*)$", open(path).read(), re.M)}


for doc in docs:
    text = open(f"{root}/{doc}").read()
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+://", target):
            continue
        file, _, anchor = target.partition("#")
        path = os.path.normpath(os.path.join(root, os.path.dirname(doc), file)) if file else \
            f"{root}/{doc}"
        if not os.path.exists(path):
            problems.append(f"{doc}: link to {target}: no such file")
        elif anchor and path.endswith(".md") and anchor not in anchors(path):
            problems.append(f"{doc}: link to {target}: no such section")

tracked = subprocess.run(["git", "-C", root, "ls-files"], capture_output=True, text=True,
                         check=True).stdout.split()
cited = set()
for f in tracked:
    if f.endswith((".csv", ".png", ".msh")) or not os.path.isfile(f"{root}/{f}"):
        continue
    text = open(f"{root}/{f}", errors="replace").read()
    cited.update(re.findall(r"\bdocs/[\w-]+\.md\b", text))
    for outside in ("design.md", "../shared", "/work/"):
        if outside in text and f != "tests/docs_check.py":
            problems.append(f"{f}: cites {outside}, outside the repository")
for name in sorted(cited):
    if not os.path.exists(f"{root}/{name}"):
        problems.append(f"{name} is cited but not in the repository")

run_folder = open(f"{root}/docs/run-folder.md").read()
rows = dict(re.findall(r"^\| `([^`]+)` \|([^|]*)\|", run_folder, re.M))
for entry in json.load(open(f"{root}/python/nct/biomarkers.json")):
    if entry["key"] not in rows:
        problems.append(f"docs/run-folder.md: no row for the registry's `{entry['key']}`")
    elif rows[entry["key"]].strip() != entry["unit"]:
        problems.append(f"docs/run-folder.md: `{entry['key']}` in {rows[entry['key']].strip()!r}, "
                        f"the registry's unit is {entry['unit']!r}")

for p in problems:
    print("FAIL", p)
print(f"{len(docs)} documents, {len(cited)} docs/ files cited: "
      f"{'ok' if not problems else str(len(problems)) + ' problems'}")
sys.exit(1 if problems else 0)
