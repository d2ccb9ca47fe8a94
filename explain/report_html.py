"""A report (explain/report.py) as one self-contained HTML page.

Readable offline and years later: the CSS is inline, the pictures are inline SVG, there is no
script, no font, no image file and no link out of the page, so the file alone is the record.
Printed (and as the PDF `gaps report --pdf` prints from this page), it is A4 with the run, the
tool's version, the store file's sha256 and "page N of M" in the margins of every page (CSS
margin boxes, which Chromium honours), each incident starts a page, and no picture, table row or
proof line is cut across two pages where it fits on one: a page torn from the bundle still says
where it came from. Each incident's explanation is
explain/explanation_formats.py's `html_fragment` at the standard level, the same words as `gaps explain`.
"""
from __future__ import annotations

import math
from .explanation_formats import esc, html_fragment
from .picture_parts import Picture
from .presence import FRESH_NS
from .provenance import Provenance
from .report_data import SECOND
from .report_parts import Report, ReportChain, ReportEntry, UsedRulebook
from .phrases import join
from .svg import colour_word
from .svg_scene import junctions_in_view, out_of_view, scene_svg
from .svg_timeline import timeline_svg
from .timeline_parts import ActTimeline

STYLE = """
:root{color-scheme:light}
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;max-width:64rem;margin:1.5rem auto;
padding:0 1rem;line-height:1.45;color:#1b1b1b;background:#fff}
h1{font-size:1.6rem;margin-bottom:.2rem}h2{font-size:1.3rem}h3{font-size:1.05rem;margin-top:1.2rem}
.meta{color:#555;margin-top:0}
table{border-collapse:collapse;font-size:.88rem;margin:.5rem 0}
td,th{border:1px solid #ccc;padding:.2rem .45rem;text-align:left;vertical-align:top}
th{background:#f2f2f2}
td.sha,code{font-family:ui-monospace,"DejaVu Sans Mono",monospace;font-size:.8rem;word-break:break-all}
span.verdict-punishable{color:#a40000;font-weight:600}span.verdict-mitigated{color:#7a5b00;font-weight:600}
span.verdict-dismissed{color:#35607a;font-weight:600}
.ok{color:#1d6b2f;font-weight:600}.bad{color:#a40000;font-weight:700}
article.incident{border-top:3px solid #333;margin-top:2.5rem;padding-top:.5rem}
figure{margin:1rem 0}figure svg{max-width:100%;height:auto;border:1px solid #ddd}
figcaption{font-size:.85rem;color:#444;margin-top:.3rem}
section.gaps-explanation h2{font-size:1.15rem}
.gaps-explanation.verdict-punishable h2{color:#a40000}.gaps-explanation.verdict-mitigated h2{color:#7a5b00}
ul.proof,ul.proof ul{list-style:none;padding-left:1.2rem}
.provenance td{word-break:break-all}
@media print{body{max-width:none;margin:0;font-size:10pt}
article.incident{break-before:page;border-top:none;margin-top:0}
figure,svg,tr,li,p{break-inside:avoid}h1,h2,h3{break-after:avoid}thead{display:table-header-group}
figure svg{width:100%;max-width:150mm}a{color:inherit;text-decoration:none}}
"""
SHA_CLASS = ' class="sha"'
OUTSIDE_NAMED = 10       # a caption names at most this many road users outside the picture
# the margins of every printed page; {run}, {version}, {store} and {sha} are CSS strings
PAGE = """
@page{{size:A4;margin:17mm 15mm 19mm 15mm;
@top-left{{content:"Incident report: run " {run};font:8pt sans-serif;color:#555}}
@top-right{{content:"mind-the-gaps " {version};font:8pt sans-serif;color:#555}}
@bottom-left{{content:"store " {store} " sha256 " {sha};font:6.5pt monospace;color:#555}}
@bottom-right{{content:"page " counter(page) " of " counter(pages);font:8pt sans-serif}}}}
"""


def to_html(report: Report) -> str:
    run = report.run
    title = f"Incident report: run {run}"
    parts = ["<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
             '<meta name="viewport" content="width=device-width, initial-scale=1">',
             f"<title>{esc(title)}</title>", f"<style>{STYLE}{_page_css(report)}</style>", "</head>", "<body>",
             "<header>", f"<h1>{esc(title)}</h1>",
             f'<p class="meta">Generated {esc(report.generated)} by <code>gaps report</code> from the event '
             f"store. {_scope(report)}</p>", *_provenance(report.provenance), "</header>"]
    parts += _summary(report)
    parts += _chain(report.chain)
    parts += _rulebooks(report.rulebooks)
    for entry in report.incidents:
        parts += _incident(entry)
    parts += ["</body>", "</html>"]
    return "\n".join(parts) + "\n"


def css_string(text: str) -> str:
    """`text` as a CSS string every character of which but letters, digits and a few harmless
    marks is a hex escape: a recorded run id or a file path cannot end the string, the rule or
    the <style> element."""
    keep = set("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 .,:_-+")
    return '"' + "".join(c if c in keep else f"\\{ord(c):06x}" for c in text) + '"'


def _page_css(report: Report) -> str:
    p = report.provenance
    return PAGE.format(run=css_string(report.run), version=css_string(p.version),
                       store=css_string(p.store_path.rsplit("/", 1)[-1]),
                       sha=css_string(p.store_sha256 or "none (a store in memory)"))


def _provenance(p: Provenance) -> list[str]:
    """Which tool made the report from which store file, so a copy of the file can be checked
    against it (sha256sum)."""
    sha = p.store_sha256 or "none: the store was in memory, not a file"
    rows = [("tool", f"{p.tool} {p.version}"), ("store file", p.store_path),
            ("store sha256", sha), ("store size", f"{p.store_bytes:,} bytes")]
    out = ['<table class="provenance"><tbody>']
    out += [f'<tr><th>{esc(k)}</th><td{SHA_CLASS if k == "store sha256" else ""}>{esc(v)}</td></tr>'
            for k, v in rows]
    out.append("</tbody></table>")
    if p.wal_pending:
        out.append('<p class="meta">The store\'s write-ahead log (its -wal file) held writes not yet in the file '
                   "when it was hashed: the sha256 is of the file as it was then, without them.</p>")
    return out


def _scope(report: Report) -> str:
    n, total = len(report.incidents), report.incidents_in_run
    if report.selected is not None:
        return f"One incident of the {total} the run holds."
    return {0: "The run holds no potential violation.", 1: "The run holds one incident."}.get(
        total, f"The run holds {total} incidents.") if n == total else f"{n} of {total} incidents."


def _summary(report: Report) -> list[str]:
    head = ["#", "id", "time", "vehicle", "action", "rule", "verdict", "penalty", "liable", "findings"]
    out = ['<section id="summary">', "<h2>Incidents</h2>"]
    if not report.incidents:
        return out + ["<p>No potential violation was recorded or re-derived in this run.</p>", "</section>"]
    out.append('<table class="summary"><thead><tr>' + "".join(f"<th>{h}</th>" for h in head) + "</tr></thead><tbody>")
    for e in report.incidents:
        r = e.row
        cells = [f'<a href="#report-incident-{e.number}">{e.number}</a>', esc(r.id), esc(r.time),
                 esc(r.vehicle), esc(r.action), esc(r.rule or "—"),
                 f'<span class="verdict-{esc(r.verdict)}">{esc(r.verdict)}</span>',
                 esc(r.penalty or "none"), esc(r.liable), str(int(r.findings))]
        out.append('<tr class="incident-row">' + "".join(f"<td>{c}</td>" for c in cells) + "</tr>")
    out += ["</tbody></table>", "</section>"]
    return out


def _chain(chain: ReportChain) -> list[str]:
    if chain.status.verified:
        status = '<span class="ok">Verified.</span>'
    elif chain.status.checked:
        status = '<span class="bad">NOT VERIFIED.</span>'
    else:
        status = "Not checked."
    out = ['<section id="chain">', "<h2>Chain verification</h2>",
           f"<p>{status} {esc(chain.text[:1].upper() + chain.text[1:])}.</p>"]
    last = chain.last
    if last:
        out.append("<table><tbody>"
                   f"<tr><th>checkpoints</th><td>{int(chain.checkpoints)}</td></tr>"
                   f"<tr><th>events at the last checkpoint</th><td>{esc(last.events)}</td></tr>"
                   f"<tr><th>chain head</th><td class=\"sha\">{esc(last.head)}</td></tr>"
                   f"<tr><th>Merkle root</th><td class=\"sha\">{esc(last.merkle_root)}</td></tr>"
                   "</tbody></table>")
    else:
        out.append("<p>The run has no checkpoint.</p>")
    out.append("<p>Anyone holding a copy of the run can recompute these with <code>gaps verify</code> or the "
               "ten-line check in the store's documentation.</p>")
    return out + ["</section>"]


def _rulebooks(books: tuple[UsedRulebook, ...]) -> list[str]:
    out = ['<section id="rulebooks">', "<h2>Rulebooks</h2>"]
    if not books:
        return out + ["<p>No rulebook was used.</p>", "</section>"]
    out.append("<p>The verdicts were reached with these rulebooks, each named by the sha256 of its text: "
               "<em>recorded</em> by the run, <em>given</em> for this report, or the project's "
               "<em>current</em> one.</p>")
    out.append("<table><thead><tr><th>rulebook</th><th>version</th><th>sha256</th><th>source</th>"
               "<th>used for</th></tr></thead><tbody>")
    for b in books:
        out.append(f"<tr><td>{esc(b.name)}</td><td>{esc(b.version or '—')}</td>"
                   f'<td class="sha">{esc(b.sha256)}</td><td>{esc(b.source)}</td>'
                   f"<td>{esc(', '.join(b.stages) or 'recorded by the run, not used')}</td></tr>")
    return out + ["</tbody></table>", "</section>"]


def _incident(e: ReportEntry) -> list[str]:
    r, pic, tl = e.row, e.scene, e.timeline
    n = int(e.number)
    out = [f'<article class="incident" id="report-incident-{n}">',
           f"<h2>Incident {n}: vehicle {esc(r.vehicle)}, {esc(r.action)}, "
           f'<span class="verdict-{esc(r.verdict)}">{esc(r.verdict)}</span></h2>',
           '<figure class="scene">', scene_svg(pic, n),
           f"<figcaption>{esc(_scene_caption(pic))}</figcaption>", "</figure>",
           '<figure class="timeline">', timeline_svg(tl, tl.heading_deg),
           f"<figcaption>{esc(_timeline_caption(tl))}</figcaption>", "</figure>",
           html_fragment(e.explanation, "standard"),
           "<h3>Rulebooks of this verdict</h3>",
           "<table><thead><tr><th>stage</th><th>rulebook</th><th>sha256</th><th>source</th></tr></thead><tbody>"]
    for b in e.rulebooks:
        out.append(f"<tr><td>{esc(b.stage)}</td><td>{esc(b.book.name)}</td>"
                   f'<td class="sha">{esc(b.book.sha256)}</td><td>{esc(b.book.source)}</td></tr>')
    out += ["</tbody></table>", "</article>"]
    return out


def _scene_caption(pic: Picture) -> str:
    unplaced = [v.id for v in pic.vehicles if v.x is None]
    stale = [f"{v.id} ({v.age_s:g} s before)" for v in pic.movers
             if v.x is not None and not v.present and v.age_s is not None]
    surface = ("lanes, crossings, stop lines and the yellow box as the map recorded them, "
               if pic.lanes else "")
    where = f" around junction {pic.junction}" if pic.junction is not None else ""
    text = (f"The scene at the incident, {pic.offset} from the run start, as the record holds it{where}: "
            f"{surface}vehicle {pic.vehicle} highlighted, arrows point where each vehicle was heading, labels "
            f"give speeds in mph, each lamp stands at its approach's stop line, wedges are the monitors' fields "
            f"of view. {_signals_caption(pic)}")
    text += _outside(pic)
    if unplaced:
        text += f" Not drawn (no position recorded): {', '.join(map(str, unplaced))}."
    if stale:
        text += (f" Not drawn (last position reported more than {FRESH_NS / SECOND:g} s before the incident, so "
                 f"not where they were): {', '.join(stale)}.")
    if pic.note:
        text += f" Note: {pic.note}."
    return text


def _outside(pic: Picture, most: int = OUTSIDE_NAMED) -> str:
    """The road users present but outside the zoomed picture, nearest the incident's vehicle first;
    on a busy map only the nearest `most` by name, the rest counted (the JSON report and `gaps
    scene` list every one)."""
    outside = set(out_of_view(pic))
    if not outside:
        return ""
    me = next((v for v in pic.vehicles if v.incident and v.x is not None and v.y is not None), None)
    users = [u for u in pic.movers if str(u.id) in outside]
    if me is not None:
        mx, my = _placed(me.x), _placed(me.y)
        users.sort(key=lambda u: (math.hypot(_placed(u.x) - mx, _placed(u.y) - my), str(u.id)))
    names = [str(u.id) for u in users]
    if len(names) <= most:
        return f" Present but outside the picture: {', '.join(names)}."
    return (f" Present but outside the picture, nearest first: {', '.join(names[:most])} and "
            f"{len(names) - most} more elsewhere on the map.")


def _signals_caption(pic: Picture) -> str:
    """The lamps of the junctions in view, in the legend's words, approaches of one colour
    together: "Signals at junction j1: west and east red and amber; north and south red."."""
    parts = []
    for junction in junctions_in_view(pic):
        by_colour: dict[str, list[str]] = {}
        for s in pic.signals:
            if str(s.junction) == junction:
                by_colour.setdefault(colour_word(s.colour), []).append(str(s.approach))
        if by_colour:
            shown = "; ".join(f"{join(approaches)} {word}" for word, approaches in by_colour.items())
            parts.append(f"Signals at junction {junction}: {shown}.")
        elif junction == pic.junction:
            parts.append(f"No signal reported at junction {junction}.")
    return " ".join(parts) or "No junction in view."


def _timeline_caption(tl: ActTimeline) -> str:
    before, after = (tl.window.t - tl.window.t_from) / SECOND, (tl.window.t_to - tl.window.t) / SECOND
    other = tl.other
    line = tl.to_line
    parts = [f"Vehicle {tl.window.vehicle} from {before:g} s before the incident to {after:g} s after, on one time "
             f"axis: its speed" + (f", the speed of {other.user} (whom {tl.window.vehicle} {other.how})"
                                   if other else "")]
    parts.append(f"its distance to the {line.approach} approach's line of junction {line.junction} (above "
                 "zero before the line, below it past the line)" if line else
                 "no distance to a stop line (the record shows no passage over one in this window)")
    parts.append(f"the colour each signal approach of junction {tl.window.junction or '(none found)'} showed")
    return ("; ".join(parts) + ". Between reports the record says nothing, so the lines join the reported points; "
            "the labelled lines are the incident and the moments of the passage.")


def _placed(value: float | None) -> float:
    """A coordinate of a road user out_of_view found (so placed: never None, else far away)."""
    return math.inf if value is None else value
