"""A regression as JUnit XML, so a CI system shows each judged case: one testsuite per run for its
incidents and one for its recorded decisions, one testcase per case, a failure per change
(message: what changed; text: why). Written with xml.etree, so any text (a hostile run id, a
rule's LE) is escaped. Times are wall seconds: a suite's is what judging its run's incidents (or
its decisions) took; its cases are judged together, so each case carries an equal share of it."""
from __future__ import annotations

import xml.etree.ElementTree as ET

from .regression import CaseResult, Regression
from .text import WHAT, from_to


def junit_xml(result: Regression, name: str = "gaps regress") -> bytes:
    """The XML document, UTF-8, with its declaration."""
    root = ET.Element("testsuites", name=name)
    failures = tests = 0
    total = 0.0
    for run in result.runs:
        for what, cases in (("incidents", run.incidents), ("decisions", run.decisions)):
            seconds = run.seconds.get(what, 0.0)
            suite = ET.SubElement(root, "testsuite", name=f"{run.run} {what}")
            failed = 0
            for case in cases:
                failed += _testcase(suite, case, seconds / len(cases))
            suite.set("tests", str(len(cases)))
            suite.set("failures", str(failed))
            suite.set("errors", "0")
            suite.set("time", _seconds(seconds))
            tests += len(cases)
            failures += failed
            total += seconds
    root.set("tests", str(tests))
    root.set("failures", str(failures))
    root.set("errors", "0")
    root.set("time", _seconds(total))
    return ET.tostring(root, encoding="utf-8", xml_declaration=True)


def _seconds(seconds: float) -> str:
    return f"{seconds:.6f}"


def _testcase(suite: ET.Element, case: CaseResult, seconds: float) -> int:
    subject = f'"{case.action}"' if case.case == "decision" else case.action
    element = ET.SubElement(suite, "testcase", classname=f"{case.run}.{case.case}",
                            name=f"{case.id} vehicle {case.vehicle} {subject}", time=_seconds(seconds))
    for change in case.changes:
        failure = ET.SubElement(element, "failure", type=change.kind,
                                message=f"{WHAT[change.kind]}: {from_to(change)}")
        failure.text = "\n".join(change.reasons)
    return 1 if case.changes else 0
