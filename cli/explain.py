"""`gaps explain --run R INCIDENT`: one incident's verdict explained, in text, Markdown, HTML or JSON.

The incident is found and its explanation worked out by the reasoner's `Case` (one way, as a
script asks: docs/api.md), put into words by `explain.explanation`; this module reads the options
and prints. INCIDENT is the incident's id (`monitor/m1:3`) or its number in `gaps incidents`
order (1 is the first). Exit codes: 0 shown; 2 for what names nothing
(no store, no such run, no such incident, a rulebook file that is missing, an unknown format).
"""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from cli import completion
from cli.app import check_files, open_existing
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
    from explain import check_explanation, explanation
    from reasoner import Case
    fmt = "json" if json_out else fmt
    check_explanation(fmt, level)
    files = check_files(rules)
    with open_existing(db) as store:
        case = Case(store, files)
        text = explanation(case, case.incident(run, incident), fmt=fmt, level=level, why_not=why_not or [])
    typer.echo(text, nl=False)
