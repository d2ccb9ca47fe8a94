"""Turning the rules' sentences into the English of a verdict: tenses, articles, rule names.

The rulebooks speak in the present tense and in templates ("173 has red light"); a verdict speaks
of what happened ("it entered the junction against a red light") and of what might have been ("had
173 been stopped"). The phrasing here is keyed by the sentences of DESIGN's core vocabulary (which
every producer writes), never by case; a sentence it does not know keeps the rule's own words.
"""
from __future__ import annotations

from typing import Any, Callable

from reasoner.when import clock, day  # noqa: F401  (times as the explanations write them: reasoner/when.py)

IRREGULAR = {"go": "went", "give": "gave", "take": "took", "cut": "cut", "keep": "kept", "stop": "stopped",
             "overtake": "overtook", "drive": "drove", "run": "ran", "make": "made", "leave": "left"}


def past(action: str) -> str:
    """"enter the junction" -> "entered the junction": the first word in the simple past."""
    verb, _, rest = action.partition(" ")
    low = verb.lower()
    if low in IRREGULAR:
        done = IRREGULAR[low]
    elif low.endswith("e"):
        done = verb + "d"
    elif low.endswith("y") and len(low) > 1 and low[-2] not in "aeiou":
        done = verb[:-1] + "ied"
    else:
        done = verb + "ed"
    return f"{done} {rest}".strip()


def rule_name(label: str | None) -> str:
    """"HC 176" -> "Highway Code rule 176"; any other label as written; none -> "the rules"."""
    if not label:
        return "the rules"
    if label.startswith("HC "):
        return "Highway Code rule " + label[3:]
    return label


def who(src: str, start: bool = False) -> str:
    """"monitor/m1" -> "monitor m1" ("Monitor m1" to start a sentence): a source named in prose."""
    role, _, name = str(src).partition("/")
    if not name:
        return str(src)
    return f"{role.capitalize() if start else role} {name}"


def value(v: Any) -> str:
    """A constant as a reader writes it: fire_engine -> fire engine."""
    return str(v).replace("_", " ")


def a(word: str) -> str:
    """The indefinite article for a word."""
    return "an" if word[:1].lower() in "aeiou" else "a"


def with_a(v: Any) -> str:
    w = value(v)
    return f"{a(w)} {w}"


# -- how an action was done: the conditions of the potential violation ---------------------------
# functor -> phrase for a condition that held (None: implied by the action itself, left out)
Phrase = Callable[[list, Any], str | None]

MANNER: dict[str, Phrase] = {
    "has_light": lambda x, v: f"against {with_a(x[1])} light",
    "has_a_sign": lambda x, v: f"at {with_a(x[1])} sign",
    "has_speed_of": lambda x, v: f"at {value(x[1])} mph",
    "the_speed_limit_is": lambda x, v: f"where the limit is {value(x[0])} mph",
    "is_approaching": lambda x, v: f"with {value(x[0])} approaching" if x[1] == v else None,
    "is_on_the_main_road": lambda x, v: "on the main road" if x[0] != v else None,
    "is_stopped_in_the_box_junction": lambda x, v: "and stopped in it",
    "has_crossed_the_stop_line": lambda x, v: None,
    "is_in_the_junction": lambda x, v: None,
    "is_at_a_box_junction": lambda x, v: None,
    "is_of_type": lambda x, v: None,
}
# functor -> phrase for a condition that held because the sentence did NOT
MANNER_NOT: dict[str, Phrase] = {
    "has_stopped_at_the_stop_line": lambda x, v: "without stopping at the stop line",
    "the_exit_of_the_box_junction_is_clear_for": lambda x, v: "while its exit was not clear",
    "is_stopped": lambda x, v: None,
    "has_light": lambda x, v: None,
}


def manner(data: list, vehicle: Any, negated: bool, text: str) -> str | None:
    """How a condition of the potential violation reads beside the action ("against a red light");
    a sentence the table does not know keeps the rule's words ("where 9 is at a crossroads")."""
    table = MANNER_NOT if negated else MANNER
    fn = table.get(data[0])
    if fn is None:
        return f"where {text}"
    return fn(list(data[1:]), vehicle)


# -- what might have been: counterfactual clauses --------------------------------------------------
# functor -> (had <it held>, had <it not held>), {0} {1} the arguments, {a1} "a"/"an" before {1}
HAD: dict[str, tuple[str, str]] = {
    "is_stopped": ("{0} been stopped", "{0} not been stopped"),
    "has_light": ("{0} had {a1} {1} light", "{0} not had {a1} {1} light"),
    "has_a_sign": ("{0} had {a1} {1} sign", "{0} had no {1} sign"),
    "is_of_type": ("{0} been {a1} {1}", "{0} not been {a1} {1}"),
    "is_on_an_emergency_call": ("{0} been on an emergency call", "{0} not been on an emergency call"),
    "has_crossed_the_stop_line": ("{0} crossed the stop line", "{0} not crossed the stop line"),
    "has_stopped_at_the_stop_line": ("{0} stopped at the stop line", "{0} not stopped at the stop line"),
    "is_in_the_junction": ("{0} been in the junction", "{0} not been in the junction"),
    "is_approaching": ("{0} been approaching {1}", "{0} not been approaching {1}"),
    "has_speed_of": ("{0} been doing {1} mph", "{0} not been doing {1} mph"),
    "the_speed_limit_is": ("the speed limit been {0} mph", "the speed limit not been {0} mph"),
    "would_force_to_change_speed_or_course": ("{0} forced {1} to change speed or course",
                                              "{0} not forced {1} to change speed or course"),
    "would_endanger": ("{0} endangered {1}", "{0} not endangered {1}"),
    "is_too_close_to_the_stop_line_to_stop_safely": ("{0} been too close to the stop line to stop safely",
                                                     "{0} not been too close to the stop line to stop safely"),
    "is_driving_itself": ("{0} been driving itself", "{0} not been driving itself"),
    "is_on_the_main_road": ("{0} been on the main road", "{0} not been on the main road"),
    "there_is_a_safe_gap_in_the_traffic_for": ("there been a safe gap in the traffic for {0}",
                                               "there been no safe gap in the traffic for {0}"),
    "has_stopped": ("{0} stopped", "{0} not stopped"),
}
# how the old value reads after "instead of"
INSTEAD: dict[str, Callable[[Any], str]] = {"is_of_type": with_a, "has_speed_of": value,
                                            "the_speed_limit_is": value,
                                            "has_a_sign": lambda v: f"{with_a(v)} sign"}


def had(data: list, text: str, holds: bool = True) -> str:
    """The clause after "had": "173 been stopped"; unknown sentences keep the rule's words
    ("it been recorded that 9 is at a crossroads")."""
    pattern = HAD.get(data[0])
    if pattern is None:
        return f"it been recorded that {text}" if holds else f"it not been recorded that {text}"
    args = [value(x) for x in data[1:]]
    fill = {str(i): s for i, s in enumerate(args)}
    fill.update({f"a{i}": a(s) for i, s in enumerate(args)})
    return pattern[0 if holds else 1].format(*args, **{k: v for k, v in fill.items() if k.startswith("a")})


def change_clause(kind: str, old: list, old_text: str, new: list | None = None, new_text: str = "") -> str:
    """One change as English: "had 173 been stopped", "had 173 had a green light instead of red",
    "had 253 not been on an emergency call"."""
    if kind == "add":
        return "had " + had(old, old_text)
    if kind == "remove":
        return "had " + had(old, old_text, holds=False)
    slot = next((i for i, (x, y) in enumerate(zip(old[1:], (new or [])[1:])) if x != y), 0)
    was = INSTEAD.get(old[0], value)(old[1 + slot])
    return "had " + had(new or old, new_text) + f" instead of {was}"


def join(items: list[str], last: str = "and") -> str:
    items = [i for i in items if i]
    if len(items) <= 1:
        return "".join(items)
    return ", ".join(items[:-1]) + f" {last} " + items[-1]


def gerund(action: str) -> str:
    """"enter the junction" -> "entering the junction"."""
    verb, _, rest = action.partition(" ")
    low = verb.lower()
    if low in ("stop", "cut", "run", "get", "set"):
        done = verb + verb[-1] + "ing"
    elif low.endswith("e") and not low.endswith(("ee", "ye", "oe")):
        done = verb[:-1] + "ing"
    else:
        done = verb + "ing"
    return f"{done} {rest}".strip()
