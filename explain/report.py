"""A run's report: every incident (or one) with its explanation, a picture of the scene at the
incident, the speed and signals around it, the evidence, the rulebooks by sha256 and the chain
verification, as one self-contained document for an investigator, an insurer or a court.

    with reasoner.open("gaps.db") as case:
        report = build_report(case, "paper-junctions")             # a Report; .to_json()
    Path("report.html").write_text(render_report(report, "html"))  # or "md", "json"

The report is data first (explain/report_parts.py's `Report`, built once here; `.json` carries
its `to_json`, exactly what the pictures draw), then drawn:
HTML (report_html.py: inline SVG and CSS, no script, no external resource, prints well),
Markdown (the same sections as text and tables) or JSON. Every recorded string is escaped by the
renderer that writes it.
"""
from __future__ import annotations

import json
import os
import tempfile
from dataclasses import replace
from datetime import datetime, timezone
from pathlib import Path
from typing import Callable, Iterable

from reasoner import Case, Incident
from reasoner.timelines import timeline as speed_and_signals
from store import GapsError, Store

from . import phrases as ph
from .act_data import act_track, named_users
from .evidence import chain_text
from .explanation_doc import document
from .provenance import provenance
from .picture_parts import MapDrawn
from .report_data import (RecordedRulebook, name_users, recorded_rulebooks, run_map, run_start_body, scene_picture,
                          vehicle_junction)
from .report_parts import LastCheckpoint, Report, ReportChain, ReportEntry, StageRulebook, SummaryRow, UsedRulebook
from .timeline_parts import ActTimeline, Moment

FORMATS = {".html": "html", ".htm": "html", ".md": "md", ".json": "json"}
Progress = Callable[[int, int], None]      # (incidents done, total)


class ReportError(GapsError, ValueError):
    """A report asked for something the store does not hold (a run, an incident)."""


def format_for(path: Path) -> str:
    """The report format an output file's suffix asks for."""
    fmt = FORMATS.get(Path(path).suffix.lower())
    if fmt is None:
        raise ReportError(f"cannot tell the format from {str(path)!r}: name the file .html, .md or .json")
    return fmt


def build_report(case: Case, run: str, *, incident: str | int | None = None,
                 progress: Progress | None = None, now: datetime | None = None) -> Report:
    """The report of `run` (only `incident`, by id or 1-based number, if given), from what the
    case answers (reasoner.Case: its rulebooks, verdicts and chain checks). NoSuchRun or
    NoSuchIncident (both saying what there is) for what the store does not hold."""
    store = case.store
    case.require(run)                           # NoSuchRun before the file is hashed
    made_from = provenance(store.path)          # before the events are read: the file as it was found
    found = case.incidents(run)
    chosen = found if incident is None else [case.incident(run, incident)]
    status = case.chain(run)
    start = run_start_body(store, run)
    the_map = run_map(start)
    entries = []
    for done, inc in enumerate(chosen, 1):
        entries.append(_entry(case, inc, the_map))
        if progress is not None:
            progress(done, len(chosen))
    generated = (now or datetime.now(timezone.utc)).astimezone(timezone.utc)
    count, last = _checkpoints(store, run)
    return Report(run, generated.isoformat(timespec="seconds").replace("+00:00", "Z"), made_from, len(found),
                  chosen[0].id if incident is not None else None,
                  ReportChain(status, chain_text(status), count, last),
                  _rulebooks(store, chosen, recorded_rulebooks(start)), tuple(entries))


def render_report(report: Report, fmt: str) -> str:
    if fmt == "html":
        from .report_html import to_html
        return to_html(report)
    if fmt == "md":
        from .report_md import to_markdown
        return to_markdown(report)
    if fmt == "json":
        return json.dumps(report.to_json(), indent=2, ensure_ascii=False, default=str) + "\n"
    raise ReportError(f"report format is html, md or json, not {fmt!r}")


def summary_row(inc: Incident) -> SummaryRow:
    """The summary table's row: what an insurer scans first."""
    p = inc.penalty
    penalty = None
    if p:
        fine = f"£{p.fine_gbp}" if p.fine_gbp is not None else "regulatory sanctions"
        penalty = fine + (f", {p.points} points" if p.points else "")
    return SummaryRow(inc.id, inc.t, ph.clock(inc.t), inc.vehicle, inc.action, inc.rule, inc.verdict, penalty,
                      inc.liable, len(inc.findings))


# --- per incident ---------------------------------------------------------------------------------

def _entry(case: Case, inc: Incident, the_map: MapDrawn) -> ReportEntry:
    store = case.store
    doc = document(inc, case.explanation(inc), store)
    picture = scene_picture(store, inc.run, inc.t, inc.vehicle, the_map)
    me = picture.me
    window = speed_and_signals(store, inc.run, inc.t, inc.vehicle, vehicle_junction(picture))
    moments = tuple(Moment(what, t) for what, t in inc.moments if window.t_from <= t <= window.t_to)
    to_line, other = act_track(store, inc, picture, window.t_from, window.t_to, case.context(inc.run))
    tl = ActTimeline(window, me.heading_deg if me else None, moments, to_line, other)
    picture = name_users(picture, named_users(inc, picture), the_map)
    return ReportEntry(case.number(inc), summary_row(inc), doc, picture, tl,
                       tuple(StageRulebook(stage, b) for stage, b in inc.rulebooks.items()))


# --- run-wide sections ----------------------------------------------------------------------------

def _checkpoints(store: Store, run: str) -> tuple[int, LastCheckpoint | None]:
    """How many checkpoints the run has and its latest (count, chain head, Merkle root): the
    figures a second party can check a copy of the run against. The store's checkpoints are
    read here, once."""
    cps = store.checkpoints(run)
    last = cps[-1] if cps else None
    return len(cps), (None if last is None else
                      LastCheckpoint(last.get("count"), last.get("head"), last.get("merkle_root")))


def _rulebooks(store: Store, incidents: list[Incident], recorded: list[RecordedRulebook]) -> tuple[UsedRulebook, ...]:
    """Every rulebook a verdict used, once, then those the run recorded that no verdict used:
    name, sha256, where it came from (given with --rules, recorded by the run, or the project's
    current one), the stages it served, and its version as the run recorded it or the store
    holds it under that sha256."""
    versions = {b.sha256: b.version for b in recorded if b.sha256 and b.version}
    seen: dict[str, UsedRulebook] = {}
    for inc in incidents:
        for stage, b in inc.rulebooks.items():
            sha = b.sha256
            if not sha:
                continue
            if sha not in seen:
                seen[sha] = UsedRulebook(b.name, sha, b.source, (), versions.get(sha) or _version(store, sha))
            if stage not in seen[sha].stages:
                seen[sha] = replace(seen[sha], stages=seen[sha].stages + (stage,))
    for r in recorded:
        if r.sha256 and r.sha256 not in seen:
            seen[r.sha256] = UsedRulebook(r.name, r.sha256, "recorded", (), r.version or _version(store, r.sha256))
    return tuple(seen.values())


def _version(store: Store, sha: str) -> str | None:
    try:
        stored = store.get_rulebook(sha)
    except ValueError:          # the stored text no longer hashes to its address
        return "stored text does not match its sha256"
    return stored.get("version") if stored else None


def print_report_pdf(report: Report, target: Path, chromium: str, page: Path | None = None,
                     stores: Iterable[str | os.PathLike] = ()) -> Path:
    """The report printed to `target` (PDF) by headless Chromium: always its HTML page, `page`
    where that is already written, else a temporary one. ToolMissing or PdfError (explain/pdf.py)
    when Chromium cannot print it."""
    from .pdf import print_pdf
    if page is not None:
        return print_pdf(page, target, chromium, stores=stores)
    with tempfile.TemporaryDirectory(prefix="gaps-report-") as tmp:
        html = Path(tmp) / "report.html"
        html.write_text(render_report(report, "html"), encoding="utf-8")
        return print_pdf(html, target, chromium, stores=stores)
