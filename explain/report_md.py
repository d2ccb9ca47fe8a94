"""A report (explain/report.py) in Markdown: the HTML report's sections as text and tables, for a
case file, a ticket or a diff between two reports.

Markdown has no portable inline pictures, so the scene is a list (signals, vehicles with position,
heading and speed (mph, with the m/s recorded), monitors with their field of view) and the timeline a table of what changed
when: the same data the HTML draws. Every recorded string goes through explain/explanation_formats.py's `md`.
"""
from __future__ import annotations

from typing import Any

from .explanation_formats import md
from .explanation_formats import to_markdown as explanation_md
from .report_data import SECOND
from .report_parts import Report, ReportChain, ReportEntry, UsedRulebook
from .svg import colour_word
from .svg_scene import junctions_in_view
from .timeline_parts import ActTimeline
from .units import speed_text


def to_markdown(report: Report) -> str:
    p = report.provenance
    out = [f"# Incident report: run {md(report.run)}", "",
           f"Generated {md(report.generated)} by `gaps report` from the event store.", "",
           f"- tool: {md(p.tool)} {md(p.version)}", f"- store file: {md(p.store_path)}",
           f"- store sha256: {md(p.store_sha256 or 'none (a store in memory)')}"
           + (" (its -wal file held writes not yet in the file, not covered)" if p.wal_pending else ""), ""]
    out += _summary(report)
    out += _chain(report.chain)
    out += _rulebooks(report.rulebooks)
    for e in report.incidents:
        out += _incident(e)
    return "\n".join(out).rstrip() + "\n"


def _table(head: list[str], rows: list[list[Any]]) -> list[str]:
    return (["| " + " | ".join(md(h) for h in head) + " |", "|" + "---|" * len(head)]
            + ["| " + " | ".join(md("" if c is None else str(c)) for c in row) + " |" for row in rows] + [""])


def _summary(report: Report) -> list[str]:
    out = ["## Incidents", ""]
    if not report.incidents:
        return out + ["No potential violation was recorded or re-derived in this run.", ""]
    rows = [[e.number, r.id, r.time, r.vehicle, r.action, r.rule or "—", r.verdict,
             r.penalty or "none", r.liable, r.findings] for e in report.incidents for r in [e.row]]
    return out + _table(["#", "id", "time", "vehicle", "action", "rule", "verdict", "penalty", "liable",
                         "findings"], rows)


def _chain(chain: ReportChain) -> list[str]:
    status = "Verified" if chain.status.verified else "NOT VERIFIED" if chain.status.checked else "Not checked"
    out = ["## Chain verification", "", f"{status}: {md(chain.text)}.", ""]
    last = chain.last
    if last:
        out += _table(["checkpoints", "events at the last", "chain head", "Merkle root"],
                      [[chain.checkpoints, last.events, last.head, last.merkle_root]])
    return out


def _rulebooks(books: tuple[UsedRulebook, ...]) -> list[str]:
    return ["## Rulebooks", ""] + _table(["rulebook", "version", "sha256", "source", "used for"],
                                         [[b.name, b.version or "—", b.sha256, b.source,
                                           ", ".join(b.stages) or "recorded by the run, not used"] for b in books])


def _incident(e: ReportEntry) -> list[str]:
    r, pic, tl = e.row, e.scene, e.timeline
    out = ["", "---", "", f"## Incident {e.number}: vehicle {md(r.vehicle)}, {md(r.action)}, "
           f"{md(r.verdict)}", "", f"### The scene at {md(pic.offset)} from the run start", ""]
    shown = junctions_in_view(pic)        # as the HTML picture's caption: the junctions the picture shows
    out += [f"- signal {md(s.junction)} {md(s.approach)}: {md(colour_word(s.colour))}" for s in pic.signals
            if str(s.junction) in shown]
    for v in pic.vehicles:
        where = ("position not recorded" if v.x is None else
                 f"at ({v.x:g}, {v.y:g}) m, heading {_n(v.heading_deg)}°, speed {speed_text(v.speed_mps)}")
        mark = " (this incident)" if v.incident else ""
        out.append(f"- vehicle {md(v.id)} ({md(v.type or 'type not recorded')}){mark}: {where}")
    for m in pic.monitors:
        out.append(f"- {md(m.id)}: at ({_n(m.x)}, {_n(m.y)}) m, heading {_n(m.heading_deg)}°, "
                   f"field of view {_n(m.fov_deg)}°, range {_n(m.range_m)} m")
    out += ["", f"### Speed and signals from {(tl.window.t_from - tl.window.t) / SECOND:g} s to "
                f"+{(tl.window.t_to - tl.window.t) / SECOND:g} s", ""]
    out += _timeline_table(tl)
    out += [_demoted(explanation_md(e.explanation, "standard")), "### Rulebooks of this verdict", ""]
    out += _table(["stage", "rulebook", "sha256", "source"],
                  [[b.stage, b.book.name, b.book.sha256, b.book.source] for b in e.rulebooks])
    return out


def _timeline_table(tl: ActTimeline) -> list[str]:
    """What changed when in the timeline's window, in time order: the HTML timeline's points."""
    rows = [[_rel(tl, p.t), f"vehicle/{tl.window.vehicle}", f"speed {speed_text(p.speed_mps)}"] for p in tl.window.speed]
    rows += [[_rel(tl, p.t), p.monitor, f"observed speed {speed_text(p.speed_mps)}"] for p in tl.window.observed_speed]
    rows += [[_rel(tl, c.t), f"signal {tl.window.junction} {a.approach}", colour_word(c.colour)]
             for a in tl.window.signals for c in a.phases]
    line = tl.to_line
    rows += [[_rel(tl, p.t), f"{p.src} #{p.seq}", f"{p.m:g} m before the line" if p.m >= 0 else
              f"{-p.m:g} m past the line"] for p in (line.points if line else ())]
    if (other := tl.other) is not None:
        rows += [[_rel(tl, p.t), f"{p.src} #{p.seq}", f"speed of {other.user} {speed_text(p.speed_mps)} "
                  f"(whom {tl.window.vehicle} {other.how})"] for p in other.speed]
    rows.sort(key=lambda row: _sort_key(row[0]))
    return _table(["time", "source", "what"], rows) if rows else ["Nothing recorded in this window.", ""]


def _demoted(text: str) -> str:
    """The explanation's headings two levels down, under the incident's. Only headings start a
    line with # (`md` escapes a recorded one)."""
    return "\n".join("##" + line if line.startswith("#") else line for line in text.splitlines()) + "\n"


def _rel(tl: ActTimeline, t: int) -> str:
    d = (max(t, tl.window.t_from) - tl.window.t) / SECOND
    return ("≤ " if t < tl.window.t_from else "") + ("0 s" if d == 0 else f"{d:+g} s")


def _sort_key(text: str) -> float:
    value = text.removeprefix("≤ ").removesuffix(" s")
    return float(value) - (0.5 if text.startswith("≤ ") else 0)


def _n(value: float | None) -> str:
    return "?" if value is None else f"{value:g}"
