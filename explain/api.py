"""What a script calls to put a case into words: an incident's explanation, a run's report, a
scene's picture.

    import explain, reasoner
    with reasoner.open("gaps.db") as case:
        inc = case.incident("paper-junctions", 1)
        print(explain.explanation(case, inc))
        explain.write_report(case, "paper-junctions", "report.html")

The reasoner answers (reasoner.Case); these functions only word and draw the answers, in the
formats `gaps explain`, `gaps report` and `gaps scene --svg` print: each returns what the command
prints, and a request that names nothing (a format, a level, a junction) is an `ExplainError`
saying what there is.
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Iterable

from store import GapsError, check_output, write_text

from .explanation_doc import document
from .explanation_formats import FORMATS as EXPLANATION_FORMATS
from .explanation_formats import render
from .layout import LEVELS
from .report import FORMATS as REPORT_SUFFIXES
from .report import ReportError, build_report, format_for, render_report
from .report_data import run_map, run_start_body, scene_picture
from .svg_scene import scene_svg

if TYPE_CHECKING:
    from reasoner import Case, Incident

REPORT_FORMATS = tuple(sorted(set(REPORT_SUFFIXES.values())))      # html, json, md
SVG_HEADER = '<?xml version="1.0" encoding="UTF-8"?>\n'


class ExplainError(GapsError, ValueError):
    """An explanation or picture asked for in a form there is not (a format, a level) or of
    something the run's map does not hold (a junction)."""


def check_explanation(fmt: str, level: str) -> None:
    """ExplainError unless `fmt` and `level` are ones an explanation is rendered in: said before
    any work, as `gaps explain` says it before it opens the store."""
    if fmt not in EXPLANATION_FORMATS:
        raise ExplainError(f"unknown format {fmt!r}; formats: {', '.join(EXPLANATION_FORMATS)}")
    if level not in LEVELS:
        raise ExplainError(f"unknown level {level!r}; levels: {', '.join(LEVELS)}")


def explanation(case: Case, incident: Incident, *, fmt: str = "text", level: str = "standard",
                why_not: Iterable[str] = ()) -> str:
    """The incident explained as `gaps explain` prints it: fmt text, md, html or json; level
    summary, standard or full; `why_not` sentences asked on the Validator Scenario."""
    check_explanation(fmt, level)
    found = case.explanation(incident, why_not=why_not)
    return render(document(incident, found, case.store), fmt, level)


def report_format(given: str | None, output: str | os.PathLike | None) -> str:
    """The report format asked for: `given` (html, md or json), else the suffix of `output`,
    else HTML (standard output, None). ReportError for a format there is not."""
    if given is not None:
        if given not in REPORT_FORMATS:
            raise ReportError(f"unknown format {given!r}; formats: {', '.join(REPORT_FORMATS)}")
        return given
    return "html" if output is None else format_for(Path(output))


def report_text(case: Case, run: str, *, fmt: str = "html", incident: str | int | None = None,
                progress: Callable[[int, int], None] | None = None) -> str:
    """The run's report (only `incident`, by id or number, if given) as html, md or json text."""
    return render_report(build_report(case, run, incident=incident, progress=progress), fmt)


def write_report(case: Case, run: str, path: str | os.PathLike, *, incident: str | int | None = None,
                 progress: Callable[[int, int], None] | None = None) -> Path:
    """The run's report written to `path` in the format its suffix names (.html, .md, .json)."""
    target = Path(path)
    check_output(target, [case.store.path])     # before the work: evidence is never an output
    text = report_text(case, run, fmt=format_for(target), incident=incident, progress=progress)
    write_text(target, text, [case.store.path])
    return target


@dataclass(frozen=True)
class ScenePicture:
    """The scene at a moment as an SVG file's text, and what `gaps scene --svg` says of it: its
    offset from the run start, the junction it is zoomed to (None: the whole map) and how many
    road users it shows on the map."""

    svg: str
    offset: str
    junction: str | None
    shown: int

    def to_json(self) -> dict[str, object]:
        return {"offset": self.offset, "junction": self.junction, "shown": self.shown}


def scene_picture_svg(case: Case, run: str, at: int | str, *, vehicle: str | None = None,
                      junction: str | None = None) -> ScenePicture:
    """The scene of `run` at `at` drawn (the report's drawing): zoomed to `junction`, else to
    `vehicle`'s, else to the busiest. A vehicle not present at that time is said as the scene
    says it (reasoner.SceneError); a junction not on the run's map is an ExplainError."""
    t = case.time(run, at)
    if vehicle is not None:
        case.scene(run, t, vehicle=vehicle, judge=False)       # UnknownVehicle names who was there
    store = case.store
    the_map = run_map(run_start_body(store, run))
    names = [j.id for j in the_map.junctions]
    if junction is not None and junction not in names:
        raise ExplainError(f"no junction {junction!r} on the map of run {run!r}; "
                           f"its junctions: {', '.join(map(str, names)) or 'none'}")
    pic = scene_picture(store, run, t, vehicle, the_map, junction=junction)
    shown = sum(1 for u in pic.movers if u.x is not None and u.present)
    return ScenePicture(SVG_HEADER + scene_svg(pic) + "\n", pic.offset, pic.junction, shown)
