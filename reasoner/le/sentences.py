"""Turning one LE sentence into an Atom with the document's templates.

Shared by rules (where `a X` introduces and `the X` refers to a variable), scenarios and
queries (`which X`), and by scenario facts from events, where every filler is a constant: such
facts are parsed as data, so a hostile fact can at worst fail to match a template.

A slot filler is read, in this order, as: a new variable (`a vehicle`, `an other vehicle`,
`a number X`, `which date`); a variable already introduced (`the vehicle`, `X`, `monthly
amount`); a list (`[a, b]`); a date, a number or arithmetic (`ET * F - Y`); else a constant,
one atom with its words as written (`enter the junction`).  Variable names drop type words
when other words remain, so `a number X` is `X` and `a first amount` is `first`, as in the
reference implementation.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from .builtins import BUILTINS, GENERIC_IS, PREDEFINED_TYPES
from .errors import LEError
from .lexer import Token, join_tokens, lex_line
from .templates import ORDINALS, Template, match_tokens
from .terms import Arg, Atom, Expr, ListTerm, Var

NUMBER = re.compile(r"-?\d+(\.\d+)?$")
INDEFINITE = {"a", "an", "which", "each", "another"}
DEFINITE = {"the"}
OPERATORS = {"+", "-", "*", "/"}


class NoMatch(Exception):
    """No template fits (or a filler cannot be read); carries the best explanation found."""


@dataclass
class Scope:
    """The variables a rule (or query, or scenario fact) has introduced so far."""

    vars: dict = field(default_factory=dict)        # name -> Var
    undefined: list = field(default_factory=list)   # (tokens) of `the X` read as a constant

    def copy(self) -> "Scope":
        return Scope(dict(self.vars), list(self.undefined))


class Vocabulary:
    """A document's templates (its own first, then the built-ins) and its type words."""

    def __init__(self, templates) -> None:
        own = list(dict.fromkeys(templates))          # unique, in declaration order
        own.sort(key=lambda t: (-len(t.parts), -t.literal_count()))
        self.own = own
        self.builtins = sorted(BUILTINS, key=lambda t: -t.literal_count())
        self.types = set(PREDEFINED_TYPES)
        self._literal_sets: dict[Template, frozenset[str]] = {}
        self._ordered = [*self.own, *self.builtins]
        self._index: tuple[dict[str, list[int]], list[int]] | None = None
        for t in own:
            for s in t.slots:
                if "_" not in s.type and " " not in s.type:
                    self.types.add(s.type)

    # -- variable names -----------------------------------------------------------------
    def var_name(self, words: list[str]) -> str:
        """The reference's naming: type words drop out when other words remain; an ordinal
        (first, second, ...) stands for the whole name."""
        def walk(ws, ordinals):
            if not ws:
                return ordinals
            w = ws[0]
            if w.lower() in ORDINALS:
                return walk(ws[1:], [w] + ordinals)
            if w in self.types:
                rest = walk(ws[1:], ordinals)
                return rest if rest else [w]
            return [w] + walk(ws[1:], ordinals)
        name = " ".join(walk(words, []))
        return " ".join(name.replace("_", " ").split())

    # -- sentences ------------------------------------------------------------------------
    def _literals(self, template: Template) -> frozenset[str]:
        literals = self._literal_sets.get(template)
        if literals is None:
            literals = self._literal_sets[template] = frozenset(
                _word_key(p) for p in template.parts if isinstance(p, str))
        return literals

    def candidates(self, tokens: list[Token], lists: bool = True):
        """(template, fillers) for every template the sentence fits, best first.

        A template fits only if each of its literal words is among the sentence's words, so
        that test (a set lookup) comes before the matcher, and only the templates filed under
        one of the sentence's words are tested at all (a template is filed under its rarest
        literal word): recorded facts are read by the hundred thousand, against rulebooks of
        fifty templates and more."""
        found = []
        present = {_word_key(tok.text) for tok in tokens}
        for t in self._filed(present):
            if not self._literals(t) <= present:
                continue
            fillers = match_tokens(t, tokens, lists)
            if fillers is not None:
                found.append((t, fillers))
        return found

    def _filed(self, present: set[str]) -> list[Template]:
        """The templates filed under the words present (and those without literal words), in
        the order the matcher prefers: own before built-in, longest first."""
        if self._index is None:
            self._index = self._file()
        by_word, unfiled = self._index
        picked = list(unfiled)
        for word in present:
            picked += by_word.get(word, ())
        picked.sort()
        return [self._ordered[i] for i in picked]

    def _file(self) -> tuple[dict[str, list[int]], list[int]]:
        counts: dict[str, int] = {}
        for t in self._ordered:
            for word in self._literals(t):
                counts[word] = counts.get(word, 0) + 1
        by_word: dict[str, list[int]] = {}
        unfiled: list[int] = []
        for i, t in enumerate(self._ordered):
            literals = self._literals(t)
            if literals:
                by_word.setdefault(min(literals, key=lambda w: (counts[w], w)), []).append(i)
            else:
                unfiled.append(i)
        return by_word, unfiled

    def sentence(self, tokens: list[Token], scope: Scope, mode: str, file: str = "<le>") -> Atom:
        """The Atom for a sentence; mode is rule, fact, query or data (constants only)."""
        if not tokens:
            raise LEError("an empty condition", file, 0, 1)
        found = self.candidates(tokens, lists=mode != "data")
        if not found:
            t0 = tokens[0]
            raise LEError(f"no template fits: {join_tokens(tokens)!r}", file, t0.line, t0.col,
                          "declare it under `the templates are:` or reword it")
        own = [(t, f) for t, f in found if not t.builtin]
        if len(own) > 1:
            a, b = own[0][0], own[1][0]
            if (len(a.parts), a.literal_count()) == (len(b.parts), b.literal_count()) and a != b:
                t0 = tokens[0]
                raise LEError(f"ambiguous sentence {join_tokens(tokens)!r}: it fits both "
                              f"`{a.text()}` and `{b.text()}`", file, t0.line, t0.col,
                              "reword it or make the templates distinct")
        last_error = None
        for template, fillers in found:
            trial = scope.copy()
            try:
                atom = self._build(template, fillers, trial, mode, file)
            except NoMatch as exc:
                last_error = str(exc)   # the message, not the exception: its traceback holds this frame
                continue
            except LEError as exc:
                if exc.file == "<le>":
                    exc.file = file
                raise
            scope.vars, scope.undefined = trial.vars, trial.undefined
            return atom
        t0 = tokens[0]
        raise LEError(f"no template fits: {join_tokens(tokens)!r}" +
                      (f" ({last_error})" if last_error else ""), file, t0.line, t0.col,
                      "declare it under `the templates are:` or reword it")

    def _build(self, template: Template, fillers, scope: Scope, mode: str, file: str) -> Atom:
        args: list[Arg] = []
        n = len(fillers)
        for i, filler in enumerate(fillers):
            if template.meta and i == n - 1:
                try:
                    args.append(self.sentence(filler, scope, mode, file))
                    continue
                except LEError:
                    pass
            args.append(self.term(filler, scope, mode))
        if template is GENERIC_IS:
            left, right = fillers[0], args[1]
            symbolic = left[0].text.lower() not in INDEFINITE | DEFINITE and isinstance(args[0], Var)
            if not (symbolic or isinstance(right, (int, float, Var, Expr, ListTerm))):
                raise NoMatch("`X is Y` compares a variable or a value")
        return Atom(template.functor, tuple(args))

    # -- terms ----------------------------------------------------------------------------
    def term(self, tokens: list[Token], scope: Scope, mode: str) -> Arg:
        if mode == "data":
            return value_of(tokens)
        first = tokens[0].text.lower() if tokens[0].kind == "word" else ""
        if first in INDEFINITE and len(tokens) > 1 and all(t.kind != "op" for t in tokens):
            words = [t.text for t in tokens[1:]]
            name = self.var_name(words)
            if first == "another":
                name, words = "other " + name, ["other"] + words
            if name:
                var = scope.vars.get(name)
                if var is None:
                    var = Var(name, " ".join(words))
                    scope.vars[name] = var
                return var
        if first in DEFINITE and len(tokens) > 1:
            name = self.var_name([t.text for t in tokens[1:]])
            if name in scope.vars:
                return scope.vars[name]
        name = self.var_name([t.text for t in tokens])
        if name in scope.vars:
            return scope.vars[name]
        if tokens[0].text == "[" and tokens[-1].text == "]":
            return self.list_term(tokens[1:-1], scope, mode)
        if len(tokens) == 1 and tokens[0].kind in ("number", "date"):
            return tokens[0].value
        if len(tokens) == 2 and tokens[0].text == "-" and tokens[1].kind == "number":
            return _negative(tokens[1])
        if any(t.text in OPERATORS or t.text in "()" for t in tokens):
            expr = self.expression(tokens, scope)
            if expr is not None:
                return expr
            if mode in ("rule", "query") and _arithmetic(tokens):
                self._unknown_in_arithmetic(tokens, scope)
        if first in DEFINITE and len(tokens) > 1 and mode == "rule":
            scope.undefined.append(tokens)
        return join_tokens(tokens)

    def _unknown_in_arithmetic(self, tokens: list[Token], scope: Scope) -> None:
        """Arithmetic with a name that is no variable: the undefined variable, located."""
        leaf: list[Token] = []
        for t in tokens + [None]:
            if t is None or t.text in OPERATORS or t.text in "()":
                if leaf and not (len(leaf) == 1 and leaf[0].kind in ("number", "date")):
                    words = [w.text for w in leaf]
                    if words[0].lower() in DEFINITE and len(words) > 1:
                        words = words[1:]
                    if self.var_name(words) not in scope.vars:
                        text = join_tokens(leaf)
                        raise LEError(f"undefined variable `{text}` in arithmetic", "<le>", leaf[0].line,
                                      leaf[0].col, f"introduce it first, e.g. `a number {text}`, in an "
                                      "earlier condition")
                leaf = []
            else:
                leaf.append(t)

    def list_term(self, tokens: list[Token], scope: Scope, mode: str) -> ListTerm:
        items: list[Arg] = []
        current: list[Token] = []
        depth = 0
        for t in tokens:
            if t.text == "[":
                depth += 1
            elif t.text == "]":
                depth -= 1
            if t.text == "," and depth == 0:
                if current:
                    items.append(self.term(current, scope, mode))
                current = []
            else:
                current.append(t)
        if current:
            items.append(self.term(current, scope, mode))
        return ListTerm(tuple(items))

    def expression(self, tokens: list[Token], scope: Scope):
        """Arithmetic over numbers, dates and known variables, or None if it is not that."""
        pos = 0

        def leaf(toks):
            if not toks:
                return None
            if len(toks) == 1 and toks[0].kind in ("number", "date"):
                return toks[0].value
            words = [t.text for t in toks]
            if words[0].lower() in DEFINITE and len(words) > 1:
                name = self.var_name(words[1:])
                if name in scope.vars:
                    return scope.vars[name]
            name = self.var_name(words)
            return scope.vars.get(name)

        def primary():
            nonlocal pos
            if pos < len(tokens) and tokens[pos].text == "(":
                pos += 1
                e = additive()
                if e is None or pos >= len(tokens) or tokens[pos].text != ")":
                    return None
                pos += 1
                return e
            if pos < len(tokens) and tokens[pos].text == "-":
                pos += 1
                e = primary()
                return None if e is None else (-e if isinstance(e, (int, float)) else Expr("neg", (e,)))
            start = pos
            while pos < len(tokens) and tokens[pos].text not in OPERATORS and tokens[pos].text not in "()":
                pos += 1
            return leaf(tokens[start:pos])

        def multiplicative():
            nonlocal pos
            e = primary()
            while e is not None and pos < len(tokens) and tokens[pos].text in ("*", "/"):
                op = tokens[pos].text
                pos += 1
                r = primary()
                e = None if r is None else Expr(op, (e, r))
            return e

        def additive():
            nonlocal pos
            e = multiplicative()
            while e is not None and pos < len(tokens) and tokens[pos].text in ("+", "-"):
                op = tokens[pos].text
                pos += 1
                r = multiplicative()
                e = None if r is None else Expr(op, (e, r))
            return e

        e = additive()
        return e if e is not None and pos == len(tokens) else None


def _arithmetic(tokens: list[Token]) -> bool:
    """Spaced operators (`A + B`, `ET * F - Y`) mean arithmetic; `not-for-profit` does not."""
    for i, t in enumerate(tokens):
        if t.text in OPERATORS and i > 0 and (t.space or (i + 1 < len(tokens) and tokens[i + 1].space)):
            return True
    return False


def value_of(tokens: list[Token]) -> Arg:
    """A filler of a fact from outside (an event): a number, a date, or a constant."""
    if len(tokens) == 1 and tokens[0].kind in ("number", "date"):
        return tokens[0].value
    if len(tokens) == 2 and tokens[0].text == "-" and tokens[1].kind == "number" and not tokens[1].space:
        return _negative(tokens[1])
    return join_tokens(tokens)


def _negative(number: Token) -> int | float:
    """Minus a number token's value (the lexer reads every number token's value)."""
    assert number.value is not None
    return -number.value


# -- compatibility helpers used by the investigation and the simulation -----------------------

def _word_key(word: str) -> str:
    """A word as templates.same_word compares it: case-blind, `a` and `an` alike."""
    word = word.lower()
    return "a" if word == "an" else word


def constant(words: list[str]) -> Arg:
    text = " ".join(words)
    if NUMBER.match(text):
        return float(text) if "." in text else int(text)
    return text


def vocabulary(templates) -> Vocabulary:
    """The Vocabulary of a template table (cached on it when it allows)."""
    cached = getattr(templates, "_vocabulary", None)
    if cached is not None:
        return cached
    values = templates.values() if hasattr(templates, "values") else templates
    vocab = Vocabulary(list(values))
    try:
        templates._vocabulary = vocab
    except AttributeError:
        pass
    return vocab


MAX_FACT = 100_000 * 4


def parse_fact(text: str, templates) -> Atom | None:
    """A scenario fact as a ground Atom, or None when no template fits (an unknown fact)."""
    if not isinstance(text, str) or len(text) > MAX_FACT:
        return None
    text = text.strip()
    if text.endswith("."):
        text = text[:-1]
    if "\n" in text or "\r" in text:
        text = " ".join(text.split())
    tokens = lex_line(text, 1, comments=False).tokens
    if not tokens:
        return None
    try:
        atom = vocabulary(templates).sentence(tokens, Scope(), "data")
    except (LEError, RecursionError):
        return None
    # a recorded fact states something in the rulebook's own words: a comparison or arithmetic
    # ("x > y") is a question, not an observation, and is not taken as one
    return None if atom.functor in _BUILTIN_FUNCTORS else atom


_BUILTIN_FUNCTORS = frozenset(t.builtin for t in BUILTINS if t.builtin)
