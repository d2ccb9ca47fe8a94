"""An explanation document laid out as blocks, at a verbosity level, for any output format.

Levels: `summary` (the verdict sentence and a plain-language paragraph), `standard` (plus each
stage's reasoning with rules that did not apply gathered up, counterfactuals, findings and the
evidence table) and `full` (every step of every proof, and the rulebooks by sha256). Text, Markdown
and HTML (explain/explanation_formats.py) draw the same blocks, so they say the same thing.

A block is a tuple: ("title", text), ("heading", text), ("para", text), ("list", [text]),
("tree", [(depth, text)]), ("table", [header], [[cell]]).
"""
from __future__ import annotations

import re

from reasoner.verdicts import Verdict

from . import phrases as ph
from .trees import outline

LEVELS = ("summary", "standard", "full")
Block = tuple


def cite(node: dict) -> str:
    ids = node.get("cites") or []
    return f" [{', '.join(ids)}]" if ids else ""


def blocks(doc: dict, level: str = "standard") -> list[Block]:
    if level not in LEVELS:
        raise ValueError(f"level is one of {', '.join(LEVELS)}, not {level!r}")
    inc = doc["incident"]
    out: list[Block] = [("title", doc["verdict"]),
                        ("para", f"Incident {inc['id']} of run {inc['run']}, {inc['time']} on {inc['day']}; "
                                 f"verdict: {inc['verdict']}.")]
    out.append(("heading", "In short"))
    out.append(("para", " ".join(doc["summary"])))
    if level == "summary":
        return out
    full = level == "full"
    out += _potential_violation(doc, full)
    out += _validation(doc, full)
    out += _penalty(doc)
    out += _liability(doc, full)
    out += _why_not(doc, full)
    out += _counterfactuals(doc)
    out += _findings(doc)
    out += _evidence(doc)
    if full:
        out += _rulebooks(doc)
    return _renumbered(out)


_NUMBERED = re.compile(r"(\d+)\. ")
_SEE = re.compile(r"\bsee (\d+)\. ")


def _renumbered(out: list[Block]) -> list[Block]:
    """The sections numbered in the order shown: a section left out (no "Why not" for a verdict
    that needs none) leaves no hole (issue 39: sections 1-4, 6-8), and a "see 5. Why not" follows
    its section's number."""
    numbers: dict[str, str] = {}
    for block in out:
        if block[0] == "heading" and (m := _NUMBERED.match(block[1])):
            numbers[m.group(1)] = str(len(numbers) + 1)

    def fix(value: object) -> object:
        if isinstance(value, str):
            return _SEE.sub(lambda m: f"see {numbers.get(m.group(1), m.group(1))}. ", value)
        if isinstance(value, list):
            return [fix(v) for v in value]
        if isinstance(value, tuple):
            return tuple(fix(v) for v in value)
        return value

    renumbered: list[Block] = []
    for block in out:
        if block[0] == "heading" and (m := _NUMBERED.match(block[1])):
            block = ("heading", f"{numbers[m.group(1)]}. {block[1][m.end():]}")
        renumbered.append(fix(block))      # type: ignore[arg-type]
    return renumbered


def _tree(tree: dict | None, full: bool, refer: dict | None = None,
          answered: dict[str, str] | None = None) -> list[Block]:
    return [("tree", outline(tree, cite, full, refer=refer, answered=answered))] if tree else []


def _asked(doc: dict) -> dict[str, str]:
    """Sentences the why-not section explains: the other sections point there instead."""
    return {w["question"]: "see 5. Why not" for w in doc["why_not"] if not w.get("error")}


def _facts(facts: list[dict]) -> list[str]:
    return [f"{f['fact']}" + (" (measured)" if f.get("measured") else "") +
            (f" [{f['evidence']}]" if f.get("evidence") else "") for f in facts]


def _measured(doc: dict) -> list[Block]:
    """The facts the history derived, with how, and the margin of the act."""
    m = doc.get("measured") or {}
    out: list[Block] = []
    if m.get("facts"):
        out.append(("para", "The facts marked (measured) were derived from the record's measurements, beside what "
                            "was stated; a stated fact they contradict is a finding, not replaced:"))
        out.append(("list", [f"{f['fact']}: {f['method']}" + (f" (uncertain: {f['uncertain']})" if f.get("uncertain")
                                                               else "") +
                             (f" [{', '.join(f['evidence'])}]" if f.get("evidence") else "") for f in m["facts"]]))
    if m.get("margin"):
        mg = m["margin"]
        out.append(("para", f"Margin of the act: {mg['text']}" + (f"; {mg['method']}" if mg.get("method") else "") +
                            (f" [{', '.join(mg['evidence'])}]." if mg.get("evidence") else ".")))
    if m.get("second_limb"):
        near = [u for u in m["second_limb"] if _in_question(u)]
        rest = [u["user"] for u in m["second_limb"] if not _in_question(u)]
        out.append(("para", "The second limb (TSRGD 2016 Sch 9 Pt 7 para 1; Sch 14 Pt 1 para 5(5)), by the "
                            "measurements: the road users about the act that it neither forced to change speed or "
                            "course nor endangered, with their figures and why:"))
        out.append(("list", [f"{u['words']}" + (f" [{', '.join(u['evidence'])}]" if u.get("evidence") else "")
                             for u in near] + ([f"and {', '.join(rest)}: paths that never met its, or no braking at 2 "
                                                "m/s² and no stop (each in the full JSON, reasoner/second_limb.py)"]
                                               if rest else [])))
    return out


def _in_question(u: dict) -> bool:
    """A road user the second limb could have been about: its path met the vehicle's (a PET), or
    it braked at 2 m/s² or more, or something of its own or another road user explains what it did."""
    return u.get("pet_s") is not None or (u.get("decel_mps2") or 0.0) >= 2.0 or \
        u["reason"] not in ("no change", "paths apart", "walking clear")


def _answered(doc: dict) -> dict[str, str]:
    """The second limb's sentences the measurements answer "no" to (reasoner/second_limb.py), each
    with the road user's figures and the reason: a proof's "V would force U ...: not recorded" says
    instead why U was not forced. A sentence that names no one ("a road user") is answered by
    them all."""
    limb = (doc.get("measured") or {}).get("second_limb") or []
    out = {text: u["words"] for u in limb for text in u.get("sentences", ())}
    if limb:
        v = doc["incident"]["vehicle"]
        every = "none of the road users about the act was (see 1., the second limb): " + \
            "; ".join(f"{u['user']} ({u['reason']})" for u in limb)
        for who in ("a road user", "a person", "a vehicle"):
            out.setdefault(f"{v} would force {who} to change speed or course", every)
            out.setdefault(f"{v} would endanger {who}", every)
    return out


def _potential_violation(doc: dict, full: bool) -> list[Block]:
    pv = doc["potential_violation"]
    rule = doc["incident"]["rule"]
    out: list[Block] = [("heading", "1. The potential violation"),
                        ("para", f"The potential violation of “{doc['incident']['action']}” was {pv['how']}. "
                                 + ("The record shows:" if pv.get("found_in") == "own-record"
                                    else "The monitor observed:"))]
    out.append(("list", _facts(pv["observed"]) or ["nothing about the vehicle"]))
    out += _measured(doc)
    if pv["tree"] and pv["tree"]["status"] == "failed" and pv["tree"]["text"] in _asked(doc):
        out.append(("para", f"The monitor rules ({pv['rulebook']}) do not derive it from that observation "
                            "(see 5. Why not)."))
    elif pv["tree"]:
        if pv["tree"]["status"] == "failed":
            lead = f"The monitor rules ({pv['rulebook']}) do not derive it from that observation:"
        else:
            lead = (f"By {ph.rule_name(rule)}" + (f" ({pv['law']})" if pv.get("law") else "") +
                    f", as the monitor rules ({pv['rulebook']}) state it, that is a potential violation:")
        out += [("para", lead)] + _tree(pv["tree"], full)
    return out


def _validation(doc: dict, full: bool) -> list[Block]:
    val = doc["validation"]
    if val is None:
        return [("heading", "2. Validation"),
                ("para", "Not reached: without a potential violation there is nothing to validate.")]
    v, action = doc["incident"]["vehicle"], doc["incident"]["action"]
    basis = ("the vehicle's own facts, with what the monitor witnessed in place of the vehicle's"
             if val["judged_on"] == "vehicle scenario" else
             "what the monitors recorded (the vehicle recorded no perception) and its spawn")
    out: list[Block] = [("heading", "2. Validation"),
                        ("para", f"The Validator Scenario ({basis}):"), ("list", _facts(val["scenario"]))]
    d = val.get("decision")
    if d:
        answer = {True: "yes", False: "no"}.get(d.get("permitted"), "not recorded")
        went = {True: "it went ahead", False: "it did not go ahead"}.get(d.get("proceeds"), "")
        out.append(("para", f"{v}'s own decision" + (f" [{d['evidence']}]" if d.get("evidence") else "") +
                    f": goal “{d.get('goal')}”, its rulebook's answer: {answer}" + (f"; {went}." if went else ".")))
    lawful = ", ".join(f"“{a}”" for a in val["lawful"]) or "none"
    unlawful = ", ".join(f"“{a}”" for a in val["not_lawful"]) or "none"
    verdict = doc["incident"]["verdict"]
    among = {Verdict.PUNISHABLE: f"“{action}” is not among the lawful actions, so the violation is punishable.",
             Verdict.MITIGATED: f"“{action}” is among the lawful actions, so the violation is mitigated.",
             Verdict.DISMISSED: "The validator rules establish neither a punishable nor a mitigated violation."}[verdict]
    out.append(("para", f"Of the actions the rules ({val['rulebook']}) speak of, these were lawful for {v} there: "
                        f"{lawful}; not lawful: {unlawful}. {among}"))
    if val["tree"]:
        out += [("para", "Why, in the rules' own words:")] + _tree(val["tree"], full, _asked(doc))
    return out


def _penalty(doc: dict) -> list[Block]:
    inc = doc["incident"]
    out: list[Block] = [("heading", "3. Penalty and the law")]
    rule = f"{ph.rule_name(inc['rule'])}" + (f" ({inc['law']})" if inc.get("law") else "")
    if not inc["rule"]:
        return out + [("para", f"No rule was found broken and no penalty applies: the potential violation was "
                               f"{inc['verdict']}.")]
    if doc["penalty"]:
        p = doc["penalty"]
        out.append(("para", f"Rule: {rule}. Offence: {p['text']}."))
        if p.get("offences"):
            out.append(("list", [f"{o['offence']} ({o.get('law')}): £{o['fine_gbp']}, {o['points']} points"
                                 for o in p["offences"]]))
    elif inc["verdict"] == Verdict.PUNISHABLE:
        out.append(("para", f"Rule: {rule}. No penalty rule applies to this violation."))
    else:
        out.append(("para", f"Rule: {rule}. No penalty: the violation is {inc['verdict']}."))
    return out


def _liability(doc: dict, full: bool) -> list[Block]:
    lia = doc["liability"]
    out: list[Block] = [("heading", "4. Liability")]
    if doc["incident"]["verdict"] != Verdict.PUNISHABLE:
        return out + [("para", f"Nobody is liable: the violation is {doc['incident']['verdict']}. "
                               f"At the time {lia['in_control_text']}.")]
    parties = ph.join(lia["parties"]) or lia["liable"]
    text = f"Liable: the {lia['liable']}. At the time {lia['in_control_text']}."
    if len(lia["parties"]) > 1:
        text += f" Answerable parties: {parties}."
    out.append(("para", text))
    if lia["tree"]:
        out += [("para", "Why, in the liability rules' words:")] + _tree(lia["tree"], full)
    return out


def _why_not(doc: dict, full: bool) -> list[Block]:
    if not doc["why_not"]:
        return []
    out: list[Block] = [("heading", "5. Why not")]
    for w in doc["why_not"]:
        if w.get("error"):
            out.append(("para", f"“{w['question']}”: {w['error']}"))
            continue
        holds = "holds" if w["holds"] else "does not hold"
        out.append(("para", f"“{w['question']}” {holds} on the {w.get('on', 'scenario')} ({w.get('rulebook')}):"))
        for t in w["trees"]:
            out += _tree(t, full, answered=_answered(doc))
    return out


def _counterfactuals(doc: dict) -> list[Block]:
    cf = doc.get("counterfactuals")
    if not cf:
        return []
    v, action = doc["incident"]["vehicle"], doc["incident"]["action"]
    out: list[Block] = [("heading", "6. What would have changed the verdict")]
    if Verdict.PUNISHABLE in cf:
        items = [f"{c['text']} [{c['kind']}]" for c in cf[Verdict.PUNISHABLE]]
        out.append(("para", "The smallest changes to the recorded facts that would have made it punishable:"))
        return out + [("list", items or ["none found within one change"])]
    lawful = f"{ph.gerund(action)} would have been lawful"
    gone = "there would have been no potential violation"
    seen: dict[str, list[str]] = {}
    kinds: dict[str, str] = {}
    for group, consequence in (("lawful", lawful), ("no_potential_violation", gone)):
        for c in cf.get(group, []):
            seen.setdefault(c["text"], []).append(consequence)
            kinds[c["text"]] = c["kind"]
    out.append(("para", "The smallest changes to the recorded facts that would have avoided a punishable "
                        "violation, by who could have made them:"))
    for kind, title in (("controlled", f"Within {v}'s control (its own driving)"),
                        ("circumstance", f"Circumstances (the signals, signs, {v}'s type and call, other road users)"),
                        ("mixed", "Both together")):
        items = [f"{text}: {' and '.join(cons)}" for text, cons in seen.items() if kinds[text] == kind]
        if items or kind != "mixed":
            out += [("para", title + ":"), ("list", items or ["none found within two changes"])]
    return out


def _findings(doc: dict) -> list[Block]:
    if not doc["findings"]:
        return [("heading", "7. Findings"), ("para", "None: no perception or decision fault, no monitor "
                                                     "disagreement, no contradiction, no missing evidence, no unknown fact.")]
    items = [f"{f['kind']}: {f.get('detail', '')}" + (f" [{', '.join(f['evidence'])}]" if f.get("evidence") else "")
             for f in doc["findings"]]
    return [("heading", "7. Findings"), ("list", items)]


def _evidence(doc: dict) -> list[Block]:
    ev = doc["evidence"]
    chain = ev["chain"]
    status = ("Verified: " if chain["verified"] else "NOT VERIFIED: " if chain["checked"] else "Not checked: ")
    rows = []
    for r in ev["events"]:
        pos = "" if r["chain_pos"] is None else str(r["chain_pos"])
        if "vouched" in r and not r["vouched"]:
            pos += " (not vouched for)"
        rows.append([r["id"], r["time"], r["src"], str(r["seq"]), r["kind"], pos, "; ".join(r["used_for"])])
    return [("heading", "8. Evidence"), ("para", f"{status}{chain['text']}."),
            ("table", ["id", "time", "source", "seq", "kind", "chain position", "used for"], rows),
            ("para", f"All events are of run {doc['incident']['run']}.")]


def _rulebooks(doc: dict) -> list[Block]:
    rows = [[stage, b.get("name", ""), b.get("sha256", ""), b.get("source", "")]
            for stage, b in (doc.get("rulebooks") or {}).items()]
    return [("heading", "9. Rulebooks"), ("table", ["stage", "rulebook", "sha256", "source"], rows)]
