"""Turning the rules' sentences into the English of a verdict: tenses, articles, rule names.

The rulebooks speak in the present tense and in templates ("173 has red light"); a verdict speaks
of what happened ("it entered the junction against a red light") and of what might have been ("had
173 been stopped"). What might have been is the rulebook's own sentence put in the past perfect by
grammar, reading the verb off its template, so a sentence of any rulebook reads without a table
entry. The few words no template holds (an article, a unit, a preposition beside the action) are
kept by hand, keyed by the sentences of reasoner/vocabulary.py, never by case; a sentence the
grammar cannot place keeps the rule's own words.
"""
from __future__ import annotations

from typing import Any, Callable, Iterator

from reasoner import vocabulary as vocab
from reasoner.verdicts import rule_number
from reasoner.vocabulary import Sentence
from reasoner.when import clock, day  # noqa: F401  (times as the explanations write them: reasoner/when.py)
from reasoner.wording import Shape, arg_text, shape

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


def margin_text(m: Any) -> str:
    """A reasoner.model.Margin in words: "seconds after red the stop line was crossed: 1.4 s
    (speed at the line 22.5 mph)", with what the record leaves open."""
    figures = "; ".join(f"{q} {v:g} {u}" for q, v, u in m.figures)
    bound = f"{m.bound} " if m.bound else ""
    spread = f" ± {m.uncertainty:g} {m.unit}" if m.uncertainty is not None else ""
    text = f"{m.quantity}: {bound}{m.value:g} {m.unit}{spread}" + (f" ({figures})" if figures else "")
    text += f" [not proven: {m.unproven}]" if m.unproven else ""
    return text + (f" [uncertain: {m.uncertain}]" if m.uncertain else "")


def rule_name(label: str | None) -> str:
    """"HC 176" -> "Highway Code rule 176"; any other label as written; none -> "the rules"."""
    if not label:
        return "the rules"
    number = rule_number(label)
    return label if number is None else "Highway Code rule " + number


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


# -- the past perfect of a rulebook's sentence ------------------------------------------------------
# A template is words and slots ("*a vehicle* has *a colour* light"); its verb is the word after a
# leading slot, or a verb among its leading words ("there is ...", "the speed limit is *a number*").
# Read that way, "had" puts any rulebook's sentence in the past: is -> been, has + participle ->
# the participle, has -> had, would + verb -> the participle. A template reads as a Shape
# (reasoner.wording): its words in order, and for each slot the index of its argument (int).

BE = {"is", "are", "was", "were"}
HAVE = {"has", "have"}
MODAL = {"would", "will"}
PARTICIPLES = {"be": "been", "go": "gone", "give": "given", "take": "taken", "drive": "driven",
               "overtake": "overtaken", "ride": "ridden", "see": "seen", "do": "done", "get": "got",
               "run": "run", "cut": "cut", "put": "put", "set": "set", "let": "let", "hit": "hit",
               "keep": "kept", "make": "made", "leave": "left", "stop": "stopped", "come": "come",
               "become": "become", "hold": "held", "find": "found", "lose": "lost", "meet": "met",
               "pay": "paid", "say": "said", "send": "sent", "stand": "stood", "show": "shown",
               "fall": "fallen", "break": "broken", "choose": "chosen", "begin": "begun",
               "have": "had", "bring": "brought", "catch": "caught", "know": "known"}
_IRREGULAR_DONE = set(PARTICIPLES.values())


def participle(verb: str) -> str:
    """"endanger" -> "endangered", "drive" -> "driven": the past participle of a bare verb."""
    low = verb.lower()
    if low in PARTICIPLES:
        return PARTICIPLES[low]
    return past(verb)


def is_participle(word: str) -> bool:
    """"crossed", "been" are; "speed" (has speed of) and "a" (has a stop sign) are not."""
    low = word.lower()
    return low in _IRREGULAR_DONE or (len(low) > 3 and low.endswith("ed") and not low.endswith("eed"))


def layouts(data: list, text: str) -> Iterator[Shape]:
    """The shapes of the templates `text` could be rendered from (reasoner.wording.sentence_text):
    the functor gives the template's words, the arguments fill its slots, and where each sits is
    read off the text. More than one only where a value is also a word of the template ("is is
    stopped"); none when the text is not words and values joined by spaces (a glued or a built-in
    sentence)."""
    if not data or not isinstance(data[0], str) or data[0].startswith("$") or not text:
        return
    words = data[0].split("_")
    args = [arg_text(x) for x in data[1:]]

    def at(pos: int, piece: str) -> int | None:
        end = pos + len(piece)
        if piece and text.startswith(piece, pos) and (end == len(text) or text[end] == " "):
            return end + 1
        return None

    def fit(pos: int, w: int, k: int) -> Iterator[Shape]:
        if pos >= len(text):
            if w == len(words) and k == len(args):
                yield []
            return
        if w < len(words) and (nxt := at(pos, words[w])) is not None:
            yield from ([words[w], *rest] for rest in fit(nxt, w + 1, k))
        if k < len(args) and (nxt := at(pos, args[k])) is not None:
            yield from ([k, *rest] for rest in fit(nxt, w, k + 1))

    yield from fit(0, 0, 0)


def layout(data: list, text: str) -> Shape | None:
    """The first shape `text` fits (layouts), or None."""
    return next(layouts(data, text), None)


def _verb_at(shape: Shape) -> int | None:
    """Where the template's verb is: after a leading slot, or among the words before its first slot."""
    if len(shape) < 2:
        return None
    verbs = BE | HAVE | MODAL
    if isinstance(shape[0], int):
        return 1 if isinstance(shape[1], str) and shape[1].lower() in verbs else None
    for i, part in enumerate(shape[1:], 1):
        if isinstance(part, int):
            return None
        if part.lower() in verbs:
            return i
    return None


def _done(verb: str, rest: Shape) -> tuple[str, Shape] | None:
    """The verb in the past perfect (after "had") and what follows it."""
    nxt = rest[0] if rest and isinstance(rest[0], str) else None
    if verb in BE:
        return "been", rest
    if verb in HAVE:
        return (nxt, rest[1:]) if nxt is not None and is_participle(nxt) else ("had", rest)
    if verb in MODAL and nxt is not None:
        return _done(nxt.lower(), rest[1:]) if nxt.lower() in HAVE else (participle(nxt), rest[1:])
    return None


def perfect(shape: Shape, args: list[str], holds: bool = True) -> str | None:
    """The clause after "had" for a sentence of this shape: "173 is stopped" -> "173 been stopped",
    "173 has crossed the stop line" -> "173 crossed the stop line", "173 has red light" -> "173 had
    red light", "173 would endanger 9" -> "173 endangered 9"; and what did not hold: "173 not been
    stopped", "173 had no stop sign", "there been no safe gap ...". None: no verb the grammar knows."""
    i = _verb_at(shape)
    if i is None:
        return None
    head, verb, rest = shape[:i], str(shape[i]).lower(), shape[i + 1:]
    negate = not holds
    if rest[:1] == ["not"]:
        rest, negate = rest[1:], not negate
    found = _done(verb, rest)
    if found is None:
        return None
    done, rest = found
    possessed = done == "had" or [str(w).lower() for w in head] == ["there"]
    if negate and possessed and rest[:1] in (["a"], ["an"]):
        words = [*head, done, "no", *rest[1:]]          # "had no stop sign", "there been no safe gap"
    else:
        words = [*head, *(["not"] if negate else []), done, *rest]
    return _fill(words, args)


def _fill(shape: Shape, args: list[str]) -> str:
    """The words with the arguments in their slots; a template's "a" before a slot agrees with it."""
    out: list[str] = []
    for j, part in enumerate(shape):
        after = shape[j + 1] if j + 1 < len(shape) else None
        if isinstance(part, int):
            out.append(args[part])
        elif part.lower() in ("a", "an") and isinstance(after, int):
            out.append(a(args[after]))
        else:
            out.append(part)
    return " ".join(out)


# -- how an action was done: the conditions of the potential violation ---------------------------
# What a condition adds beside the action ("entered the junction against a red light") is a choice
# of words no template holds, so these stay by hand, keyed by the rulebooks' sentences; a sentence
# not here keeps the rule's own words ("where 9 is at a crossroads").
Phrase = Callable[[list, Any], str | None]          # (arguments, the vehicle) -> phrase, None: left out

MANNER: dict[Sentence, Phrase] = {
    vocab.HAS_LIGHT: lambda x, v: f"against {with_a(x[1])} light",      # the preposition and article
    vocab.CROSSED_THE_STOP_LINE_ON: lambda x, v: f"on {with_a(x[1])} light",     # the act: crossing on it
    vocab.STOP_LINE_NOT_CLEARLY_VISIBLE: lambda x, v: "where the stop line was not clearly visible",
    vocab.HAS_SIGN: lambda x, v: f"at {with_a(x[1])} sign",             # the preposition
    vocab.HAS_SPEED_OF: lambda x, v: f"at {value(x[1])} mph",           # the unit
    vocab.SPEED_LIMIT_IS: lambda x, v: f"where the limit is {value(x[0])} mph",   # the unit
    # another road user approaching the vehicle; the vehicle itself needs no naming
    vocab.IS_APPROACHING: lambda x, v: f"with {value(x[0])} approaching" if x[1] == v else None,
    vocab.IS_ON_THE_MAIN_ROAD: lambda x, v: "on the main road" if x[0] != v else None,
    vocab.IS_STOPPED_IN_THE_BOX_JUNCTION: lambda x, v: "and stopped in it",  # the box the action named
    # implied by the action itself ("entered the junction"), left out
    vocab.HAS_CROSSED_THE_STOP_LINE: lambda x, v: None,
    vocab.IS_IN_THE_JUNCTION: lambda x, v: None,
    vocab.IS_AT_A_BOX_JUNCTION: lambda x, v: None,
    vocab.IS_OF_TYPE: lambda x, v: None,                                # the verdict names the vehicle
}
# a condition that held because the sentence did NOT
MANNER_NOT: dict[Sentence, Phrase] = {
    vocab.HAS_STOPPED_AT_THE_STOP_LINE: lambda x, v: "without stopping at the stop line",
    vocab.HAS_STOPPED_BEFORE_ENTERING_THE_MAJOR_ROAD: lambda x, v: "without stopping before the major road",
    vocab.STOP_LINE_NOT_CLEARLY_VISIBLE: lambda x, v: None,                # the line was visible: the usual case
    vocab.CROSSED_THE_STOP_LINE_ON: lambda x, v: None,                  # no record of when it crossed
    vocab.EXIT_OF_THE_BOX_JUNCTION_IS_CLEAR: lambda x, v: "while its exit was not clear",
    vocab.IS_STOPPED: lambda x, v: None,                                # implied: it moved
    vocab.HAS_LIGHT: lambda x, v: None,                                 # another colour is named
}


def _by_functor(table: dict[Sentence, Any]) -> dict[str, Any]:
    return {s.functor: entry for s, entry in table.items()}


_MANNER, _MANNER_NOT = _by_functor(MANNER), _by_functor(MANNER_NOT)


def manner(data: list, vehicle: Any, negated: bool, text: str) -> str | None:
    """How a condition of the potential violation reads beside the action ("against a red light");
    a sentence the table does not know keeps the rule's words ("where 9 is at a crossroads")."""
    fn = (_MANNER_NOT if negated else _MANNER).get(data[0])
    if fn is None:
        return f"where {text}"
    return fn(list(data[1:]), vehicle)


# -- what might have been: counterfactual clauses --------------------------------------------------
# The clause after "had" is the rulebook's own sentence put in the past perfect by grammar
# (reasoner.wording: a template is words and slots; the functor is its words). Only where the template
# lacks a word a reader needs does a sentence read through another template, written here the way a
# rulebook would write it, with the reason beside it.
PROSE: dict[Sentence, str] = {
    vocab.HAS_LIGHT: "*a vehicle* has a *a colour* light",        # the article: "had a red light"
    vocab.CROSSED_THE_STOP_LINE_ON: "*a vehicle* has crossed the stop line on a *a colour* light",  # the tense
    vocab.IS_OF_TYPE: "*a vehicle* is a *a type*",                # the article: "been an ambulance"
    vocab.HAS_SPEED_OF: "*a vehicle* is doing *a number* mph",    # the unit: "been doing 38 mph"
    vocab.SPEED_LIMIT_IS: "the speed limit is *a number* mph",    # the unit: "been 30 mph"
}
# how the old value reads after "instead of", where the bare value does not
INSTEAD: dict[Sentence, Callable[[Any], str]] = {
    vocab.IS_OF_TYPE: with_a,                                     # the article: "instead of a car"
    vocab.HAS_SIGN: lambda v: f"{with_a(v)} sign",                # the noun: "instead of a stop sign"
}
_PROSE = {s.functor: shape(t) for s, t in PROSE.items()}
_INSTEAD = _by_functor(INSTEAD)


def _arity(shape: Shape) -> int:
    return sum(isinstance(part, int) for part in shape)


def had(data: list, text: str, holds: bool = True) -> str:
    """The clause after "had": "173 been stopped"; a sentence the grammar cannot place keeps the
    rule's words ("it been recorded that 9 is at a crossroads")."""
    args = [value(x) for x in data[1:]]
    prose = _PROSE.get(data[0])
    shapes = [prose] if prose is not None and _arity(prose) == len(args) else layouts(data, text)
    clause = next((c for c in (perfect(s, args, holds) for s in shapes) if c is not None), None)
    if clause is None:
        return f"it been recorded that {text}" if holds else f"it not been recorded that {text}"
    return clause


def change_clause(kind: str, old: list, old_text: str, new: list | None = None, new_text: str = "") -> str:
    """One change as English: "had 173 been stopped", "had 173 had a green light instead of red",
    "had 253 not been on an emergency call"."""
    if kind == "add":
        return "had " + had(old, old_text)
    if kind == "remove":
        return "had " + had(old, old_text, holds=False)
    slot = next((i for i, (x, y) in enumerate(zip(old[1:], (new or [])[1:])) if x != y), 0)
    was = _INSTEAD.get(old[0], value)(old[1 + slot])
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
