"""A report page printed to PDF by a headless Chromium, when one is installed.

A PDF is what goes into a court bundle or an insurer's claim file; the browser that shows the
HTML report prints it, so the PDF and the page cannot drift apart. Chromium is optional: nothing
else in the project needs it, so its absence is reported as a missing tool, not an error of the
report. Each print gets its own throw-away profile, so two prints at once (or a print beside a
running browser) never fight over one profile lock.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
from pathlib import Path
from typing import Iterable

from store import GapsError, check_output, write_bytes

CANDIDATES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
DEBIAN_PATH = "/usr/bin/chromium"


class ToolMissing(GapsError, RuntimeError):
    """No headless Chromium on this machine."""

    exit_code = 3


class PdfError(GapsError, RuntimeError):
    """Chromium ran but did not print the page."""


def find_chromium() -> str | None:
    """A Chromium to run headless: $GAPS_CHROMIUM, one on PATH, else Debian's /usr/bin/chromium."""
    wanted = os.environ.get("GAPS_CHROMIUM")
    if wanted:
        return wanted if shutil.which(wanted) else None
    for name in CANDIDATES:
        found = shutil.which(name)
        if found:
            return found
    return DEBIAN_PATH if os.access(DEBIAN_PATH, os.X_OK) else None


def headless_args(chromium: str, profile: str) -> list[str]:
    """The command line every headless run of the report starts with (also the browser test's)."""
    return [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
            "--disable-extensions", f"--user-data-dir={profile}"]


def print_pdf(html: Path, pdf: Path, chromium: str | None = None, timeout_s: float = 120.0,
              stores: Iterable[str | os.PathLike] = ()) -> Path:
    """Print the HTML file to `pdf`; ToolMissing without Chromium, PdfError if it fails. Chromium
    prints into a folder of its own; the PDF then replaces `pdf` only through store.write_bytes,
    which never writes over a store (`stores`, or any this process opened) or a non-regular file."""
    chromium = chromium or find_chromium()
    if chromium is None:
        raise ToolMissing("--pdf needs a headless Chromium and none was found (on Debian: apt-get install "
                          "chromium; or set GAPS_CHROMIUM)")
    check_output(pdf, stores)
    with tempfile.TemporaryDirectory(prefix="gaps-chromium-") as profile:
        printed = Path(profile) / "printed.pdf"
        try:
            done = subprocess.run(headless_args(chromium, profile) + [
                "--no-pdf-header-footer", "--print-to-pdf-no-header", f"--print-to-pdf={printed}",
                Path(html).resolve().as_uri()], capture_output=True, text=True, timeout=timeout_s)
        except subprocess.TimeoutExpired:
            raise PdfError(f"Chromium did not print the report within {timeout_s:g} s") from None
        except OSError as exc:
            raise PdfError(f"cannot run {chromium}: {exc}") from None
        if not printed.is_file() or printed.read_bytes()[:5] != b"%PDF-":
            last = (done.stderr.strip().splitlines() or ["no message"])[-1]
            raise PdfError(f"Chromium (exit {done.returncode}) wrote no PDF: {last}")
        return write_bytes(pdf, printed.read_bytes(), stores)
