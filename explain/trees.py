"""Proof trees as indented English, at two depths, and what a tree says was decisive.

A proof tree (DESIGN "Proof trees", enriched by reasoner.engine.enrich) already carries each
step's English in the rulebook's own words, its rule label and source line, and the events of its
facts. Here the tree becomes lines an investigator reads top-down: "because" and "and" under what
held, "but" where a rule met an exception, "not recorded" where a fact was missing. At the
standard level rules that failed at their very first condition are gathered into one line (an
ambulance's proof otherwise lists every Highway Code rule that did not apply); the full level shows
every attempt.

Lines are (depth, text) pairs; the renderers only indent and escape them.
"""
from __future__ import annotations

from typing import Any, Callable, Mapping

Line = tuple[int, str]
Cite = Callable[[dict], str]        # a node -> " [E2]" (its events), or ""


def where(node: dict) -> str:
    """" [HC 176, validators.le:137]": the rule a step used, to check it against the rulebook."""
    src = node.get("source")
    if not src:
        return ""
    label = node.get("label")
    return f" [{label + ', ' if label else ''}{src['file']}:{src['line']}]"


def outline(node: dict, cite: Cite, full: bool = False, depth: int = 0, lead: str = "",
            refer: dict[str, str] | None = None, answered: dict[str, str] | None = None) -> list[Line]:
    """The lines of one tree. `lead` is the connective the parent gives this step; `refer` maps
    the text of a negated sentence explained elsewhere to where ("see 5. Why not"); `answered`
    maps a sentence no fact states that the measurements answer "no" to (the second limb's "V
    would force U ...") to the measured answer, said in its place of "not recorded"."""
    status, kids, text = node["status"], node["children"], node["text"]
    head = node["sentence"][0] if node["sentence"] else ""
    if status in ("fact", "builtin") and not kids:
        return [(depth, f"{lead}{text}{cite(node)}")]
    if status == "failed":
        return _failed(node, cite, full, depth, lead, answered)
    if head == "$not" and len(kids) == 1 and kids[0]["status"] == "failed":
        inner = kids[0]
        if refer and inner["text"] in refer:
            return [(depth, f"{lead}{text} ({refer[inner['text']]})")]
        if _simple_failure(inner):
            return [(depth, f"{lead}{text}{_short_reason(inner)}")]
        return [(depth, f"{lead}{text}, because:")] + _failed(inner, cite, full, depth + 1, "", answered)
    lines = [(depth, f"{lead}{text}{where(node)}{cite(node)}")]
    for i, kid in enumerate(kids):
        lines += outline(kid, cite, full, depth + 1, "because " if i == 0 else "and ", refer, answered)
    return lines


def _failed(node: dict, cite: Cite, full: bool, depth: int, lead: str,
            answered: dict[str, str] | None = None) -> list[Line]:
    kids, text = node["children"], node["text"]
    head = node["sentence"][0] if node["sentence"] else ""
    if node.get("truncated"):
        return [(depth, f"{lead}{text}: not explored further")]
    if head == "$not" and len(kids) == 1 and kids[0]["status"] != "failed":
        # the exception held: the negation fails because its sentence is true
        return outline(kids[0], cite, full, depth, f"{lead}but ", answered=answered)
    if node.get("rule") is not None:            # one rule's attempt
        lines = [(depth, f"{lead}the rule{where(node)} does not apply:")]
        for i, kid in enumerate(kids):
            # a broken negation says "but" itself ("but 173 must not enter the junction")
            connective = "but " if i and kid["status"] == "failed" and not _is_broken_negation(kid) else ""
            lines += outline(kid, cite, full, depth + 1, connective, answered=answered)
        return lines
    if not kids:
        if answered and text in answered:
            return [(depth, f"{lead}{text}: not so, by the measurements: {answered[text]}")]
        return [(depth, f"{lead}{text}: not recorded")]
    if head in ("$or", "$and"):
        lines = [(depth, f"{lead}{text} does not hold:")]
        for kid in kids:
            lines += outline(kid, cite, full, depth + 1, answered=answered)
        return lines
    if _simple_failure(node):
        return [(depth, f"{lead}{text} does not hold{_short_reason(node)}")]
    lines = [(depth, f"{lead}{text} does not hold:")]
    early = [k for k in kids if _fails_first(k)] if not full else []
    for kid in kids:
        if kid not in early:
            lines += outline(kid, cite, full, depth + 1, answered=answered)
    if early:
        lines.append((depth + 1, f"{_count(len(early), len(early) < len(kids))} on its first "
                                 f"condition: {_first_conditions(early)}"))
    return lines


def _is_broken_negation(node: dict) -> bool:
    return node["sentence"][:1] == ["$not"] and node["status"] == "failed"


def _fails_first(attempt: dict) -> bool:
    """A rule attempt that failed on its first condition."""
    kids = attempt["children"]
    return (attempt.get("rule") is not None and len(kids) == 1 and kids[0]["status"] == "failed"
            and not _is_broken_negation(kids[0]))


def _simple_failure(node: dict) -> bool:
    """A failed sentence whose every rule failed at its first condition, a sentence no rule
    concludes (so "not recorded" is the whole reason): one line says it."""
    kids = node["children"]
    return node["status"] == "failed" and bool(kids) and all(
        _fails_first(k) and not k["children"][0]["children"] for k in kids)


def _short_reason(node: dict) -> str:
    needs = [k["children"][0]["text"] + where(k) for k in node["children"]]
    if len(needs) == 1:
        return f": its rule needs {needs[0]}, which is not recorded"
    return f": every rule for it needs one of {'; '.join(needs)}; none is recorded"


def _first_conditions(attempts: list[dict]) -> str:
    return "; ".join(f"{k['children'][0]['text']}{where(k)}" for k in attempts)


def _count(n: int, others: bool = True) -> str:
    """"1 other rule does not apply, failing", "3 other rules do not apply, each failing"."""
    if not others:
        return "its rule does not apply, failing" if n == 1 else f"none of its {n} rules applies, each failing"
    return "1 other rule does not apply, failing" if n == 1 else f"{n} other rules do not apply, each failing"


# -- what a tree says was decisive ---------------------------------------------------------------

def conditions(node: dict) -> list[tuple[list, bool, str]]:
    """The sentences a proved rule step rests on, as (data, negated, text): the facts and the
    negations that held (a "not stopped" holds because "stopped" failed)."""
    out = []
    for kid in node["children"]:
        if kid["sentence"][:1] == ["$not"]:
            for cond in kid["sentence"][1]:
                if isinstance(cond, list) and not str(cond[0]).startswith("$"):
                    inner = next((k for k in kid["children"]), None)
                    out.append((cond, True, inner["text"] if inner else kid["text"]))
        elif kid["status"] in ("fact", "proved"):       # a builtin (38 > 30) restates the facts
            out.append((kid["sentence"], False, kid["text"]))
    return out


def exceptions(tree: dict, functor: str) -> list[dict]:
    """The sentences that kept rules concluding `functor` from applying: in each attempt that got
    past its first condition, the negated sentence that held (an ambulance on call "is used for an
    emergency purpose"). Nodes, so that callers keep their text and proof."""
    found: list[dict] = []
    for node in walk(tree):
        if node["status"] != "failed" or node.get("rule") is None or node["sentence"][:1] != [functor]:
            continue
        kids = node["children"]
        if len(kids) < 2 or not kids[-1]["sentence"][:1] == ["$not"] or kids[-1]["status"] != "failed":
            continue
        held = [k for k in kids[-1]["children"] if k["status"] != "failed"]
        for k in held:
            if all(k["text"] != f["text"] for f in found):
                found.append(k)
    return found


def first(tree: dict, test: Callable[[dict], bool]) -> dict | None:
    return next((n for n in walk(tree) if test(n)), None)


def walk(tree: Mapping[str, Any]):
    stack = [tree]
    while stack:
        node = stack.pop(0)
        yield node
        stack[:0] = node.get("children", [])


def events_of(tree: Mapping[str, Any]) -> list[dict]:
    return [ref for node in walk(tree) for ref in node.get("evidence", [])]


def facts_used(tree: dict | None) -> set[str]:
    """The recorded sentences a proof rests on: the text of its fact leaves that held (a
    negation's failed inside is what was *not* recorded, and is left out)."""
    if tree is None:
        return set()
    found: set[str] = set()
    todo = [tree]
    while todo:
        node = todo.pop()
        if node["status"] == "fact":
            found.add(node["text"])
        if node["status"] != "failed":
            todo.extend(node["children"])
    return found
