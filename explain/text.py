"""Proof trees as plain indented text (`gaps rules query --explain`), and `explain_incident`, the
text explanation of one incident that `gaps incidents` and `gaps demo` print.

The English comes from the rulebook's own templates (via `reasoner.wording`), so an
investigator reads the words the rules were written in, and every fact names its event.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

from reasoner.when import date_clock
from reasoner.wording import Rulebook, arg_text, sentence_text


if TYPE_CHECKING:
    from reasoner import Case
    from reasoner.model import Incident

INDENT = "  "


def sentence(data: list, rb: Rulebook) -> str:
    """The English of one node's sentence (`['has_light', 173, 'red']` → `173 has red light`)."""
    return sentence_text(data, rb)


def where(rule_id, rb: Rulebook, with_law: bool = True) -> str:
    """` [HC 176 (its law), file:line]`: the citation an investigator checks the step against."""
    if rule_id is None:
        return ""
    rule = rb.rule(rule_id)
    label = rule.label or ""
    if label and with_law and rule.law:
        label += f" ({rule.law})"
    return f" [{label + ', ' if label else ''}{rb.name}:{rule.line}]"


def render_tree(node: dict, rb: Rulebook, evidence: dict[str, dict] | None = None, depth: int = 0) -> list[str]:
    """Lines of an indented English proof: `because`, `and`, `it is not the case that`.

    With `evidence` (sentence -> event ref) each fact cites the event it came from."""
    pad = INDENT * depth
    text = sentence(node["sentence"], rb)
    status, kids = node["status"], node["children"]
    if status == "fact" and not kids:
        return [f"{pad}{text}{cite(evidence.get(text)) if evidence is not None else ''}"
                f"{where(node['rule'], rb)}"]
    if status == "failed":
        return _failed(node, text, rb, evidence, depth)
    lines = [f"{pad}{text}{where(node['rule'], rb)}"]
    for i, kid in enumerate(kids):
        joiner = "because " if i == 0 else "and "
        if node["sentence"][0] == "$not":
            joiner = "because "
        sub = render_tree(kid, rb, evidence, depth + 1)
        sub[0] = f"{INDENT * (depth + 1)}{joiner}{sub[0].lstrip()}"
        lines += sub
    return lines


def _failed(node, text, rb, evidence, depth) -> list[str]:
    pad = INDENT * depth
    kids = node["children"]
    if node["rule"] is not None:       # one rule's attempt: the conditions up to the one that failed
        lines = [f"{pad}the rule{where(node['rule'], rb, with_law=False)} does not apply:"]
        for kid in kids:
            lines += render_tree(kid, rb, evidence, depth + 1)
        return lines
    head = node["sentence"][0]
    if node.get("truncated"):
        return [f"{pad}{text} does not hold (not explored further)"]
    if head == "$not":
        lines = [f"{pad}{text} does not hold, because:"]
    elif head == "$or":
        lines = [f"{pad}none of these holds: {text}"]
    elif head == "$and":
        lines = [f"{pad}{text} does not hold:"]
    elif kids:
        lines = [f"{pad}{text} does not hold: no rule for it applies"]
    else:
        return [f"{pad}{text} is not established by any fact or rule"]
    for kid in kids:
        lines += render_tree(kid, rb, evidence, depth + 1)
    return lines


def cite(ref: dict | None) -> str:
    if not ref:
        return " (recorded potential violation)"
    return f" (fact: {ref['src']} #{ref['seq']}, {ref['kind']}, {clock(ref['t'])})"


clock = date_clock     # 2024-11-21 08:00:10.000 UTC (reasoner/when.py)


def explain_incident(case: Case, inc: Incident, level: str = "standard") -> str:
    """The whole explanation of one incident as text, verdict first: the case that judged it
    answers what the explanation asks (reasoner.Case.explanation), explanation_doc words it and
    explain.explanation_formats draws it; the evidence gets chain positions from the case's store."""
    from .explanation_doc import document
    from .explanation_formats import to_text
    return to_text(document(inc, case.explanation(inc), case.store), level).rstrip("\n")
