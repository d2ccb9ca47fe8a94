"""`gaps report --run R [--incident I] -o FILE [--pdf]`: a run's incidents as one self-contained
report (HTML, Markdown or JSON, from the suffix of FILE), and a PDF beside it with --pdf.

The report is explain/report.py's; the PDF is explain/pdf.py's. This module reads the options,
shows progress on stderr and writes the files. Exit codes: 0 written; 2 for what names nothing
(no store, run, incident or rulebook file, a suffix that is no format, a folder that is not
there); 3 for --pdf without a headless Chromium (a missing tool, like a missing SWI-Prolog).
"""
from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Optional

import typer

from cli.app import DbOption, app, fail, open_existing
from cli.progress import stderr_progress
from cli.safe_text import printable


@app.command("report")
def report_command(run: str = typer.Option(..., "--run", help="Run id."),
                   output: Path = typer.Option(..., "-o", "--output",
                                               help="Report file: .html (self-contained page), .md or .json."),
                   incident: Optional[str] = typer.Option(
                       None, "--incident", help="Only this incident: its id (monitor/m1:3) or number (1, 2, ...)."),
                   pdf: bool = typer.Option(False, "--pdf", help="Also print the report to FILE.pdf with a "
                                                                 "headless Chromium."),
                   rules: Optional[list[Path]] = typer.Option(
                       None, "--rules", help="Judge with this LE rulebook first (repeatable), as `gaps incidents`."),
                   db: Optional[Path] = DbOption) -> None:
    """A report of a run's incidents for investigators, insurers and courts: the summary table, and
    per incident the explanation, the scene, a speed and signal timeline, the evidence, the
    rulebooks by sha256 and the hash chain verification."""
    from explain.pdf import PdfError, ToolMissing, find_chromium, print_pdf
    from explain.report import ReportError, build_report, format_for, render_report
    try:
        fmt = format_for(output)
    except ReportError as exc:
        fail(str(exc))
    if not output.parent.is_dir():
        fail(f"no such folder for the report: {output.parent}")
    for path in rules or []:
        if not path.is_file():
            fail(f"no such rulebook file: {path}")
    chromium = find_chromium() if pdf else None
    if pdf and chromium is None:
        fail("--pdf needs a headless Chromium and none was found (on Debian: apt-get install chromium; "
             "or set GAPS_CHROMIUM)", code=3)
    with open_existing(db) as store, stderr_progress("explaining incidents") as progress:
        try:
            report = build_report(store, run, incident=incident, rules=[str(p) for p in rules or []],
                                  progress=progress)
        except ReportError as exc:
            fail(str(exc))
    text = render_report(report, fmt)
    try:
        output.write_text(text, encoding="utf-8")
    except OSError as exc:
        fail(f"cannot write {output}: {exc.strerror or exc}")
    n = len(report["incidents"])
    typer.echo(f"Wrote the report of run {printable(run)} ({n} incident{'s' if n != 1 else ''}, "
               f"{len(text.encode()):,} bytes) to {output}")
    if pdf:
        target = output.with_suffix(".pdf")
        try:
            if fmt == "html":
                print_pdf(output, target, chromium)
            else:               # the PDF is always the HTML page printed
                with tempfile.TemporaryDirectory(prefix="gaps-report-") as tmp:
                    page = Path(tmp) / "report.html"
                    page.write_text(render_report(report, "html"), encoding="utf-8")
                    print_pdf(page, target, chromium)
        except ToolMissing as exc:
            fail(str(exc), code=3)
        except PdfError as exc:
            fail(str(exc), code=3)
        typer.echo(f"Printed it to {target} ({target.stat().st_size:,} bytes)")
