"""The demo run's report opened in a real headless browser (Debian's chromium): it loads without a
console message, its scene and timeline pictures are laid out at a real size, and a screenshot is
kept as an artifact ($GAPS_ARTIFACTS, else tests/artifacts/; the path is printed).

`make test` installs chromium first (scripts/ensure-chromium.sh); where it cannot be installed the
test is skipped and says why. The control test proves the console check sees an error when there
is one, so a silent browser cannot pass for a clean page.
"""
from __future__ import annotations

import json
import os
import re
import subprocess
from datetime import datetime, timezone
from pathlib import Path

import pytest

from explain.pdf import find_chromium, headless_args, print_pdf
from explain.report import build_report, render_report
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
        report = build_report(store, RUN, now=datetime(2026, 1, 2, tzinfo=timezone.utc))
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
