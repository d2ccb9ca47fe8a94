"""LE templates: declaring sentence shapes, matching sentences to them, rendering them back.

A template such as `*a vehicle* has *a colour* light` gives the Prolog functor `has_light`
(the words outside the slots joined by `_`, as the reference implementation names them) and
an argument per slot.  Matching is how rules, scenario facts and queries become terms, and
rendering is how terms become English again, so both directions live here.

Matching follows the reference implementation: a slot's filler runs up to the first
occurrence of the template's next word (so it is decided without backtracking, in time linear
in the sentence), a filler is never empty and never contains the word `that`, and a template
whose last two parts are `that *a sentence*` takes a whole sentence in that slot.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

from .errors import LEError
from .lexer import Token, lex_line

DETERMINERS = {"a", "an", "the"}
ORDINALS = {"first", "second", "third", "fourth", "fifth", "sixth", "seventh", "eighth", "ninth",
            "tenth"}


@dataclass(frozen=True)
class Slot:
    """A place in a template, named by its type (`vehicle`, `colour`, `other entity`)."""

    type: str
    label: str = field(default="", compare=False)    # the words as declared: "first percentage"

    @property
    def phrase(self) -> str:
        """How an unknown value in this slot reads: `a vehicle`, `an other entity`."""
        words = self.label or self.type
        return f"{article(words)} {words}"


def article(words: str) -> str:
    return "an" if words[:1].lower() in "aeiou" and words[:1] else "a"


@dataclass(frozen=True)
class Template:
    """One declared sentence shape: literal words and slots, in order.

    `glue[i]` is True when part i was written directly after the previous one (`year-to-date`),
    so that rendering gives back the words as declared."""

    parts: tuple
    glue: tuple = field(default=(), compare=False)
    builtin: str | None = field(default=None, compare=False)   # Prolog functor of a built-in
    line: int = field(default=0, compare=False)

    @cached_property
    def functor(self) -> str:
        if self.builtin:
            return self.builtin
        return "_".join(p for p in self.parts if isinstance(p, str))

    @cached_property
    def arity(self) -> int:
        return sum(isinstance(p, Slot) for p in self.parts)

    @cached_property
    def slots(self) -> tuple[Slot, ...]:
        """The slots in order (worked out once: every sentence rendered asks for them)."""
        return tuple(p for p in self.parts if isinstance(p, Slot))

    @property
    def meta(self) -> bool:
        """`... that *a sentence*`: the last slot holds a sentence."""
        return (len(self.parts) >= 2 and isinstance(self.parts[-1], Slot)
                and isinstance(self.parts[-2], str) and self.parts[-2].lower() == "that")

    def literal_count(self) -> int:
        return sum(isinstance(p, str) for p in self.parts)

    def text(self) -> str:
        return render(self, [f"*{s.phrase}*" for s in self.slots])


# A template compiles to a Prolog predicate of one argument per slot, and SWI-Prolog refuses more
# than 1,024 (`max_procedure_arity`): that used to end a load in a traceback. A sentence of the
# Highway Code has a handful; these caps leave room and keep matching a sentence cheap.
MAX_SLOTS = 64
MAX_PARTS = 256


def parse_template(text: str, line: int = 0) -> Template:
    """Parse `*a vehicle* has *a colour* light.` into its words and slots."""
    tokens = [t for t in lex_line(text.strip(), line or 1).tokens]
    while tokens and tokens[-1].text in (".", ","):
        tokens.pop()
    return template_from_tokens(tokens, line)


def template_from_tokens(tokens: list[Token], line: int = 0) -> Template:
    parts: list = []
    glue: list[bool] = []
    i = 0
    while i < len(tokens):
        t = tokens[i]
        if t.text == "*":
            j = i + 1
            while j < len(tokens) and tokens[j].text != "*":
                j += 1
            if j == len(tokens):
                raise LEError("a slot is not closed: `*` without its pair", "<le>", t.line, t.col,
                              "write slots as *a name*")
            inner = tokens[i + 1:j]
            if inner and inner[0].text.lower() in DETERMINERS:
                inner = inner[1:]
            label = [w.text for w in inner]
            if not label:
                raise LEError("an empty slot `**`", "<le>", t.line, t.col, "write slots as *a name*")
            type_words = [w for w in label if w.lower() not in ORDINALS] or label
            parts.append(Slot("_".join(type_words), " ".join(label)))
            glue.append(not t.space)
            i = j + 1
        else:
            parts.append(t.text)
            glue.append(i > 0 and not t.space)
            i += 1
    if not any(isinstance(p, Slot) for p in parts) and not parts:
        raise LEError("an empty template", "<le>", line, 1)
    slots = sum(isinstance(p, Slot) for p in parts)
    if slots > MAX_SLOTS:
        raise LEError(f"a template of {slots} slots; a template has at most {MAX_SLOTS}", "<le>", line,
                      tokens[0].col if tokens else 1, "split the sentence into several templates")
    if len(parts) > MAX_PARTS:
        raise LEError(f"a template of {len(parts)} words and slots; a template has at most {MAX_PARTS}",
                      "<le>", line, tokens[0].col if tokens else 1, "split the sentence into several templates")
    return Template(tuple(parts), tuple(glue), line=line)


def same_word(a: str, b: str) -> bool:
    a, b = a.lower(), b.lower()
    return a == b or (a in ("a", "an") and b in ("a", "an"))


def _stops(tok: Token, stop: str | None) -> bool:
    return stop is not None and tok.kind != "number" and same_word(tok.text, stop)


def match_tokens(template: Template, tokens: list[Token], lists: bool = True):
    """Split `tokens` into slot fillers (lists of tokens), or None if the sentence does not fit.

    For a meta template the last filler is the whole sentence after `that`.  With `lists`
    off (facts from outside), brackets are ordinary characters of a constant."""
    parts = template.parts
    fillers: list[list[Token]] = []
    j, n = 0, len(tokens)
    meta = template.meta
    for i, part in enumerate(parts):
        if isinstance(part, str):
            if j >= n or not same_word(tokens[j].text, part):
                return None
            j += 1
            if meta and i == len(parts) - 2:
                if j >= n:
                    return None
                fillers.append(tokens[j:])
                return fillers
            continue
        stop = parts[i + 1] if i + 1 < len(parts) and isinstance(parts[i + 1], str) else None
        start = j
        if lists and j < n and tokens[j].text == "[":
            depth = 0
            while j < n:
                if tokens[j].text == "[":
                    depth += 1
                elif tokens[j].text == "]":
                    depth -= 1
                    if depth == 0:
                        j += 1
                        break
                j += 1
            else:
                return None
            if depth != 0:
                return None
        else:
            while j < n and not _stops(tokens[j], stop):
                if tokens[j].kind == "word" and tokens[j].text.lower() == "that":
                    break
                if lists and tokens[j].text in ("[", "]"):
                    break
                j += 1
        if j == start:
            return None
        fillers.append(tokens[start:j])
    return fillers if j == n else None


def match(template: Template, words: list[str]) -> list[list[str]] | None:
    """Split `words` into slot fillers (each one or more words), or None if it does not fit."""
    tokens = lex_line(" ".join(words), 1).tokens
    found = match_tokens(template, tokens)
    if found is None:
        return None
    return [[t.text for t in f] for f in found]


def render(template: Template, args: list[str]) -> str:
    """Fill the template's slots with already-rendered arguments."""
    it = iter(args)
    out: list[str] = []
    glue = template.glue or (False,) * len(template.parts)
    for i, p in enumerate(template.parts):
        text = next(it) if isinstance(p, Slot) else p
        if out and not glue[i]:
            out.append(" ")
        out.append(str(text))
    return "".join(out)

