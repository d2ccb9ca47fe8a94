"""The demo run's report opened in a real headless browser (Debian's chromium): it loads without a
console message, its scene and timeline pictures are laid out at a real size, and a screenshot is
kept as an artifact ($GAPS_ARTIFACTS, else tests/artifacts/; the path is printed).

`make test` installs chromium first (scripts/ensure-chromium.sh); where it cannot be installed the
test is skipped and says why. The control test proves the console check sees an error when there
is one, so a silent browser cannot pass for a clean page.
"""
from __future__ import annotations

import itertools
import json
import os
import re
import shutil
import subprocess
from datetime import datetime, timezone
from html import unescape
from importlib.metadata import version
from pathlib import Path

import pytest

from explain.labels import Box
from explain.pdf import find_chromium, headless_args, print_pdf
from reasoner import Case
from explain.report import build_report, render_report
from explain.svg_scene import scene_svg
from explain.svg_timeline import timeline_svg
from tests.helpers.scene_pictures import FIRE_ENGINE, QUICK, STOP_AND_GO, a_timeline, crowded_picture
from sim_replay.paper import RUN, paper_run
from store import Store

CHROMIUM = find_chromium()
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="no headless Chromium (on Debian: apt-get install "
                                                          "chromium; `make test` runs scripts/ensure-chromium.sh)")
ARTIFACTS = Path(os.environ.get("GAPS_ARTIFACTS") or Path(__file__).parents[1] / "artifacts")
CONSOLE = re.compile(r":CONSOLE[:(]")

# Loads the report in a frame and writes the laid-out size of each picture into the page, for
# --dump-dom to read (the report itself has no script; this harness is test-only).
HARNESS = """<!DOCTYPE html><html><body><pre id="result">not loaded</pre>
<iframe id="report" src="report.html" style="width:1280px;height:2000px"></iframe>
<script>
document.getElementById("report").addEventListener("load", function () {
  var doc = this.contentDocument, out = {};
  ["svg.gaps-scene", "svg.gaps-timeline", "table.summary", "section.gaps-explanation"].forEach(function (sel) {
    out[sel] = Array.prototype.map.call(doc.querySelectorAll(sel), function (el) {
      var r = el.getBoundingClientRect(); return [Math.round(r.width), Math.round(r.height)]; });
  });
  document.getElementById("result").textContent = JSON.stringify(out);
});
</script></body></html>
"""


def chromium(tmp: Path, *args: str, timeout: float = 120) -> subprocess.CompletedProcess:
    profile = tmp / f"profile-{len(list(tmp.glob('profile-*')))}"
    return subprocess.run(headless_args(CHROMIUM, str(profile)) + ["--enable-logging=stderr", "--v=0", *args],
                          capture_output=True, text=True, timeout=timeout)


def console_messages(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if CONSOLE.search(line)]


@pytest.fixture(scope="module")
def report_page(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("browser")
    with Store(folder / "demo.db") as store:
        store.append(paper_run())
        report = build_report(Case(store), RUN, now=datetime(2026, 1, 2, tzinfo=timezone.utc))
    page = folder / "report.html"
    page.write_text(render_report(report, "html"), encoding="utf-8")
    (folder / "harness.html").write_text(HARNESS, encoding="utf-8")
    return page


def test_the_console_check_sees_an_error(tmp_path):
    page = tmp_path / "broken.html"
    page.write_text("<!DOCTYPE html><p>x</p><script>console.error('broken'); missingFunction();</script>")
    done = chromium(tmp_path, "--dump-dom", page.as_uri())
    found = console_messages(done.stderr)
    assert any("broken" in m for m in found) and any("missingFunction" in m for m in found), done.stderr[-2000:]


def test_report_renders_without_console_messages(report_page, tmp_path):
    done = chromium(tmp_path, "--dump-dom", report_page.as_uri())
    assert done.returncode == 0, done.stderr[-2000:]
    assert console_messages(done.stderr) == []
    dom = done.stdout
    assert dom.count('class="gaps-scene"') == 2 and dom.count('class="gaps-timeline"') == 2
    assert "Incident report: run paper-junctions" in dom


def test_pictures_are_laid_out_at_a_real_size(report_page, tmp_path):
    harness = report_page.with_name("harness.html")
    done = chromium(tmp_path, "--allow-file-access-from-files", "--dump-dom", harness.as_uri())
    result = re.search(r'<pre id="result">(.*?)</pre>', done.stdout, re.S)
    assert result and result.group(1) != "not loaded", done.stdout[:2000] + done.stderr[-2000:]
    sizes = json.loads(result.group(1))
    assert len(sizes["svg.gaps-scene"]) == 2 and len(sizes["svg.gaps-timeline"]) == 2
    for width, height in sizes["svg.gaps-scene"]:
        assert width >= 600 and height >= 400
    for width, height in sizes["svg.gaps-timeline"]:
        assert width >= 600 and height >= 180
    assert sizes["table.summary"][0][1] > 40 and len(sizes["section.gaps-explanation"]) == 2


def test_screenshot_is_kept_as_an_artifact(report_page, tmp_path, capsys):
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    shot = ARTIFACTS / "report-demo.png"
    shot.unlink(missing_ok=True)
    done = chromium(tmp_path, f"--screenshot={shot}", "--window-size=1280,2000", "--hide-scrollbars",
                    report_page.as_uri())
    assert done.returncode == 0 and shot.is_file(), done.stderr[-2000:]
    data = shot.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert int.from_bytes(data[16:20], "big") == 1280 and int.from_bytes(data[20:24], "big") == 2000
    assert len(data) > 50_000          # a blank page of this size compresses to a few kB
    (ARTIFACTS / "report-demo.html").write_text(report_page.read_text(encoding="utf-8"), encoding="utf-8")
    with capsys.disabled():
        print(f"\nreport screenshot: {shot}")


def test_pdf_is_printed(report_page, tmp_path):
    pdf = print_pdf(report_page, tmp_path / "report.pdf")
    data = pdf.read_bytes()
    assert data.startswith(b"%PDF-") and len(data) > 10_000
    assert len(re.findall(rb"/Type\s*/Page[^s]", data)) >= 3      # the summary, then a page per incident


# --- the printed form and the labels as the browser lays them out ---------------------------------

PDFTOTEXT = shutil.which("pdftotext")
A4_PT = (595.28, 841.89)      # 210 x 297 mm


def pdf_pages(pdf: Path) -> list[str]:
    """The text of each page of the PDF (pdftotext, poppler-utils)."""
    text = subprocess.run([PDFTOTEXT, "-layout", str(pdf), "-"], capture_output=True, text=True,
                          timeout=60, check=True).stdout
    return text.split("\f")[:-1] if text.endswith("\f") else text.split("\f")


@pytest.fixture(scope="module")
def printed(report_page, tmp_path_factory) -> Path:
    return print_pdf(report_page, tmp_path_factory.mktemp("pdf") / "report.pdf")


def test_pdf_pages_are_a4(printed):
    boxes = re.findall(rb"/MediaBox\s*\[\s*0\s+0\s+([0-9.]+)\s+([0-9.]+)\s*\]", printed.read_bytes())
    assert boxes, "no page size in the PDF"
    for w, h in boxes:
        assert (float(w), float(h)) == pytest.approx(A4_PT, abs=1.0)      # not US letter (612 x 792)


@pytest.mark.skipif(PDFTOTEXT is None, reason="pdftotext not installed (apt-get install poppler-utils)")
def test_every_pdf_page_says_page_n_of_m_the_version_and_the_store_sha256(printed, report_page):
    pages = pdf_pages(printed)
    total = len(pages)
    assert total >= 3
    sha = re.search(r'<th>store sha256</th><td class="sha">([0-9a-f]{64})</td>', report_page.read_text())
    assert sha, "no store sha256 in the page"
    for n, text in enumerate(pages, 1):
        assert f"page {n} of {total}" in text, (n, text[-400:])
        assert f"mind-the-gaps {version('mind-the-gaps')}" in text and sha.group(1) in text
        assert "Incident report: run paper-junctions" in text


@pytest.mark.skipif(PDFTOTEXT is None, reason="pdftotext not installed (apt-get install poppler-utils)")
def test_each_incident_starts_a_pdf_page(printed):
    starts = {}
    for n, text in enumerate(pdf_pages(printed), 1):
        body = [line.strip() for line in text.splitlines() if line.strip()]
        body = [line for line in body if not line.startswith(("Incident report: run", "store demo.db sha256"))]
        for line in body:
            if line.startswith("Incident ") and ": vehicle" in line:
                starts[line.split(":")[0]] = (n, body.index(line))
    assert set(starts) == {"Incident 1", "Incident 2"}
    assert all(position == 0 for _, position in starts.values()), starts   # the first thing on its page
    assert starts["Incident 1"][0] > 1 and starts["Incident 2"][0] > starts["Incident 1"][0]


LABELS_HARNESS = """<!DOCTYPE html><html><body>{svgs}<pre id="result">not run</pre><script>
function box(el) {{ var b = el.getBBox(); return [b.x, b.y, b.width, b.height]; }}
function boxes(svg, sel) {{
  return Array.prototype.map.call(svg.querySelectorAll(sel), function (t) {{
    var est = t.getAttribute("data-box");
    return [t.textContent, box(t), est && est.split(" ").map(Number)]; }});
}}
var out = {{scenes: [], timelines: []}};
document.querySelectorAll("svg.gaps-scene").forEach(function (svg) {{
  out.scenes.push(boxes(svg, "text.label"));
}});
document.querySelectorAll("svg.gaps-timeline").forEach(function (svg) {{
  out.timelines.push({{view: svg.getAttribute("viewBox").split(" ").map(Number),
    labels: boxes(svg, "text.moment-label, text.incident-label, text.speed-value"),
    lines: Array.prototype.map.call(svg.querySelectorAll("line.moment, line.incident-time"), box)}});
}});
document.getElementById("result").textContent = JSON.stringify(out);
</script></body></html>
"""
@pytest.fixture(scope="module")
def pictures_page(tmp_path_factory) -> Path:
    """The crowded scene and timelines of demo-like moments, each an SVG as the report draws it."""
    timelines = [timeline_svg(a_timeline(moments), 90.0) for moments in (FIRE_ENGINE, STOP_AND_GO, QUICK)]
    page = tmp_path_factory.mktemp("pictures") / "labels.html"
    page.write_text(LABELS_HARNESS.format(svgs=scene_svg(crowded_picture(), 1) + "".join(timelines)),
                    encoding="utf-8")
    return page


def test_labels_as_drawn_do_not_overlap_and_fit_their_boxes(pictures_page, tmp_path):
    done = chromium(tmp_path, "--dump-dom", pictures_page.as_uri())
    result = re.search(r'<pre id="result">(.*?)</pre>', done.stdout, re.S)
    assert result and result.group(1) != "not run", done.stderr[-2000:]
    found = json.loads(result.group(1))
    (scene,) = found["scenes"]
    assert len(scene) == 10
    _assert_apart_and_boxed(scene)
    assert len(found["timelines"]) == 3
    for timeline, moments in zip(found["timelines"], (FIRE_ENGINE, STOP_AND_GO, QUICK)):
        labels = timeline["labels"]
        frame = Box(*timeline["view"])
        for text, real, _ in labels:                # as drawn: inside the picture, no line through it
            r = Box(*real)
            assert r.within(frame), (text, r, frame)
            for x, top, _, height in timeline["lines"]:
                assert not (r.x < x < r.x + r.w and top < r.y + r.h and r.y < top + height), (text, r, x)
        _assert_apart_and_boxed(labels)
        assert len(labels) == len(moments) + 2 and len(timeline["lines"]) == len(moments) + 1


def _assert_apart_and_boxed(found: list) -> None:
    """No two labels the browser drew meet, and each box the layout estimated holds its text."""
    drawn = [(text, Box(*real)) for text, real, _ in found]
    for (a, box_a), (b, box_b) in itertools.combinations(drawn, 2):
        assert not box_a.intersects(box_b), (a, box_a, b, box_b)
    for text, real, estimated in found:
        assert estimated, f"{text!r} has no box of the layout's (data-box)"
        r, e = Box(*real), Box(*estimated)
        assert r.x >= e.x - 1.5 and r.x + r.w <= e.x + e.w + 1.5, (text, r, e)     # a j's hook: 1 px
        assert r.y >= e.y - 2 and r.y + r.h <= e.y + e.h + 2, (text, r, e)


PDFTOPPM = shutil.which("pdftoppm")


@pytest.mark.skipif(PDFTOTEXT is None or PDFTOPPM is None, reason="poppler-utils not installed")
def test_the_printed_pictures_read_as_pages(pictures_page, tmp_path, capsys):
    """The same pictures printed to PDF, as a court's bundle holds them: on the pages no word
    of one label runs into another's, and each page is kept as an image for a person to look at
    ($GAPS_ARTIFACTS/pictures-page-N.png)."""
    pdf = print_pdf(pictures_page, tmp_path / "pictures.pdf")
    html = subprocess.run([PDFTOTEXT, "-bbox", str(pdf), "-"], capture_output=True, text=True, timeout=60,
                          check=True).stdout
    pages = re.findall(r"<page [^>]*>(.*?)</page>", html, re.S)
    assert pages
    for number, page in enumerate(pages, 1):
        words = [(unescape(text), Box(float(x0), float(y0), float(x1) - float(x0), float(y1) - float(y0)))
                 for x0, y0, x1, y1, text in re.findall(r'<word xMin="([0-9.]+)" yMin="([0-9.]+)" xMax="([0-9.]+)" '
                                                         r'yMax="([0-9.]+)">([^<]*)</word>', page)]
        for (a, box_a), (b, box_b) in itertools.combinations(words, 2):
            if a == b and abs(box_a.x - box_b.x) < 0.5 and abs(box_a.w - box_b.w) < 0.5:
                continue        # one label's halo (its stroke, paint-order) and its fill: one text
            shrunk_a = Box(box_a.x + 0.5, box_a.y + 1.5, box_a.w - 1, box_a.h - 3)   # poppler's boxes touch
            assert not shrunk_a.intersects(box_b), f"page {number}: {a!r} {box_a} runs into {b!r} {box_b}"
    text = "".join(pages)
    for what in ("stood still before the line", "left the junction"):
        assert all(word in text for word in what.split())
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    for old in ARTIFACTS.glob("pictures-page-*.png"):
        old.unlink()
    subprocess.run([PDFTOPPM, "-r", "80", "-png", str(pdf), str(ARTIFACTS / "pictures-page")], check=True, timeout=60)
    shots = sorted(ARTIFACTS.glob("pictures-page-*.png"))
    assert shots and all(shot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for shot in shots)
    with capsys.disabled():
        print(f"\nprinted pictures: {', '.join(map(str, shots))}")
