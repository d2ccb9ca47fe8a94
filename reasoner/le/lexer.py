"""Splitting LE text into located tokens, line by line.

LE is read as lines of tokens: indentation matters (it nests `and`/`or`), and a statement may
span lines.  A token keeps its line, column and whether a space came before it, so that a
constant is rebuilt exactly as written (`not-for-profit`, `Tom's`) while the parser still sees
the pieces (`ET-P` is a subtraction).  `%` starts a comment that runs to the end of the line.
Tabs count as four columns of indentation, as in the reference implementation.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

from .dates import parse_date
from .errors import LEError

TAB = 4

# Order matters: a date before a number, a number before a word, operators before punctuation.
TOKEN = re.compile(r"""
    (?P<date>\d{4}-\d{1,2}-\d{1,2}(?:T\d{1,2}:\d{1,2}(?::\d{1,2}(?:\.\d+)?)?(?:Z|[+-]\d{2}:?\d{2})?)?)(?![\w-])
  | (?P<number>\d+(?:\.\d+)?(?:[eE][+-]?\d+)?)(?![\w])
  | (?P<word>\w+)
  | (?P<op>>=|=<|<=|\\==|\\=|==|=:=|=\\=|!=)
  | (?P<punct>\S)
""", re.VERBOSE)


@dataclass(frozen=True)
class Token:
    kind: str          # word, number, date, op, punct
    text: str
    line: int
    col: int           # 1-based column in the source line
    space: bool        # whitespace (or the line start) before it
    value: int | float | None = None   # a number's, or a date's seconds since the epoch

    def is_word(self, *words: str) -> bool:
        return self.kind == "word" and self.text.lower() in words


@dataclass
class Line:
    number: int        # 1-based line number in the file
    indent: int        # columns of leading whitespace (tab = 4)
    tokens: list[Token]

    @property
    def text(self) -> str:
        return join_tokens(self.tokens)


def indentation(raw: str) -> int:
    n = 0
    for ch in raw:
        if ch == " ":
            n += 1
        elif ch == "\t":
            n += TAB
        else:
            break
    return n


def strip_comment(raw: str) -> str:
    i = raw.find("%")
    return raw if i < 0 else raw[:i]


def lex_line(raw: str, number: int, comments: bool = True, limit: int | None = None) -> Line:
    """The line's tokens; with `limit`, reading stops after limit + 1 of them."""
    text = strip_comment(raw) if comments else raw
    tokens: list[Token] = []
    prev_end = -1
    for m in TOKEN.finditer(text):
        if limit is not None and len(tokens) > limit:
            break
        kind = m.lastgroup
        assert kind is not None         # every alternative of TOKEN is a named group
        value: int | float | None = None
        tok_text = m.group(kind)
        if kind == "date":
            value = parse_date(tok_text)
            if value is None:           # 2021-13-45: not a date, read it as numbers and dashes
                kind = "word"
        elif kind == "number":
            try:
                value = float(tok_text) if any(c in tok_text for c in ".eE") else int(tok_text)
            except ValueError:          # more digits than Python converts: a word, not a number
                kind, value = "word", None
            if isinstance(value, float) and not math.isfinite(value):
                kind, value = "word", None
        space = prev_end < 0 or m.start() > prev_end
        tokens.append(Token(kind, tok_text, number, m.start() + 1, space, value))
        prev_end = m.end()
    return Line(number, indentation(text), tokens)


def lex(source: str, max_tokens: int | None = None, file: str = "<le>") -> list[Line]:
    """Every non-blank line of `source` (after comments are removed), with its tokens; past
    `max_tokens` tokens in all, an LEError at the line that goes over (reading stops there)."""
    lines = []
    count = 0
    for number, raw in enumerate(source.splitlines(), 1):
        line = lex_line(raw, number, limit=None if max_tokens is None else max_tokens - count)
        if line.tokens:
            lines.append(line)
            count += len(line.tokens)
            if max_tokens is not None and count > max_tokens:
                raise LEError(f"the document has more than {max_tokens} words and signs (reading stopped here)",
                              file, number, 1, "split it into several documents")
    return lines


def join_tokens(tokens: list[Token]) -> str:
    """The text of tokens as written, with any run of whitespace between them made one space."""
    out = []
    for i, t in enumerate(tokens):
        if i and t.space:
            out.append(" ")
        out.append(t.text)
    return "".join(out)


def words(tokens: list[Token]) -> list[str]:
    return [t.text for t in tokens]
