"""Explanations as text: the verdict first, then the proofs that support it.

The English comes from the rulebook's own templates (via `reasoner.le.templates.render`), so an
investigator reads the words the rules were written in, and every fact names its event.
"""
from __future__ import annotations

from datetime import datetime, timezone
from typing import Callable

from reasoner.engine import Rulebook
from reasoner.le.render import arg_text as le_arg_text
from reasoner.le.render import sentence_text

INDENT = "  "


def arg_text(arg) -> str:
    return le_arg_text(arg)


def sentence(data: list, rb: Rulebook) -> str:
    """The English of one node's sentence (`['has_light', 173, 'red']` → `173 has red light`)."""
    return sentence_text(data, rb.document)


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


def clock(t_ns: int) -> str:
    dt = datetime.fromtimestamp(t_ns / 1e9, tz=timezone.utc)
    return dt.strftime("%Y-%m-%d %H:%M:%S.") + f"{(t_ns // 1_000_000) % 1000:03d} UTC"


def headline(inc: dict) -> str:
    rule = f" of {inc['rule']}" if inc["rule"] else ""
    law = f" ({inc['law']})" if inc.get("law") else ""
    what = {"punishable": "a punishable violation", "mitigated": "a mitigated violation",
            "dismissed": "no violation (the potential violation was dismissed)"}[inc["verdict"]]
    return (f"Vehicle {inc['vehicle']} committed {what}{rule}{law} at {clock(inc['t'])}: "
            f"it did \"{inc['action']}\".")


def explain_incident(inc: dict, rulebooks: Callable[[str], Rulebook | None]) -> str:
    """The whole explanation of one incident, verdict first. `rulebooks` finds a rulebook by
    sha256 (Investigation.rulebook): each proof is rendered with the words of its own rulebook."""
    how = ("recorded by " + inc["monitor"] + (" and re-derived from its observation" if inc["rederived"]
                                             else ", but NOT re-derivable from its observation")
           if inc["recorded"] else f"re-derived from the observations of {inc['monitor']}, which recorded none")
    lines = [headline(inc), f"Why: {inc['why']}." if inc.get("why") else "", "", f"Potential violation, {how}:"]
    lines += _proof_lines(inc["proofs"]["potential_violation"], rulebooks, dict(inc["scenarios"]["monitor"]))
    if "verdict" in inc["proofs"]:
        vfacts = "; ".join(s for s, _ in inc["scenarios"]["validator"]) or "nothing recorded"
        lines += ["", f"Validation on the Validator Scenario ({vfacts}):"]
        lines += _proof_lines(inc["proofs"]["verdict"], rulebooks, dict(inc["scenarios"]["validator"]))
    if inc["penalty"]:
        p = inc["penalty"]
        lines += ["", f"Penalty: {p['offence']} ({p['law']}): £{p['fine_gbp']}, {p['points']} penalty points."]
    control = inc.get("control") or {}
    lines.append(f"Liable: {inc['liable']}.  In control at the time: {control.get('in_control', 'unknown')}.")
    for stage, book in inc["rulebooks"].items():
        lines.append(f"Rulebook ({stage}): {book['name']} sha256 {book['sha256'][:16]}… ({book['source']}).")
    for f in inc["findings"]:
        lines.append(f"Finding: {f['kind']}: {f.get('detail', '')}")
    return "\n".join(lines)


def _proof_lines(proofs: dict, rulebooks: Callable[[str], Rulebook | None], evidence: dict) -> list[str]:
    rb = rulebooks(proofs["rulebook"]) if proofs.get("rulebook") else None
    if rb is None:
        return ["  (no rulebook for this stage)"]
    lines: list[str] = []
    for tree in proofs["trees"]:
        lines += render_tree(tree, rb, evidence, 1)
    return lines
