"""Plain-English explanations of verdicts and reports, rendered from what the reasoner found.

`explain.explanation(case, incident)` and `explain.write_report(case, run, path)` are the public
entry points (docs/api.md); the modules below them word and draw, they do not reason.
"""
from .api import explanation, report_text, write_report
from .text import explain_incident, render_tree, sentence

__all__ = ["explain_incident", "explanation", "render_tree", "report_text", "sentence", "write_report"]
