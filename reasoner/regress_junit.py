"""A regression as JUnit XML, so a CI system shows each judged case: one testsuite per run for its
incidents and one for its recorded decisions, one testcase per case, a failure per change
(message: what changed; text: why). Written with xml.etree, so any text (a hostile run id, a
rule's LE) is escaped."""
from __future__ import annotations

import xml.etree.ElementTree as ET

from .regress import CaseResult, Regression
from .regress_text import WHAT, from_to


def junit_xml(result: Regression, name: str = "gaps regress") -> bytes:
    """The XML document, UTF-8, with its declaration."""
    root = ET.Element("testsuites", name=name)
    failures = tests = 0
    for run in result.runs:
        for what, cases in (("incidents", run.incidents), ("decisions", run.decisions)):
            suite = ET.SubElement(root, "testsuite", name=f"{run.run} {what}")
            failed = 0
            for case in cases:
                failed += _testcase(suite, case)
            suite.set("tests", str(len(cases)))
            suite.set("failures", str(failed))
            suite.set("errors", "0")
            tests += len(cases)
            failures += failed
    root.set("tests", str(tests))
    root.set("failures", str(failures))
    root.set("errors", "0")
    return ET.tostring(root, encoding="utf-8", xml_declaration=True)


def _testcase(suite: ET.Element, case: CaseResult) -> int:
    subject = f'"{case.action}"' if case.case == "decision" else case.action
    element = ET.SubElement(suite, "testcase", classname=f"{case.run}.{case.case}",
                            name=f"{case.id} vehicle {case.vehicle} {subject}")
    for change in case.changes:
        failure = ET.SubElement(element, "failure", type=change.kind,
                                message=f"{WHAT[change.kind]}: {from_to(change)}")
        failure.text = "\n".join(change.reasons)
    return 1 if case.changes else 0
