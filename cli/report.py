"""`gaps report --run R [--incident I] -o FILE [--pdf]`: a run's incidents as one self-contained
report (HTML, Markdown or JSON, from the suffix of FILE or --format), and a PDF beside it with --pdf.

The report is `explain.build_report`'s, from the reasoner's `Case` (docs/api.md); its PDF is
`explain.print_report_pdf`'s. This module reads the options, shows progress on stderr and writes
the files (`-o -`: the report to standard output). Exit codes:
0 written; 2 for what names nothing (no store, run, incident or rulebook file, a suffix that is no
format, a folder that is not there); 3 for --pdf without a headless Chromium (a missing tool,
like a missing SWI-Prolog).
"""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from cli.app import check_files, db_path, fail, open_existing, writable_output
from cli.options import DbOption, RulesOption, RunRequired, is_stdio
from cli.progress import stderr_progress
from cli.safe_text import printable


def report(run: str = RunRequired,
           output: Path = typer.Option(..., "-o", "--output",
                                       help="Report file: .html (self-contained page), .md or .json; - for stdout."),
           fmt: Optional[str] = typer.Option(None, "--format",
                                             help="html, md or json (default: from the suffix; html for -)."),
           incident: Optional[str] = typer.Option(
               None, "--incident", help="Only this incident: its id (monitor/m1:3) or number (1, 2, ...)."),
           pdf: bool = typer.Option(False, "--pdf", help="Also print the report to FILE.pdf with a headless Chromium."),
           rules: Optional[list[Path]] = RulesOption,
           db: Optional[Path] = DbOption) -> None:
    """Write a report of a run's incidents for investigators, insurers and courts.

    The summary table, and per incident the explanation, the scene, a speed and signal timeline,
    the evidence, the rulebooks by sha256 and the hash chain verification.
    """
    from explain import (PdfError, ToolMissing, build_report, find_chromium, print_report_pdf, render_report,
                         report_format)
    from reasoner import Case
    to_stdout = is_stdio(output)
    fmt = report_format(fmt, None if to_stdout else output)
    if to_stdout and pdf:
        fail("--pdf writes FILE.pdf beside the report: give -o FILE rather than -")
    if not to_stdout and not output.parent.is_dir():
        fail(f"no such folder for the report: {output.parent}")
    if not to_stdout:
        writable_output(output, db)
        writable_output(output.with_suffix(".pdf") if pdf else None, db)
    files = check_files(rules)
    chromium = find_chromium() if pdf else None
    if pdf and chromium is None:
        fail("--pdf needs a headless Chromium and none was found (on Debian: apt-get install chromium; "
             "or set GAPS_CHROMIUM)", code=3)
    with open_existing(db) as store, stderr_progress("explaining incidents") as progress:
        built = build_report(Case(store, files), run, incident=incident, progress=progress)
    text = render_report(built, fmt)
    if to_stdout:
        typer.echo(text, nl=False)
        return
    from store import write_text
    try:
        write_text(output, text, [db_path(db)])
    except OSError as exc:
        fail(f"cannot write {output}: {exc.strerror or exc}")
    n = len(built.incidents)
    typer.echo(f"Wrote the report of run {printable(run)} ({n} incident{'s' if n != 1 else ''}, "
               f"{len(text.encode()):,} bytes) to {output}")
    if chromium is not None:                # --pdf, and a Chromium to print it
        target = output.with_suffix(".pdf")
        try:
            print_report_pdf(built, target, chromium, page=output if fmt == "html" else None, stores=[db_path(db)])
        except (ToolMissing, PdfError) as exc:
            fail(str(exc), code=3)
        typer.echo(f"Printed it to {target} ({target.stat().st_size:,} bytes)")

