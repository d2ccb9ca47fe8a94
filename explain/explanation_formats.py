"""An explanation in text, Markdown, HTML or JSON.

The document holds strings that producers wrote (facts, sources, actions); none of them may steer
the output. Text escapes every non-printable character (a terminal is told nothing), Markdown
escapes its markup characters and angle brackets, HTML escapes everything. `html_fragment` is a
<section> for a report to embed (`gaps report` reuses it); `html_page` wraps it as a document.
"""
from __future__ import annotations

import html
import json
import re
import textwrap

from .layout import blocks

FORMATS = ("text", "md", "html", "json")
WIDTH = 100


def render(doc: dict, fmt: str = "text", level: str = "standard") -> str:
    if fmt == "text":
        return to_text(doc, level)
    if fmt == "md":
        return to_markdown(doc, level)
    if fmt == "html":
        return html_page(doc, level)
    if fmt == "json":
        return to_json(doc)
    raise ValueError(f"format is one of {', '.join(FORMATS)}, not {fmt!r}")


# -- text ----------------------------------------------------------------------------------------

def safe(text: object) -> str:
    """Printable text: backslashes doubled, control and format characters as escapes."""
    return "".join("\\\\" if ch == "\\" else ch if ch.isprintable() else ch.encode("unicode_escape").decode("ascii")
                   for ch in str(text))


def to_text(doc: dict, level: str = "standard") -> str:
    out: list[str] = []
    for block in blocks(doc, level):
        kind = block[0]
        if kind == "title":
            out += textwrap.wrap(safe(block[1]), WIDTH) + [""]
        elif kind == "heading":
            out += ["", safe(block[1]), "-" * len(safe(block[1]))]
        elif kind == "para":
            out += textwrap.wrap(safe(block[1]), WIDTH, break_on_hyphens=False)
        elif kind == "list":
            for item in block[1]:
                out += textwrap.wrap(safe(item), WIDTH, initial_indent="  - ", subsequent_indent="    ",
                                     break_on_hyphens=False)
        elif kind == "tree":
            out += ["  " + "  " * depth + safe(text) for depth, text in block[1]]
        elif kind == "table":
            out += _text_table(block[1], block[2])
    return "\n".join(out).rstrip() + "\n"


def _text_table(header: list[str], rows: list[list[str]]) -> list[str]:
    cells = [[safe(c) for c in header]] + [[safe(c) for c in r] for r in rows]
    widths = [max(len(r[i]) for r in cells) for i in range(len(header) - 1)]
    lines = []
    for n, r in enumerate(cells):
        lines.append("  " + "  ".join(c.ljust(w) for c, w in zip(r, widths)) + "  " + r[-1])
        if n == 0:
            lines.append("  " + "  ".join("-" * w for w in widths) + "  " + "-" * len(r[-1]))
    return lines


# -- Markdown ------------------------------------------------------------------------------------

_MD_SPECIAL = re.compile(r"([\\`*_{}\[\]<>()#+!|~])")


def md(text: str) -> str:
    """Markdown-inert text: markup characters escaped, angle brackets as entities."""
    return _MD_SPECIAL.sub(r"\\\1", safe(text)).replace("\\<", "&lt;").replace("\\>", "&gt;")


def to_markdown(doc: dict, level: str = "standard") -> str:
    out: list[str] = []
    for block in blocks(doc, level):
        kind = block[0]
        if kind == "title":
            out += [f"# {md(block[1])}", ""]
        elif kind == "heading":
            out += ["", f"## {md(block[1])}", ""]
        elif kind == "para":
            out += [md(block[1]), ""]
        elif kind == "list":
            out += [f"- {md(item)}" for item in block[1]] + [""]
        elif kind == "tree":
            out += [f"{'  ' * depth}- {md(text)}" for depth, text in block[1]] + [""]
        elif kind == "table":
            out.append("| " + " | ".join(md(h) for h in block[1]) + " |")
            out.append("|" + "---|" * len(block[1]))
            out += ["| " + " | ".join(md(c) for c in row) + " |" for row in block[2]]
            out.append("")
    return "\n".join(out).rstrip() + "\n"


# -- HTML ----------------------------------------------------------------------------------------

def esc(text: object) -> str:
    """HTML-inert text: markup escaped, control characters shown as escapes (as in text)."""
    return html.escape(safe(text), quote=True)


def html_fragment(doc: dict, level: str = "standard") -> str:
    """A <section> of the explanation, every recorded string escaped."""
    verdict = esc(doc["incident"]["verdict"])
    out = [f'<section class="gaps-explanation verdict-{verdict}" id="incident-{esc(doc["incident"]["id"])}">']
    for block in blocks(doc, level):
        kind = block[0]
        if kind == "title":
            out.append(f"<h2>{esc(block[1])}</h2>")
        elif kind == "heading":
            out.append(f"<h3>{esc(block[1])}</h3>")
        elif kind == "para":
            out.append(f"<p>{esc(block[1])}</p>")
        elif kind == "list":
            out.append("<ul>" + "".join(f"<li>{esc(i)}</li>" for i in block[1]) + "</ul>")
        elif kind == "tree":
            out.append(_html_tree(block[1]))
        elif kind == "table":
            head = "".join(f"<th>{esc(h)}</th>" for h in block[1])
            body = "".join("<tr>" + "".join(f"<td>{esc(c)}</td>" for c in row) + "</tr>" for row in block[2])
            out.append(f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>")
    out.append("</section>")
    return "\n".join(out) + "\n"


def _html_tree(lines: list[tuple[int, str]]) -> str:
    """Nested <ul> from (depth, text) lines."""
    out, depth = ['<ul class="proof">'], 0
    for i, (d, text) in enumerate(lines):
        while depth < d:
            out.append("<ul>")
            depth += 1
        while depth > d:
            out.append("</li></ul>")
            depth -= 1
        if i and not out[-1].endswith(("<ul>", '<ul class="proof">')):
            out.append("</li>")
        out.append(f"<li>{esc(text)}")
    while depth > 0:
        out.append("</li></ul>")
        depth -= 1
    out.append("</li></ul>")
    return "".join(out)


STYLE = """body{font-family:system-ui,sans-serif;max-width:60rem;margin:2rem auto;padding:0 1rem;line-height:1.45}
h2{font-size:1.3rem}.verdict-punishable h2{color:#a40000}.verdict-mitigated h2{color:#7a5b00}
ul.proof,ul.proof ul{list-style:none;padding-left:1.2rem}table{border-collapse:collapse;font-size:.9rem}
td,th{border:1px solid #ccc;padding:.2rem .4rem;text-align:left;vertical-align:top}"""


def html_page(doc: dict, level: str = "standard") -> str:
    title = esc(f"Incident {doc['incident']['id']} of run {doc['incident']['run']}")
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{title}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n"
            f"{html_fragment(doc, level)}</body>\n</html>\n")


# -- JSON ----------------------------------------------------------------------------------------

def to_json(doc: dict) -> str:
    return json.dumps(doc, indent=2, ensure_ascii=False, default=str) + "\n"
