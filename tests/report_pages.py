"""The four kinds of report pages in a real browser (headless Chromium).

report_pages.py NCT SCENE OUT STUDY ABLATION FIT COHORT [RUN]

Runs SCENE's axisymmetric section on 2 ranks into OUT/run (its page
written at the end by default; again with --no-report, none; with RUN,
an existing run folder, its page instead), takes the
pages the study, ablation, fit and cohort fixtures' drivers wrote at their
ends, and opens each in Chromium (Debian's, through chromedriver): no
console error, no resource loaded from anywhere (the page is one file),
every expected section and figure rendered with a size; on the run's
page, the slider and the A1 / HC buttons move the corneal profile and the
cursor; a full-page screenshot per page (OUT/<kind>.png) that is not
blank. Exits 77 (skipped) with the reason when Chromium, chromedriver or
Selenium is missing.
"""
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

nct, scene, out = sys.argv[1], sys.argv[2], pathlib.Path(sys.argv[3])
folders = dict(zip(("study", "ablation", "fit", "cohort"), map(pathlib.Path, sys.argv[4:8])))
given_run = pathlib.Path(sys.argv[8]) if len(sys.argv) > 8 else None

missing = [p for p in ("/usr/bin/chromium", "/usr/bin/chromedriver") if not os.path.exists(p)]
try:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
except ImportError:
    missing.append("python3-selenium")
if missing:
    print(f"SKIPPED: {', '.join(missing)} not installed (scripts/install-deps.sh installs "
          "chromium, chromium-driver and python3-selenium)")
    sys.exit(77)

from PIL import Image  # noqa: E402 (matplotlib's dependency)

shutil.rmtree(out, ignore_errors=True)
out.mkdir(parents=True)
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
run = ["mpirun", "-n", "2", "--oversubscribe", nct, "run", scene, "--set",
       'mesh.dimension="axisymmetric"']
if given_run:
    folders["run"] = given_run
else:
    p = subprocess.run(run + ["--out", str(out / "run")], env=env, capture_output=True, text=True)
    print(p.stdout[-2000:], p.stderr[-2000:])
    assert p.returncode == 0, p.returncode
    assert f"report: {out / 'run' / 'report.html'} (run)" in p.stdout
    p = subprocess.run(run + ["--out", str(out / "quiet"), "--no-report"], env=env,
                       capture_output=True, text=True)
    assert p.returncode == 0 and (out / "quiet" / "summary.json").exists(), p.stderr
    assert not (out / "quiet" / "report.html").exists() and "report:" not in p.stdout
    folders["run"] = out / "run"

SECTIONS = {
    "run": ["model", "cost", "profile", "curves", "pressures", "dcr", "cbi", "solver", "files"],
    "study": ["design", "cases", "effects", "anova", "correlation", "files"],
    "ablation": ["design", "cases", "ablation", "files"],
    "fit": ["parameters", "correlations", "readings", "iterations", "files"],
    "cohort": ["patients", "stiffness", "recovery", "files"]}
FIGURES = {
    "run": ["profiles", "deformation", "pressures", "solver"],
    "study": ["main_effects", "pareto", "correlation"],
    "ablation": ["variants"],
    "fit": ["fit-curves", "fit-profiles", "fit-residuals", "fit-convergence", "fit-correlation"],
    "cohort": ["cohort-iop", "cohort-age", "cohort-recovery"]}

options = webdriver.ChromeOptions()
options.binary_location = "/usr/bin/chromium"
for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
             "--disable-background-networking", "--disable-component-update", "--disable-sync",
             "--disable-dev-shm-usage", "--window-size=1400,1000"):
    options.add_argument(flag)
profile = tempfile.mkdtemp(prefix="nct-chromium-")
options.add_argument("--user-data-dir=" + profile)
options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
browser = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)


def js(code, *args):
    return browser.execute_script(code, *args)


def check_player():
    """The slider and the event buttons move the profile and the cursor."""
    shape = lambda: js("return document.getElementById('profile-anterior').getAttribute('d')")  # noqa
    cursor = lambda: js("return document.getElementById('cursor').getAttribute('x1')")  # noqa
    events = js("return JSON.parse(document.getElementById('report-data').textContent)"
                ".player.events")
    assert set(events) == {"A1", "HC", "A2"}, events
    at_hc = shape()  # the page opens at HC
    js("const s = document.getElementById('frame'); s.value = arguments[0];"
       "s.dispatchEvent(new Event('input'));", 0)
    at_start = shape()
    assert at_start != at_hc and len(at_start) > 100, "the slider did not move the profile"
    assert "frame 1 of" in js("return document.getElementById('readout').textContent")
    browser.find_element("css selector", f"button[data-frame='{events['A1']}']").click()
    assert shape() not in (at_start, at_hc) and "(A1)" in js(
        "return document.getElementById('readout').textContent")
    x_a1 = cursor()
    browser.find_element("css selector", f"button[data-frame='{events['HC']}']").click()
    assert shape() == at_hc and cursor() != x_a1, "HC did not return to the HC frame"


def not_blank(png):
    """Many colours and a real spread of brightness: a rendered page."""
    image = Image.open(png).convert("RGB")
    small = image.resize((200, 200 * image.height // image.width))
    colours = len(set(small.getdata()))
    grey = small.convert("L")
    spread = max(grey.getdata()) - min(grey.getdata())
    assert image.height > 800 and colours > 50 and spread > 100, (png, colours, spread)


try:
    for kind, folder in folders.items():
        page = folder / "report.html"
        assert page.is_file(), f"{page}: the driver wrote no page at its end"
        browser.get(page.resolve().as_uri())
        errors = [e for e in browser.get_log("browser") if e["level"] == "SEVERE"]
        assert not errors, errors
        loaded = js("return performance.getEntriesByType('resource').map(e => e.name)")
        assert not loaded, f"{kind}: the page loaded {loaded}"
        text = page.read_text()
        outside = re.findall(r"""(?:src|href)\s*=\s*["']?(?:https?:|//)|url\(\s*["']?https?:"""
                             r"|@import|<link\b|<iframe\b", text)
        assert not outside, f"{kind}: the page refers outside itself: {outside}"
        ids = js("return [...document.querySelectorAll('main > section')].map(s => s.id)")
        for section in SECTIONS[kind]:
            assert section in ids, f"{kind}: no section '{section}' among {ids}"
        sizes = js("return Object.fromEntries([...document.querySelectorAll('figure.plot')]"
                   ".map(f => [f.dataset.name, f.querySelector('svg').getBoundingClientRect()"
                   ".width]))")
        for name in FIGURES[kind]:
            assert sizes.get(name, 0) > 100, f"{kind}: figure {name}: {sizes}"
        if kind == "run":
            check_player()
            assert "displacement.xdmf" in js("return document.getElementById('files').innerText")
            assert js("return document.querySelectorAll('#dcr tbody tr').length") >= 10
        height = js("return document.documentElement.scrollHeight")
        browser.set_window_size(1400, min(height + 40, 12000))
        png = out / f"{kind}.png"
        browser.save_screenshot(str(png))
        browser.set_window_size(1400, 1000)
        not_blank(png)
        print(f"{kind}: {page}: sections {ids}, {len(sizes)} figures, no console error; {png}")
finally:
    browser.quit()
    shutil.rmtree(profile, ignore_errors=True)
print("report pages: OK")
