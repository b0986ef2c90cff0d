"""The report and a ``diagnose --html`` page in a real headless Chromium (Debian's chromium and chromium-driver).

Skipped, with the reason, where no Chromium or ChromeDriver is installed
(``.ci/run`` installs them).  Selenium is pointed at the system driver, so no
browser or driver is ever downloaded.
"""

import json
import re
import shutil
import tempfile

import pytest

from thermolimb.cli.main import main
from thermolimb.data import WX200_BAG
from thermolimb.demo_registry import run_demo
from thermolimb.report import build_report

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")
MISSING = [name for name, found in (("chromium", CHROMIUM), ("chromium-driver (chromedriver)", CHROMEDRIVER))
           if not found]
pytestmark = pytest.mark.skipif(bool(MISSING), reason=f"{' and '.join(MISSING)} not installed here: apt install "
                                                      f"{' '.join(m.split()[0] for m in MISSING)} (as .ci/run does)")
FLAGS = ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync", "--disable-dev-shm-usage")

FIGURES = """return Array.from(document.querySelectorAll('.js-plotly-plot')).map(g => ({
    id: g.id, traces: g.data.length, points: (g.calcdata || []).reduce((n, c) => n + c.length, 0)}));"""
IMAGES = """return Array.from(document.images).map(i => ({src: i.getAttribute('src'), width: i.naturalWidth}));"""
AXES = r"""return Array.from(document.querySelectorAll('.js-plotly-plot')).map(g => Object.keys(g.layout)
    .filter(k => /^[xy]axis\d*$/.test(k)).map(k => (g.layout[k].title || {}).text || ''));"""
TRACES = "return Array.from(document.querySelectorAll('.js-plotly-plot')).map(g => g.data.map(t => t.name || ''));"
BARS = """return Array.from(document.querySelectorAll('.js-plotly-plot')).map(g => g.data
    .filter(t => t.type === 'bar').flatMap(t => [].concat(t.y || [], t.x || [], t.text || [], t.hovertext || [])));"""
RESOURCES = "return performance.getEntriesByType('resource').map(e => e.name);"


@pytest.fixture(scope="module")
def browser():
    webdriver = pytest.importorskip("selenium.webdriver")
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in FLAGS:
        options.add_argument(flag)
    profile = tempfile.mkdtemp(prefix="chromium-")
    options.add_argument(f"--user-data-dir={profile}")
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
    yield driver
    driver.quit()
    shutil.rmtree(profile, ignore_errors=True)


def _open(browser, path):
    browser.get(path.resolve().as_uri())
    browser.get_log("browser")  # nothing from earlier pages
    browser.refresh()
    severe = [e for e in browser.get_log("browser") if e["level"] == "SEVERE"]
    assert not severe, severe
    external = [r for r in browser.execute_script(RESOURCES) if not r.startswith(("file:", "data:", "blob:"))]
    assert not external, f"the page loads from the network: {external}"


def test_diagnose_html_page_has_its_figures_with_data(browser, tmp_path):
    page = tmp_path / "diagnose.html"
    assert main(["diagnose", str(WX200_BAG.paths[0]), "--actuator", "waist", "--auto", "--html", str(page),
                 "--effort-unit", "mA", "--quiet"]) == 0
    _open(browser, page)
    figures = browser.execute_script(FIGURES)
    assert [f["id"] for f in figures] == ["figure-0", "figure-1", "figure-2"]  # temperature, candidates, waterfall
    assert figures[0]["traces"] >= 4 and figures[0]["points"] >= 4 * 21  # 21 samples per trace
    assert all(f["points"] > 0 for f in figures)
    assert page.read_text().count("<script type=\"text/javascript\">/**") <= 1  # Plotly embedded once
    titles = [t for figure in browser.execute_script(AXES) for t in figure]
    assert titles and all(re.search(r"\(.+\)$", t) for t in titles if t), titles  # every drawn axis has its unit
    assert "effort (mA)" in titles and "temperature (°C)" in titles, titles  # the unit the user gave, not N m


def test_diagnose_html_page_draws_every_step_of_the_search(browser, tmp_path, capsys):
    """On a plant log whose search takes more than one step, the page draws each step's model over the data."""
    log, page = tmp_path / "plant.csv", tmp_path / "steps.html"
    assert main(["simulate", "--profile", "random", "--duration", "1800", "--dt", "1", "--network", "first_order",
                 "--actuators", "knee:X8-9", "--effects", "sensor_noise,speed_losses", "--out", str(log),
                 "--quiet"]) == 0
    capsys.readouterr()
    assert main(["diagnose", str(log), "--auto", "--html", str(page), "--json", "--quiet"]) == 0
    steps = json.loads(capsys.readouterr().out)["auto"]
    assert len(steps) > 1, steps
    _open(browser, page)
    names = {n for figure in browser.execute_script(TRACES) for n in figure}
    for step in steps:
        assert any(n.startswith(",".join(step["model"]) + " ") for n in names), (step["model"], names)
    titles = [t for figure in browser.execute_script(AXES) for t in figure]
    assert "effort (N m)" in titles, titles  # the plant's unit, from its log's header


def test_discovery_candidates_are_drawn_like_catalog_ones(browser, tmp_path, capsys):
    """A channel term found by --discover appears on the page as catalog candidates do: a bar of the candidates
    figure named after its channel, and its step's model over the measurement."""
    log, page = tmp_path / "brake.csv", tmp_path / "brake.html"
    assert main(["simulate", "--profile", "random", "--duration", "3600", "--dt", "1", "--network", "first_order",
                 "--effects", "sensor_noise,quantisation,holding_brake", "--out", str(log), "--quiet"]) == 0
    capsys.readouterr()
    assert main(["diagnose", str(log), "--actuator", "knee", "--auto", "--discover", "--html", str(page), "--json",
                 "--quiet"]) == 0
    record = json.loads(capsys.readouterr().out)
    channel = [c for c in record["candidates"] if c["kind"] == "channel"]
    assert channel, [c["label"] for c in record["candidates"]]
    _open(browser, page)
    shown = " ".join(str(v) for figure in browser.execute_script(BARS) for v in figure)
    assert any(c["label"].split(" (")[0] in shown for c in channel), shown[:500]
    names = {n for figure in browser.execute_script(TRACES) for n in figure}
    assert any("brake" in n for n in names), names


def test_report_opens_with_every_figure_drawn(browser, tmp_path):
    for name in ("thermal-fit", "diagnose"):
        run_demo(name, tmp_path, quick=True, quiet=True)
    index = build_report(tmp_path)
    _open(browser, index)
    images = browser.execute_script(IMAGES)
    assert len(images) >= 5 and all(i["width"] > 100 for i in images), images
    text = browser.find_element("tag name", "body").text
    assert "prediction RMSE, output error" in text and "recommended first" in text
    assert "catalog_only[0]" not in text and "channels.knee" not in text  # no flattened JSON keys
    _open(browser, tmp_path / "diagnose" / "interactive.html")
    assert all(f["points"] > 0 for f in browser.execute_script(FIGURES))
