"""What a script calls to put a case into words: an incident's explanation, a run's report.

    import explain, reasoner
    with reasoner.open("gaps.db") as case:
        inc = case.incident("paper-junctions", 1)
        print(explain.explanation(case, inc))
        explain.write_report(case, "paper-junctions", "report.html")

The reasoner answers (reasoner.Case); these functions only word and draw the answers, in the
formats `gaps explain` and `gaps report` print.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Iterable

from store import check_output, write_text

from .explanation_doc import document
from .explanation_formats import render
from .report import build_report, format_for, render_report

if TYPE_CHECKING:
    from reasoner import Case, Incident


def explanation(case: Case, incident: Incident, *, fmt: str = "text", level: str = "standard",
                why_not: Iterable[str] = ()) -> str:
    """The incident explained as `gaps explain` prints it: fmt text, md, html or json; level
    summary, standard or full; `why_not` sentences asked on the Validator Scenario."""
    found = case.explanation(incident, why_not=why_not)
    return render(document(incident, found, case.store), fmt, level)


def report_text(case: Case, run: str, *, fmt: str = "html", incident: str | int | None = None,
           progress: Callable[[int, int], None] | None = None) -> str:
    """The run's report (only `incident`, by id or number, if given) as html, md or json text."""
    case.require(run)
    chosen = None if incident is None else str(incident)
    built = build_report(case.store, run, incident=chosen, progress=progress, investigation=case.investigation)
    return render_report(built, fmt)


def write_report(case: Case, run: str, path: str | os.PathLike, *, incident: str | int | None = None,
                 progress: Callable[[int, int], None] | None = None) -> Path:
    """The run's report written to `path` in the format its suffix names (.html, .md, .json)."""
    target = Path(path)
    check_output(target, [case.store.path])     # before the work: evidence is never an output
    text = report_text(case, run, fmt=format_for(target), incident=incident, progress=progress)
    write_text(target, text, [case.store.path])
    return target
