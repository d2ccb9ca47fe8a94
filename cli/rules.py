"""`gaps rules check|query|prolog|verify FILE.le`: the LE tool chain on one document.

check, query and prolog read standard input for FILE `-` (its messages name it `stdin.le`).
"""
from __future__ import annotations

import sys
from pathlib import Path
from typing import List, Optional

import typer

from cli.app import fail, print_json
from cli.options import JsonOption, is_stdio

HELP = "Check, query, compile and verify Logical English rulebooks."
FileArg = typer.Argument(..., help="An LE document (FILE.le); - for stdin.")
STDIN_NAME = "stdin.le"


def _name(path: Path) -> str:
    return STDIN_NAME if is_stdio(path) else path.name


def _read(path: Path) -> str:
    if is_stdio(path):
        try:
            return sys.stdin.buffer.read().decode("utf-8")
        except UnicodeDecodeError:
            fail("standard input is not UTF-8 text")
    if not path.is_file():
        fail(f"no such file: {path}")
    try:
        return path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        fail(f"{path} is not UTF-8 text")


def check(file: Path = FileArg, json_out: bool = JsonOption) -> None:
    """Compile and load the document, printing its errors (exit 1) and warnings."""
    from reasoner import check_rulebook
    checked = check_rulebook(_read(file), _name(file))
    if json_out:
        print_json(checked.to_json(str(file)))
    elif checked.error is not None:
        typer.echo(str(checked.error), err=True)
    else:
        for w in checked.warnings:
            typer.echo(str(w))
        summary = ", ".join(f"{n} {k}" for k, n in checked.counts.items())
        typer.echo(f"{_name(file)}: ok ({summary}; {len(checked.warnings)} warnings)")
    if not checked.ok:
        raise typer.Exit(1)


def query(file: Path = FileArg,
          query_: str = typer.Option(..., "--query", "-q",
                                     help="A query of the document by name, or a question in LE."),
          scenario: Optional[str] = typer.Option(None, "--scenario", "-s",
                                                 help="A scenario of the document by name."),
          fact: List[str] = typer.Option([], "--fact", "-f", help="Extra scenario facts in LE (repeatable)."),
          explain: bool = typer.Option(False, "--explain", help="Add proof trees (or why there is no answer)."),
          json_out: bool = JsonOption) -> None:
    """Answer a query on a scenario, one LE sentence per proof."""
    from explain import render_tree
    from reasoner import QuestionError, ask_rulebook
    try:
        asked = ask_rulebook(_read(file), _name(file), query_, scenario=scenario, facts=fact, explain=explain)
    except QuestionError as exc:
        fail(str(exc), 1)
    if json_out:
        print_json(asked.to_json())
        return
    result, rb = asked.result, asked.rulebook
    if not result.answers:
        typer.echo("no answers")
    for i, answer in enumerate(result.answers):
        typer.echo(answer)
        if explain:
            for tree in result.proofs[i]:
                typer.echo("\n".join(render_tree(tree, rb, None, 1)))
    if explain and result.why_not:
        typer.echo("why not:")
        for tree in result.why_not:
            typer.echo("\n".join(render_tree(tree, rb, None, 1)))


def prolog(file: Path = FileArg) -> None:
    """Print the Prolog clauses the document compiles to, each after its LE source line."""
    from reasoner import prolog_text
    typer.echo(prolog_text(_read(file), _name(file)), nl=False)


def verify(file: Path = typer.Argument(..., help="An LE document (FILE.le) or a folder of them."),
           tests: Optional[Path] = typer.Option(None, "--tests", help="Expectations (default FILE.le.tests)."),
           json_out: bool = JsonOption) -> None:
    """Run the expectations of FILE.le.tests against the document (a directory: every .le in it).

    Each `expected(Query, Scenario, Answers).` line of the tests file is one expectation.
    """
    from reasoner import verify_rulebooks
    verified = verify_rulebooks(file, tests)
    reports = verified.reports
    if json_out:
        print_json(verified.to_json())
    else:
        for r in reports:
            if r.error:
                typer.echo(f"{r.file}: does not load: {r.error}")
            for o in r.outcomes:
                if not o.passed:
                    e = o.expectation
                    typer.echo(f"FAIL {Path(r.file).name} query {e.query!r} scenario {e.scenario!r}: "
                               f"expected {e.answers} got {o.got if o.error is None else o.error}")
            if len(reports) > 1:
                typer.echo(f"{Path(r.file).name}: {r.passed} passed, {r.failed} failed")
        note = f" ({verified.normalised} after normalising dates and punctuation spacing)" if verified.normalised else ""
        typer.echo(f"{verified.passed} passed, {verified.failed} failed{note}")
    raise typer.Exit(0 if verified.ok else 1)
