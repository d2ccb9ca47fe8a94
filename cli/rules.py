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
    from reasoner.engine import get_engine
    from reasoner.rulebooks import LEError
    text = _read(file)
    try:
        rb = get_engine().load(text, _name(file))
    except LEError as exc:
        if json_out:
            print_json({"file": str(file), "ok": False, "errors": [exc.as_dict()], "warnings": []})
        else:
            typer.echo(str(exc), err=True)
        raise typer.Exit(1)
    doc = rb.document
    counts = {"templates": len(doc.templates), "rules": len(doc.rules),
              "scenarios": len(doc.scenarios), "queries": len(doc.queries)}
    if json_out:
        print_json({"file": str(file), "ok": True, "errors": [], "counts": counts,
                    "warnings": [w.as_dict() for w in doc.warnings], "sha256": rb.sha256})
        return
    for w in doc.warnings:
        typer.echo(str(w))
    summary = ", ".join(f"{n} {k}" for k, n in counts.items())
    typer.echo(f"{_name(file)}: ok ({summary}; {len(doc.warnings)} warnings)")


def query(file: Path = FileArg,
          query_: str = typer.Option(..., "--query", "-q",
                                     help="A query of the document by name, or a question in LE."),
          scenario: Optional[str] = typer.Option(None, "--scenario", "-s",
                                                 help="A scenario of the document by name."),
          fact: List[str] = typer.Option([], "--fact", "-f", help="Extra scenario facts in LE (repeatable)."),
          explain: bool = typer.Option(False, "--explain", help="Add proof trees (or why there is no answer)."),
          json_out: bool = JsonOption) -> None:
    """Answer a query on a scenario, one LE sentence per proof."""
    from explain.text import render_tree
    from reasoner.engine import QuestionError, enrich, get_engine
    from reasoner.rulebooks import parse_facts, parse_question
    engine = get_engine()
    rb = engine.load(_read(file), _name(file))
    doc = rb.document
    if query_ in doc.queries or query_ in doc.unreadable_queries:
        body = rb.query(query_).body
    else:
        body = parse_question(doc, query_)
    facts = list(rb.scenario(scenario)) if scenario is not None else []
    for f in fact:
        facts += parse_facts(doc, f)
    try:
        result = engine.answers(rb, body, facts, explain=explain)
    except QuestionError as exc:
        fail(str(exc), 1)
    if json_out:
        out = {"answers": result.answers}
        if explain:
            out["proofs"] = [[enrich(t, rb) for t in trees] for trees in result.proofs]
            if result.why_not is not None:
                out["why_not"] = [enrich(t, rb) for t in result.why_not]
        print_json(out)
        return
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
    from reasoner.engine import get_engine
    engine = get_engine()
    rb = engine.load(_read(file), _name(file))
    typer.echo(engine.prolog_text(rb), nl=False)


def verify(file: Path = typer.Argument(..., help="An LE document (FILE.le) or a folder of them."),
           tests: Optional[Path] = typer.Option(None, "--tests", help="Expectations (default FILE.le.tests)."),
           json_out: bool = JsonOption) -> None:
    """Run the expectations of FILE.le.tests against the document (a directory: every .le in it).

    Each `expected(Query, Scenario, Answers).` line of the tests file is one expectation.
    """
    from reasoner.rulebooks import ExpectationError
    from reasoner.rules_verify import verify_file
    files = sorted(file.glob("*.le")) if file.is_dir() else [file]
    if not files or not all(f.is_file() for f in files):
        fail(f"no LE document at {file}")
    try:
        reports = [verify_file(f, tests=tests if not file.is_dir() else None) for f in files]
    except ExpectationError as exc:
        fail(f"cannot read the expectations: {exc}")
    passed = sum(r.passed for r in reports)
    failed = sum(r.failed for r in reports)
    normalised = sum(r.normalised for r in reports)
    if json_out:
        print_json({"passed": passed, "failed": failed, "passed_only_after_normalising": normalised,
                    "documents": [r.as_dict() for r in reports]})
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
        note = f" ({normalised} after normalising dates and punctuation spacing)" if normalised else ""
        typer.echo(f"{passed} passed, {failed} failed{note}")
    raise typer.Exit(0 if failed == 0 and not any(r.error for r in reports if r.outcomes) else 1)
