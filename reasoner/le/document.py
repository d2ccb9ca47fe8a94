"""Reading an LE document: declarations, knowledge base, ontology, scenarios and queries.

A document is read as statements (each ending with a full stop) grouped in sections headed by
`the templates are:`, `the knowledge base <name> includes:`, `the ontology is:`,
`scenario <name> is:`, `query <name> is:` (and the other declaration headers of the
reference implementation).  A rule is `<head> if <conditions>`, one condition per line;
`and`/`or` start a line, and the indentation of a connective gives its precedence (the less
indented binds more loosely; connectives at one indentation must be the same).  Blocks
(`it is not the case that`, `for all cases in which ... it is the case that`, `... is the sum of
each ... such that`, `... is a collection of ... where`) hold the more indented lines below.

Any error stops the whole document: it is reported with file:line:column and a hint, and
nothing of the document is loaded.
"""
from __future__ import annotations

import re
import time
from dataclasses import dataclass

from .errors import LEError, LEWarning
from .lexer import Line, Token, join_tokens, lex
from .builtins import BUILTIN_FUNCTORS
from .sentences import Scope, Vocabulary
from .templates import Template, template_from_tokens
from .parsed import Document
from .terms import Aggregate, Cond, Query, Rule, Scenario, Var

LABEL = re.compile(r"^\s*%\s*(HC\s+\d+)\s*(?::\s*(.*?))?\s*$")

DECLARATION_HEADERS = [
    ("templates", ["the", "templates", "are"]),
    ("templates", ["the", "predicates", "are"]),
    ("templates", ["the", "timeless", "predicates", "are"]),
    ("templates", ["the", "meta", "predicates", "are"]),
    ("templates", ["the", "metapredicates", "are"]),
    ("templates", ["the", "meta", "-", "predicates", "are"]),
    ("templates", ["the", "event", "predicates", "are"]),
    ("templates", ["the", "fluents", "are"]),
    ("templates", ["the", "time", "-", "varying", "predicates", "are"]),
    ("kb", ["the", "rules", "are"]),
    ("kb", ["the", "knowledge", "base", "includes"]),
    ("ontology", ["the", "ontology", "is"]),
]
MAX_SOURCE = 2_000_000
MAX_HEADER = 64          # tokens: a section header is never longer
# The parsing budget. The bundled rulebooks have at most a few hundred statements of at most a
# hundred or so tokens each and read in milliseconds; a hostile document of the allowed size read
# for a minute or more (100,000 conditions in one rule: 25 s; one sentence of 300,000 words: 55 s).
MAX_TOKENS = 100_000  # highway_code.le, the largest, has about 6,000
MAX_STATEMENTS = 5_000
MAX_STATEMENT_TOKENS = 5_000
PARSE_SECONDS = 10.0


@dataclass
class Statement:
    lines: list[Line]          # the statement's lines (tokens of this statement only)
    end: Token | None          # the full stop (None for a header)
    header: tuple | None = None

    @property
    def end_line(self) -> int:
        """The line of its full stop (a header, which has none, ends on its first line)."""
        return self.end.line if self.end is not None else self.first.line

    @property
    def first(self) -> Token:
        return self.lines[0].tokens[0]

    @property
    def tokens(self) -> list[Token]:
        return [t for line in self.lines for t in line.tokens]

    @property
    def text(self) -> str:
        return "\n".join(join_tokens(line.tokens) for line in self.lines)


def _lower(tokens: list[Token]) -> list[str]:
    return [t.text.lower() for t in tokens]


def header_of(tokens: list[Token]):
    """(section, name) when `tokens` (before a colon) are a section header, else None."""
    words = _lower(tokens)
    for section, pattern in DECLARATION_HEADERS:
        if words == pattern:
            flavour = "time" if ("fluents" in pattern or "event" in pattern or "varying" in pattern) else None
            return section, flavour
    if len(words) >= 5 and words[:3] == ["the", "knowledge", "base"] and words[-1] == "includes":
        return "kb", join_tokens(tokens[3:-1])
    if len(words) >= 3 and words[0] in ("scenario", "query") and words[-1] == "is":
        return words[0], join_tokens(tokens[1:-1])
    return None


def split_statements(lines: list[Line], file: str) -> list[Statement]:
    """Cut the token lines into statements at full stops and after section headers."""
    out: list[Statement] = []
    current: list[Line] = []

    def current_tokens():
        return [t for l in current for t in l.tokens]

    for line in lines:
        start = 0
        toks = line.tokens
        for i, tok in enumerate(toks):
            if tok.kind == "punct" and tok.text == ".":
                piece = toks[start:i]
                if piece:
                    current.append(_piece(line, piece, start))
                if not current:
                    raise LEError("a full stop with nothing before it", file, tok.line, tok.col)
                out.append(Statement(current, tok))
                current, start = [], i + 1
            elif tok.kind == "punct" and tok.text == ":":
                piece = toks[start:i]
                size = sum(len(l.tokens) for l in current) + len(piece)
                found = header_of(current_tokens() + piece) if size <= MAX_HEADER else None
                if found:
                    if piece:
                        current.append(_piece(line, piece, start))
                    out.append(Statement(current, None, found))
                    current, start = [], i + 1
        if start < len(toks):
            current.append(_piece(line, toks[start:], start))
    if current:
        first = current[0].tokens[0]
        rest = current_tokens()
        if len(rest) <= MAX_HEADER and header_of(rest):
            raise LEError("a section header needs a colon", file, first.line, first.col)
        raise LEError("unfinished statement: no full stop", file, first.line, first.col,
                      "end every rule, fact and query with `.`")
    return out


def _piece(line: Line, tokens: list[Token], start: int) -> Line:
    indent = line.indent if start == 0 else tokens[0].col - 1
    return Line(line.number, indent, tokens)


def parse_document(source: str, file: str = "<le>") -> Document:
    """Parse (and check) a whole LE document; raises LEError on the first problem."""
    if not isinstance(source, str):
        raise LEError("an LE document is text", file, 0, 1)
    if len(source) > MAX_SOURCE:
        raise LEError(f"the document is larger than {MAX_SOURCE} characters", file, 0, 1)
    parser = _Parser(source, file)
    try:
        return parser.parse()
    except RecursionError:
        where = parser.current.first if parser.current is not None else None
        raise parser.error("the document nests too deeply to read", where,
                           "write fewer brackets or shorter sentences") from None


class _Parser:
    def __init__(self, source: str, file: str) -> None:
        self.source = source
        self.file = file
        self.doc = Document(file)
        self.labels = self._labels(source)
        self.vocab = Vocabulary([])   # the document's own, once its templates are declared (_declare)
        self.current: Statement | None = None  # the statement being read, for an error's place

    @staticmethod
    def _labels(source: str) -> dict[int, tuple]:
        labels = {}
        for number, raw in enumerate(source.splitlines(), 1):
            m = LABEL.match(raw)
            if m:
                labels[number] = (re.sub(r"\s+", " ", m.group(1)), m.group(2) or None)
        return labels

    def error(self, message: str, tok: Token | None, hint: str = "") -> LEError:
        return LEError(message, self.file, tok.line if tok else 0, tok.col if tok else 1, hint)

    def warn(self, message: str, tok: Token | None, hint: str = "") -> None:
        self.doc.warnings.append(LEWarning(message, self.file, tok.line if tok else 0,
                                           tok.col if tok else 1, hint))

    # -- sections -------------------------------------------------------------------------
    def _within_budget(self, st: Statement) -> None:
        """Stop a document that is too long to read, at the statement where it goes over."""
        self.current = st
        if len(st.tokens) > MAX_STATEMENT_TOKENS:
            raise self.error(f"a statement of {len(st.tokens)} words and signs; a statement has at most "
                             f"{MAX_STATEMENT_TOKENS}", st.first, "split it into several rules")
        if time.monotonic() > self.deadline:
            raise self.error(f"the document took longer than {PARSE_SECONDS:.0f} s to read; stopped here",
                             st.first, "split it into smaller documents")

    def parse(self) -> Document:
        self.deadline = time.monotonic() + PARSE_SECONDS
        statements = split_statements(lex(self.source, MAX_TOKENS, self.file), self.file)
        if len(statements) > MAX_STATEMENTS:
            raise self.error(f"the document has {len(statements)} statements; a document has at most "
                             f"{MAX_STATEMENTS}", statements[MAX_STATEMENTS].first, "split it into several documents")
        section, name = None, None
        pending_templates: list[Template] = []
        content: list[tuple] = []
        asked: dict[str, Statement | None] = {}
        previous_end = 0
        for st in statements:
            self._within_budget(st)
            if st.header:
                section, name = st.header
                if section in ("scenario", "query") and not name:
                    raise self.error(f"a {section} needs a name", st.first)
                if section == "scenario":
                    if name in self.doc.scenarios:
                        raise self.error(f"scenario {name!r} is defined twice", st.first)
                    self.doc.scenarios[name] = Scenario(name, [], st.first.line)
                elif section == "query":
                    if name in asked:
                        raise self.error(f"query {name!r} is defined twice", st.first)
                    asked[name] = None
                elif section == "kb" and name:
                    self.doc.kb_names.append(name)
                elif section == "templates" and name == "time":
                    self.warn("fluents and events are declared as ordinary templates here (no event "
                              "calculus)", st.first, "see docs/le-compatibility.md")
                previous_end = st.first.line
                continue
            words = _lower(st.tokens)
            if words[:4] == ["the", "target", "language", "is"]:
                lang = [w for w in words[4:] if w != ":"]
                if len(lang) != 1:
                    raise self.error("`the target language is` names one language", st.first)
                self.doc.target = lang[0]
                if lang[0] != "prolog":
                    self.warn(f"the target language {lang[0]!r} is read as prolog", st.first,
                              "this compiler targets Prolog only")
                previous_end = st.end_line
                continue
            if section is None:
                raise self.error(f"text outside any section: {join_tokens(st.tokens)[:60]!r}", st.first,
                                 "start with `the templates are:` and then "
                                 "`the knowledge base <name> includes:`")
            if section == "templates":
                if content:
                    raise self.error("templates must be declared before the rules that use them",
                                     st.first, "move this template up to `the templates are:`")
                pending_templates.extend(self._templates(st))
            elif section == "query":
                assert name is not None     # a query's header names it (refused above when it does not)
                if asked[name] is not None:
                    raise self.error(f"query {name!r} holds one question", st.first,
                                     "end the question with a single full stop")
                asked[name] = st
                content.append(("query", name, st, previous_end))
            else:
                content.append((section, name, st, previous_end))
            previous_end = st.end_line
        for qname, question in asked.items():
            if question is None:
                raise LEError(f"query {qname!r} has no question", self.file, 0, 1)
        self._declare(pending_templates)
        for section, name, st, prev in content:
            self._within_budget(st)
            if section == "query":
                try:
                    self._query(name, st)
                except LEError as exc:      # a question it cannot read does not stop the rules
                    self.doc.unreadable_queries[name] = exc
                    self.doc.warnings.append(LEWarning(f"query {name!r} cannot be asked: {exc.message}",
                                                       exc.file, exc.line, exc.column, exc.hint))
            elif section == "scenario":
                self.doc.scenarios[name].rules.append(self._statement(st, f"scenario:{name}", prev))
            else:
                self.doc.rules.append(self._statement(st, section, prev))
        return self.doc

    # -- templates --------------------------------------------------------------------------
    def _templates(self, st: Statement) -> list[Template]:
        out = []
        for line in st.lines:
            piece: list[Token] = []
            for tok in line.tokens + [None]:
                if tok is None or (tok.kind == "punct" and tok.text == ","):
                    if piece:
                        try:
                            out.append(template_from_tokens(piece, piece[0].line))
                        except LEError as exc:
                            raise LEError(exc.message, self.file, piece[0].line, piece[0].col,
                                          exc.hint or "write a template as words and *a slot*s") from None
                    piece = []
                else:
                    piece.append(tok)
        return out

    def _declare(self, templates: list[Template]) -> None:
        table = self.doc.templates
        for t in templates:
            key = t.functor
            existing = table.get(key)
            if existing is not None:
                if existing == t:
                    continue
                if existing.arity == t.arity:
                    raise LEError(f"two templates compile to the same predicate {key}/{t.arity}: "
                                  f"`{existing.text()}` and `{t.text()}`", self.file, t.line, 1,
                                  "change the words of one of them")
                key = f"{t.functor}/{t.arity}"
                if key in table:
                    continue
            if t.meta and sum(1 for p in t.parts if isinstance(p, str) and p.lower() == "that") > 1:
                self.warn("only the last `that` of a template takes a sentence", None)
            table[key] = t
        self.vocab = Vocabulary(list(table.values()))
        table._vocabulary = self.vocab

    # -- statements -----------------------------------------------------------------------
    def _label_for(self, line: int, previous_end: int):
        for n in range(line - 1, previous_end, -1):
            if n in self.labels:
                return self.labels[n]
        return None

    def _statement(self, st: Statement, section: str, previous_end: int) -> Rule:
        scope = Scope()
        mode = "fact" if section.startswith("scenario:") else "rule"
        tokens = st.tokens
        split = next((i for i, t in enumerate(tokens) if t.is_word("if")), None)
        if split is None:
            head = self.vocab.sentence(tokens, scope, mode, self.file)
            body: list = []
        else:
            if split == 0:
                raise self.error("a rule needs a conclusion before `if`", tokens[0])
            head = self.vocab.sentence(tokens[:split], scope, mode, self.file)
        if head.functor in BUILTIN_FUNCTORS:
            raise self.error(f"a rule or fact cannot conclude the built-in `{join_tokens(tokens[:split])}`",
                             tokens[0], "declare a template for it, or write it as a condition")
        if split is not None:
            body_lines = self._body_lines(st, tokens[split])
            if not body_lines:
                raise self.error("`if` needs conditions after it", tokens[split],
                                 "write one condition per line after `if`")
            body = self._conditions(body_lines, scope, mode)
        self._check_undefined(scope, mode)
        label = self._label_for(st.first.line, previous_end) if section in ("kb", "ontology") else None
        return Rule(head, body, st.first.line, label[0] if label else None, label[1] if label else None,
                    st.text, section)

    def _body_lines(self, st: Statement, if_tok: Token) -> list[Line]:
        """The lines after `if`: the rest of the `if` line first (indented like `if` when `if`
        starts its line), then the following lines."""
        out: list[Line] = []
        seen = False
        for line in st.lines:
            if seen:
                out.append(line)
                continue
            if if_tok in line.tokens:
                i = line.tokens.index(if_tok)
                rest = line.tokens[i + 1:]
                seen = True
                if rest:
                    indent = line.indent if i == 0 else 0
                    out.append(Line(line.number, indent, rest))
        return out

    def _query(self, name: str, st: Statement) -> None:
        scope = Scope()
        lines = st.lines
        toks = st.tokens
        if len(toks) > 2 and _lower(toks[:2]) == ["for", "which"]:
            colon = next((i for i, t in enumerate(toks) if t.text == ":"), None)
            if colon is None:
                raise self.error("`for which ...` needs a colon before the question", toks[0])
            for piece in _split_commas(toks[2:colon]):
                words = [t.text for t in piece if not t.is_word("and")]
                if words:
                    vname = self.vocab.var_name(words)
                    scope.vars.setdefault(vname, Var(vname, " ".join(words)))
            rest = toks[colon + 1:]
            if not rest:
                raise self.error("the question is missing after `for which ...:`", toks[colon])
            lines = _relines(lines, rest)
        body = self._conditions(lines, scope, "query")
        self.doc.queries[name] = Query(name, body, st.first.line, st.text)

    # -- conditions -----------------------------------------------------------------------
    def _conditions(self, lines: list[Line], scope: Scope, mode: str) -> list:
        items, pos = self._block(lines, 0, lines[0].indent, scope, mode)
        if pos < len(lines):
            line = lines[pos]
            tok = line.tokens[0]
            if tok.is_word("and", "or"):
                raise self.error(f"bad indentation: `{tok.text}` is less indented than the first "
                                 "condition of its block", tok,
                                 "indent each `and`/`or` at least as much as the condition it continues")
            raise self.error("a condition must start with `and` or `or`", tok,
                             "put one condition per line, each after `and` or `or`")
        return items

    def _block(self, lines: list[Line], pos: int, ind0: int, scope: Scope, mode: str):
        """The conditions of one block as a conjunction list, and the position after it."""
        first = lines[pos]
        cond, pos = self._condition(lines, pos, first.tokens, scope, mode)
        items: list = [cond]
        while pos < len(lines):
            line = lines[pos]
            op = line.tokens[0]
            if line.indent < ind0 or not op.is_word("and", "or"):
                break
            if len(line.tokens) == 1:
                raise self.error(f"`{op.text}` needs a condition on the same line", op,
                                 f"write `{op.text} <condition>` on one line")
            cond, pos = self._condition(lines, pos, line.tokens[1:], scope, mode)
            items.append((line.indent, op.text.lower(), cond, op))
        return self._tree(items), pos

    def _tree(self, items: list) -> list:
        """Nest a flat `c0 (ind, op, c1) ...` list by the indentation of its connectives."""
        if len(items) == 1:
            return _conj(items[0])
        ops = items[1:]
        low = min(i[0] for i in ops)
        kinds = {i[1] for i in ops if i[0] == low}
        if len(kinds) > 1:
            clash = [i[3] for i in ops if i[0] == low]
            raise self.error("`and` and `or` at the same indentation: the nesting is ambiguous", clash[-1],
                             "indent the connective that binds more tightly further than the other")
        kind = kinds.pop()
        groups: list[list] = [[items[0]]]
        for it in ops:
            if it[0] == low:
                groups.append([it[2]])
            else:
                groups[-1].append(it)
        subtrees = [self._tree(g) for g in groups]
        if kind == "and":
            return [c for sub in subtrees for c in sub]
        return [Cond(any_of=tuple(tuple(sub) for sub in subtrees), line=_line_of(subtrees))]

    def _condition(self, lines: list[Line], pos: int, tokens: list[Token], scope: Scope, mode: str):
        """One condition starting at lines[pos] (its tokens after the connective); returns the
        Cond (or a list for a block already nested) and the next line position."""
        line = lines[pos]
        words = _lower(tokens)
        tok0 = tokens[0]
        if words[:6] == ["it", "is", "not", "the", "case", "that"]:
            rest = tokens[6:]
            if rest:
                cond, nxt = self._condition(lines, pos, rest, scope, mode)
                return Cond(negated=tuple(_conj(cond)), line=tok0.line), nxt
            inner, nxt = self._sub_block(lines, pos, scope, mode, tok0, "`it is not the case that`")
            return Cond(negated=tuple(inner), line=tok0.line), nxt
        if words[:5] == ["for", "all", "cases", "in", "which"]:
            if len(words) > 5:
                raise self.error("`for all cases in which` ends its line", tokens[5],
                                 "put the cases on the lines below it, indented")
            cases, nxt = self._sub_block(lines, pos, scope, mode, tok0, "`for all cases in which`")
            if nxt >= len(lines) or _lower(lines[nxt].tokens) != ["it", "is", "the", "case", "that"]:
                raise self.error("`for all cases in which` needs `it is the case that` after its cases",
                                 tok0, "write `it is the case that` on its own line, then the conclusions")
            then, nxt = self._sub_block(lines, nxt, scope, mode, lines[nxt].tokens[0],
                                        "`it is the case that`")
            return Cond(forall=(tuple(cases), tuple(then)), line=tok0.line), nxt
        following = lines[pos + 1].tokens if pos + 1 < len(lines) else []
        agg = self._aggregate_head(tokens, following)
        if agg is not None:
            return self._aggregate(lines, pos, tokens, agg, scope, mode)
        sentence = list(tokens)
        nxt = pos + 1
        while nxt < len(lines) and lines[nxt].tokens[0].is_word("that") and not sentence[-1].is_word("that"):
            sentence += lines[nxt].tokens
            nxt += 1
        atom = self.vocab.sentence(sentence, scope, mode, self.file)
        return Cond(atom=atom, line=tok0.line), nxt

    def _sub_block(self, lines, pos, scope, mode, tok, what):
        line = lines[pos]
        nxt = pos + 1
        if nxt >= len(lines) or lines[nxt].indent <= line.indent:
            raise self.error(f"{what} needs an indented block below it", tok,
                             "indent the conditions under it further than its own line")
        return self._block(lines, nxt, lines[nxt].indent, scope, mode)

    AGGREGATES = [
        (["is", "the", "sum", "of", "each"], "sum", ["such", "that"]),
        (["is", "the", "maximum", "of", "each"], "max", ["such", "that"]),
        (["is", "the", "max", "of", "each"], "max", ["such", "that"]),
        (["is", "the", "minimum", "of", "each"], "min", ["such", "that"]),
        (["is", "the", "min", "of", "each"], "min", ["such", "that"]),
        (["is", "the", "number", "of", "each"], "count", ["such", "that"]),
        (["is", "a", "collection", "of"], "bag", ["where"]),
        (["is", "the", "collection", "of"], "bag", ["where"]),
        (["is", "the", "bag", "of", "all"], "bag", ["where"]),
        (["is", "a", "set", "of"], "set", ["where"]),
        (["is", "the", "set", "of"], "set", ["where"]),
    ]

    def _aggregate_head(self, tokens, following):
        words = _lower(tokens)
        where_next = bool(following) and following[0].is_word("where")
        for i in range(1, len(words)):
            for pattern, kind, closer in self.AGGREGATES:
                if words[i:i + len(pattern)] == pattern:
                    rest = words[i + len(pattern):]
                    if kind in ("bag", "set"):
                        if rest and rest[-1] == "where":
                            end = len(words) - 1
                        elif where_next:
                            end = len(words)
                        else:
                            continue
                    elif rest[-2:] == closer:
                        end = len(words) - 2
                    else:
                        continue
                    each = tokens[i + len(pattern):end]
                    if not each:
                        continue
                    return kind, tokens[:i], each, end < len(words)
        return None

    def _term(self, tokens, scope, mode):
        """vocab.term, its errors located in this document (the vocabulary does not know the file)."""
        try:
            return self.vocab.term(tokens, scope, mode)
        except LEError as exc:
            if exc.file == "<le>":
                exc.file = self.file
            raise

    def _aggregate(self, lines, pos, tokens, agg, scope, mode):
        kind, result_toks, each_toks, has_closer = agg
        tok0 = tokens[0]
        result = self._term(result_toks, scope, mode)
        nxt = pos + 1
        if kind in ("bag", "set"):
            if each_toks[0].text == "[":
                each = self._term(each_toks, scope, mode)
            else:
                each = self._each(each_toks, scope)
            if has_closer:
                body, nxt = self._sub_block(lines, pos, scope, mode, tok0, "`where`")
            else:
                if nxt >= len(lines) or not lines[nxt].tokens[0].is_word("where") or len(lines[nxt].tokens) < 2:
                    where = lines[nxt].tokens[0] if nxt < len(lines) else tok0
                    raise self.error("a collection needs `where` and its conditions", where,
                                     "write `where <condition>` on the next line, indented")
                where_line = lines[nxt]
                sub = [Line(where_line.number, where_line.indent, where_line.tokens[1:])] + lines[nxt + 1:]
                body, used = self._block(sub, 0, where_line.indent, scope, mode)
                nxt = nxt + used
        else:
            each = self._each(each_toks, scope)
            body, nxt = self._sub_block(lines, pos, scope, mode, tok0, "`such that`")
        if nxt < len(lines) and lines[nxt].tokens[0].is_word("at") and len(lines[nxt].tokens) > 1:
            self.warn("a time after an aggregate (`at ...`) is read but not used", lines[nxt].tokens[0],
                      "the Prolog target of the reference implementation ignores it too")
            nxt += 1
        return Cond(aggregate=Aggregate(kind, result, each, tuple(body)), line=tok0.line), nxt

    def _each(self, each_toks: list[Token], scope: Scope) -> Var:
        """What an aggregate ranges over: a variable, new or already introduced."""
        words = [t.text for t in each_toks]
        if words[0].lower() in ("a", "an", "the", "each"):
            words = words[1:]
        name = self.vocab.var_name(words) if words else ""
        if not name:
            raise self.error("an aggregate needs the name of what it collects", each_toks[0])
        each = scope.vars.get(name) or Var(name, " ".join(words))
        scope.vars[name] = each
        return each

    def _check_undefined(self, scope: Scope, mode: str) -> None:
        for toks in scope.undefined:
            if toks[-1].text not in self.vocab.types:
                continue        # `the UK`: a constant that starts with `the`
            self.warn(f"`{join_tokens(toks)}` refers to no variable introduced before it; it is read "
                      f"as the constant {join_tokens(toks)!r}", toks[0],
                      f"introduce it with `a {join_tokens(toks[1:])}` first, or drop `the`")


def _conj(cond) -> list:
    return cond if isinstance(cond, list) else [cond]


def _line_of(subtrees) -> int:
    for sub in subtrees:
        for c in sub:
            if getattr(c, "line", 0):
                return c.line
    return 0


def _split_commas(tokens: list[Token]) -> list[list[Token]]:
    out: list[list[Token]] = []
    cur: list[Token] = []
    for t in tokens:
        if t.text == ",":
            out.append(cur)
            cur = []
        else:
            cur.append(t)
    out.append(cur)
    return out


def _relines(lines: list[Line], rest: list[Token]) -> list[Line]:
    keep = set(id(t) for t in rest)
    out = []
    for line in lines:
        toks = [t for t in line.tokens if id(t) in keep]
        if toks:
            indent = line.indent if toks[0] is line.tokens[0] else toks[0].col - 1
            out.append(Line(line.number, indent, toks))
    return out


def _parser_for(document: Document, file: str) -> _Parser:
    parser = _Parser("", file)
    parser.doc = Document(file, templates=document.templates)
    parser.vocab = getattr(document.templates, "_vocabulary", None) or Vocabulary(list(document.templates.values()))
    return parser


def _guarded(fn):
    def wrapper(document, text, file=None):
        if not isinstance(text, str) or len(text) > MAX_SOURCE:
            raise LEError("the text is too long (or not text)", file or "<le>", 0, 1)
        try:
            return fn(document, text, file) if file else fn(document, text)
        except RecursionError:
            raise LEError("the text nests too deeply to read", file or "<le>", 0, 1) from None
    wrapper.__doc__ = fn.__doc__
    wrapper.__name__ = fn.__name__
    return wrapper


@_guarded
def parse_question(document: Document, text: str, file: str = "<question>") -> list:
    """Conditions asked outside the document (`which person acquires ... on which date`),
    read with the document's templates; a final full stop is optional."""
    text = text.strip()
    if not text.endswith("."):
        text += "."
    parser = _parser_for(document, file)
    statements = split_statements(lex(text), file)
    if len(statements) != 1 or statements[0].header:
        raise LEError("a question is one statement", file, 1, 1, "ask one question, ending with `.`")
    scope = Scope()
    return parser._conditions(statements[0].lines, scope, "query")


@_guarded
def parse_facts(document: Document, text: str, file: str = "<scenario>") -> list[Rule]:
    """Scenario statements written outside the document (`173 has red light. ...`)."""
    text = text.strip()
    if text and not text.endswith("."):
        text += "."
    parser = _parser_for(document, file)
    out = []
    for st in split_statements(lex(text), file):
        if st.header:
            raise LEError("a section header inside facts", file, st.first.line, st.first.col)
        out.append(parser._statement(st, "scenario:<given>", 0))
    return out


@_guarded
def parse_rule(document: Document, text: str, file: str = "<rule>") -> Rule:
    """One rule or fact written outside the document, read with its templates."""
    parser = _parser_for(document, file)
    statements = split_statements(lex(text), file)
    if len(statements) != 1 or statements[0].header:
        raise LEError("a rule is one statement", file, 1, 1, "end the rule with `.`")
    return parser._statement(statements[0], "kb", 0)
