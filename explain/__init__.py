"""Plain-English explanations of verdicts and reports, rendered from what the reasoner found.

`explain.explanation(case, incident)` and `explain.write_report(case, run, path)` are the public
entry points (docs/api.md); beside them, the words and drawings the command line prints (an
incident's line, a scene's text, a report's PDF). Every other room reaches explain through these
names; the modules below them word and draw, they do not reason.
"""
from .api import (EXPLANATION_FORMATS, REPORT_FORMATS, ExplainError, ScenePicture, check_explanation, explanation,
                  report_format, report_text, scene_picture_svg, write_report)
from .featured import featured
from .listing import acts_summary, explanations, incident_line
from .pdf import PdfError, ToolMissing, find_chromium
from .provenance import tool_version
from .report import ReportError, build_report, print_report_pdf, render_report
from .report_parts import Report
from .scene_text import scene_lines
from .text import explain_incident, render_tree, sentence

__all__ = ["EXPLANATION_FORMATS", "REPORT_FORMATS", "ExplainError", "PdfError", "Report", "ReportError", "ScenePicture",
           "ToolMissing", "acts_summary", "build_report", "check_explanation", "explain_incident", "explanation",
           "explanations", "featured", "find_chromium", "incident_line", "print_report_pdf", "render_report",
           "render_tree", "report_format", "report_text", "scene_lines", "scene_picture_svg", "sentence",
           "tool_version", "write_report"]
