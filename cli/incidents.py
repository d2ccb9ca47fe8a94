"""`gaps incidents`: every potential violation of a run, validated, one line each (or explained)."""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from cli.app import check_files, open_existing, print_json
from cli.options import DbOption, JsonOption, RulesOption, RunOption
from cli.progress import stderr_progress
from cli.safe_text import printable
from reasoner import Case


def incidents(run: Optional[str] = RunOption, db: Optional[Path] = DbOption,
              json_out: bool = JsonOption,
              rules: Optional[list[Path]] = RulesOption,
              verdict: Optional[str] = typer.Option(None, "--verdict",
                                                    help="Only this verdict: punishable, mitigated or dismissed."),
              vehicle: Optional[str] = typer.Option(None, "--vehicle", help="Only this vehicle's incidents."),
              rule: Optional[str] = typer.Option(None, "--rule", help="Only incidents under this rule (HC 176)."),
              source: Optional[str] = typer.Option(
                  None, "--source", help="Where the act was found: monitors (by a monitor), own-record (only in "
                                         "the vehicle's own record), or all (the default)."),
              explain: bool = typer.Option(False, "--explain", help="Print each incident's full explanation.")
              ) -> None:
    """List every potential violation of a run, validated as punishable, mitigated or dismissed.

    One line per incident: time, id, vehicle, action, rule, verdict, penalty, who is liable, the
    margin where there is one, and the findings. A rulebook given with --rules is judged with
    first; a stage it does not define keeps the run's own or the current rulebook.
    """
    files = check_files(rules)
    with open_existing(db) as store:
        show_incidents(Case(store, files), run, json_out, explain=explain,
                       verdict=verdict, vehicle=vehicle, rule=rule, source=source)


def show_incidents(case: Case, run: Optional[str], json_out: bool, *, explain: bool,
                   verdict: Optional[str] = None, vehicle: Optional[str] = None, rule: Optional[str] = None,
                   source: Optional[str] = None) -> None:
    """Judge the run (every run: None) and print its incidents as JSON, one line each, or
    explained in full."""
    from explain import explanations, incident_line
    with stderr_progress("judging incidents") as progress:      # the bar is gone before printing
        case.incidents(run, progress=progress)
    found = case.numbered(run, verdict=verdict, vehicle=vehicle, rule=rule, source=source)
    if json_out:
        print_json([{**inc.summary_json(), "number": n} for n, inc in found])
    elif not found:
        typer.echo("No potential violations recorded" + _filtered(verdict, vehicle, rule, source) + ".")
    elif explain:
        for text in explanations(case, found):
            typer.echo(text)
    else:
        several = len({inc.run for _, inc in found}) > 1     # numbers count within a run: say whose
        shown = None
        for n, inc in found:
            if several and inc.run != shown:
                shown = inc.run
                typer.echo(printable(f"run {inc.run} (`gaps explain --run {inc.run} N`):"))
            typer.echo(printable(incident_line(inc, n)))


def _filtered(verdict: Optional[str], vehicle: Optional[str], rule: Optional[str], source: Optional[str] = None) -> str:
    said = [f"verdict {verdict}" if verdict else "", f"vehicle {vehicle}" if vehicle else "",
            f"rule {rule}" if rule else "", f"source {source}" if source and source != "all" else ""]
    shown = ", ".join(s for s in said if s)
    return f" matching {printable(shown)}" if shown else ""
