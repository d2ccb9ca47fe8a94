"""Running a document's `FILE.le.tests` expectations (`gaps rules verify`)."""
from __future__ import annotations

from pathlib import Path

from .engine import Engine, QuestionError, get_engine
from .le.errors import LEError
from .le.expectations import Outcome, Report, compare, read_expectations


def verify_file(path: str | Path, engine: Engine | None = None, tests: str | Path | None = None) -> Report:
    """Load `path` and run the expectations beside it (`path.tests`, or `tests`)."""
    path = Path(path)
    tests_path = Path(tests) if tests else path.with_name(path.name + ".tests")
    report = Report(str(path))
    expectations = read_expectations(tests_path.read_text(encoding="utf-8")) if tests_path.exists() else []
    engine = engine or get_engine()
    try:
        rb = engine.load(path.read_text(encoding="utf-8"), path.name)
    except LEError as exc:
        report.error = str(exc)
        report.outcomes = [Outcome(e, None, False, error="the document did not load") for e in expectations]
        return report
    for e in expectations:
        try:
            result = engine.query(rb, e.query, e.scenario)
        except (LEError, QuestionError) as exc:
            report.outcomes.append(Outcome(e, None, False, error=str(exc)))
            continue
        passed, exact = compare(e.answers, result.answers)
        report.outcomes.append(Outcome(e, result.answers, passed, exact and passed))
    return report
