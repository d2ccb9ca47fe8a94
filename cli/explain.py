"""`gaps explain --run R INCIDENT`: one incident's verdict explained, in text, Markdown, HTML or JSON.

The explanation is the reasoner's (Investigation.explanation), worded by explain/explanation_doc.py
and drawn by explain/explanation_formats.py; this module reads the options, finds the incident and prints. INCIDENT is the incident's id (`monitor/m1:3`) or its
number in `gaps incidents` order (1 is the first). Exit codes: 0 shown; 2 for what names nothing
(no store, no such run, no such incident, a rulebook file that is missing, an unknown format).
"""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from cli import completion
from cli.app import check_files, fail, open_existing, require_run
from cli.options import DbOption, IncidentHelp, JsonOption, RulesOption, RunRequired


def explain(incident: str = typer.Argument(..., help=IncidentHelp, autocompletion=completion.incidents),
            run: str = RunRequired,
            fmt: str = typer.Option("text", "--format", help="text, md, html (a full page) or json."),
            level: str = typer.Option("standard", "--level", help="summary, standard or full (every proof step)."),
            why_not: Optional[list[str]] = typer.Option(
                None, "--why-not", help="Also explain why this sentence does or does not hold on the "
                                        "Validator Scenario, e.g. \"173 can enter the junction\" (repeatable)."),
            rules: Optional[list[Path]] = RulesOption,
            db: Optional[Path] = DbOption, json_out: bool = JsonOption) -> None:
    """Explain why an incident's verdict is what it is.

    The verdict in one sentence, a plain summary, the potential violation, the validation, the
    penalty and liability, why-not questions, counterfactuals and the evidence.
    """
    from explain.layout import LEVELS
    from explain.explanation_formats import FORMATS
    if json_out:
        fmt = "json"
    if fmt not in FORMATS:
        fail(f"unknown format {fmt!r}; formats: {', '.join(FORMATS)}")
    if level not in LEVELS:
        fail(f"unknown level {level!r}; levels: {', '.join(LEVELS)}")
    files = check_files(rules)
    from explain.explanation_doc import document
    from explain.explanation_formats import render
    from explain.report import pick
    from reasoner.investigation import Investigation
    with open_existing(db) as store:
        require_run(store, run)
        inv = Investigation(store, rules=files)
        found = inv.incidents(run)
        chosen = pick(found, incident)
        if chosen is None:
            ids = ", ".join(f"{i}={inc.id}" for i, inc in enumerate(found, 1)) or "none"
            fail(f"no incident {incident!r} in run {run!r}; incidents: {ids}")
        doc = document(chosen, inv.explanation(chosen, why_not=why_not or []), store)
    typer.echo(render(doc, fmt, level), nl=False)
