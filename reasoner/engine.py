"""The Prolog side of the reasoner: rulebooks loaded into SWI-Prolog through janus_swi.

One engine per process (janus embeds a single Prolog), safe to ask from several threads at once
(a Dask worker's executor threads, by default as many as its CPUs): each thread that asks gets a
Prolog engine of its own, attached on its first question and kept for the thread's life
(`_Threads`), and a rulebook is loaded once under a lock.  Rulebooks are compiled to data in
Python and built into clauses by `prolog/engine.pl`; each lives in a module named by the
sha256 of its LE text, so a run can be judged by exactly the rules it recorded while other
versions stay loaded beside it.  A scenario is data too: asserted for one question into a
thread-local context and retracted after it.
"""
from __future__ import annotations

import hashlib
import threading
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Mapping, Sequence

from store import EventRef, GapsError

from .le.compile import atom_data, body_data, fact_data, predicates
from .le.document import parse_document
from .le.errors import LEError
from .le.render import atom_list, sentence_text
from .le.render_memo import ShapeMemo
from .le.parsed import Document
from .le.terms import Atom, Rule
from .prolog_home import import_janus

ENGINE_PL = Path(__file__).with_name("prolog") / "engine.pl"


class QuestionError(GapsError, RuntimeError):
    """A question could not be answered (it ran past the engine's limits, or is malformed)."""


@dataclass
class Rulebook:
    """A loaded rulebook: its parsed document and the Prolog module holding it."""

    name: str
    sha256: str
    module: str
    document: Document
    _shapes: ShapeMemo = field(default_factory=ShapeMemo, repr=False, compare=False)

    def rule(self, rule_id):
        if rule_id is None or isinstance(rule_id, str) or not 0 <= rule_id < len(self.document.rules):
            return None
        return self.document.rules[rule_id]

    def render(self, data) -> str:
        """Any goal or answer data (or an Atom) as an LE sentence with this rulebook's templates,
        rendered once per shape (le/render_memo.py: a simulation or a judgement renders a hundred
        thousand sentences a minute, alike but for their numbers)."""
        if type(data) is Atom:
            data = atom_list(data)
        if type(data) is list:
            return self._shapes.text(data, self._sentence)
        return sentence_text(data, self.document)

    def _sentence(self, data) -> str:
        return sentence_text(data, self.document)

    def source(self, rule_id) -> dict | None:
        rule = self.rule(rule_id)
        return {"file": self.name, "line": rule.line} if rule else None

    def scenario(self, name: str) -> list[Rule]:
        try:
            return self.document.scenarios[name].rules
        except KeyError:
            known = ", ".join(self.document.scenarios) or "none"
            raise LEError(f"no scenario {name!r} in {self.name} (scenarios: {known})", self.name) from None

    def query(self, name: str):
        if name in self.document.unreadable_queries:
            raise self.document.unreadable_queries[name]
        try:
            return self.document.queries[name]
        except KeyError:
            known = ", ".join(self.document.queries) or "none"
            raise LEError(f"no query {name!r} in {self.name} (queries: {known})", self.name) from None


@dataclass
class Answer:
    """The first proof of a question (a JSON-ready tree, in a list), or why it has none."""

    proofs: list[dict]
    why_not: dict | None

    @property
    def holds(self) -> bool:
        return bool(self.proofs)


@dataclass
class QueryResult:
    """The answers to a query as LE sentences (one per proof), with proof trees when asked."""

    answers: list[str]
    bindings: list = field(default_factory=list)       # the answers' data
    proofs: list = field(default_factory=list)         # per answer: list of trees
    why_not: list | None = None                        # trees, when there is no answer

    def as_dict(self) -> dict:
        out = {"answers": self.answers}
        if self.proofs:
            out["proofs"] = self.proofs
        if self.why_not is not None:
            out["why_not"] = self.why_not
        return out


def enrich(tree: dict, rb: Rulebook, evidence: Mapping[str, EventRef] | None = None) -> dict:
    """A proof tree as DESIGN's JSON: each node also gets its English `text`, the `label` of its
    rule ("HC 176"), the `source` line of the LE it came from (rule stays the rule's index) and,
    for a fact, the `evidence` that recorded it (from `evidence`: sentence -> event ref, written
    as JSON here because the tree is JSON)."""
    rule = rb.rule(tree.get("rule"))
    text = rb.render(tree["sentence"])
    cited = list(tree.get("evidence", []))
    if evidence and tree["status"] == "fact" and text in evidence:
        cited.append(evidence[text].to_json())
    return {"sentence": tree["sentence"], "text": text, "status": tree["status"],
            "rule": tree.get("rule"), "label": rule.label if rule else None,
            "source": rb.source(tree.get("rule")), "evidence": cited,
            "children": [enrich(k, rb, evidence) for k in tree["children"]],
            **({"truncated": True} if tree.get("truncated") else {})}


def sha256_text(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


class _Threads(threading.local):
    """Which of this process's threads have a Prolog engine attached for good.

    janus_swi attaches a Prolog engine to the calling thread for the length of one `query_once`
    (created and destroyed every call), and `apply_once` attaches none: asked from any thread
    but the one that started Prolog, `holds` dereferenced a thread without an engine and the
    process died of SIGSEGV (janus_swi 1.5.3; a plain `dask worker` runs tasks on two executor
    threads here). `janus.attach_engine()` once per thread gives it an engine until it exits:
    every call works, and a thread's calls stop paying an engine's creation each. Each engine has
    its own thread-local scenario (prolog/engine.pl), so threads asking at once do not mix facts."""

    attached: bool = False


class Engine:
    """Loads rulebooks once each and answers questions against a scenario of facts."""

    def __init__(self) -> None:
        self._janus = import_janus()
        self._threads = _Threads()
        self._loading = threading.RLock()
        self._on_thread()
        self._call("load_files(F, [if(not_loaded)]), gaps_engine:new_rulebook(gaps_probe, [])",
                   F=str(ENGINE_PL))
        self._loaded: dict[str, Rulebook] = {}
        self._renamed: dict[tuple[str, str], Rulebook] = {}   # the same text loaded under other names

    # -- loading --------------------------------------------------------------------------
    def load(self, text: str, name: str = "<le>") -> Rulebook:
        """Parse, check and load a rulebook (once per text); an LEError loads nothing. The same text
        loaded under another name is the same module, named as this caller names it: what a report
        or a citation (`validators.le:12`) shows must not depend on what the process loaded first."""
        with self._loading:                  # two threads loading one text would build one module twice
            return self._load(text, name)

    def _load(self, text: str, name: str) -> Rulebook:
        sha = sha256_text(text)
        if sha in self._loaded:
            first = self._loaded[sha]
            if first.name == name:
                return first
            return self._renamed.setdefault((sha, name), replace(first, name=name))
        doc = parse_document(text, name)
        rb = Rulebook(name, sha, f"le_{sha[:16]}", doc)
        try:
            self._call("gaps_engine:new_rulebook(M, D)", M=rb.module, D=predicates(doc))
            rules = [(i, atom_data(r.head), body_data(r.body)) for i, r in enumerate(doc.rules)]
            for start in range(0, len(rules), 500):
                self._call("gaps_engine:add_rules(M, R)", M=rb.module, R=rules[start:start + 500])
        except Exception as exc:
            self._janus.query_once("gaps_engine:drop_rulebook(M)", {"M": rb.module})
            text = str(exc)
            if "le_reserved" in text:
                raise LEError(f"a template compiles to a Prolog built-in predicate ({text[:200]})", name, 0, 1,
                              "change the template's words") from None
            raise
        self._loaded[sha] = rb
        return rb

    # -- asking ---------------------------------------------------------------------------
    def ask(self, rb: Rulebook, goal: Atom, facts: list) -> Answer:
        """One sentence with its proof tree: the first proof (the one a search for every proof
        lists first), or why there is none."""
        result = self._guarded("gaps_engine:ask(M, F, G, P, W)", M=rb.module,
                               F=self._facts(facts), G=atom_data(goal))
        return Answer(result["P"], result["W"])

    def ask_first(self, rb: Rulebook, goals: Sequence[Atom], facts: list) -> tuple[int, Answer]:
        """The first of these sentences with a proof, on one scenario: its index and its first
        proof, as asking `holds` and then `ask` of each in turn gives them; (-1, what `ask` gives
        for the first) when none has a proof. The facts are sent and indexed once."""
        result = self._guarded("gaps_engine:ask_first(M, F, G, I, P, W)", M=rb.module,
                               F=self._facts(facts), G=[atom_data(g) for g in goals])
        return result["I"], Answer(result["P"], result["W"])

    def first_holding(self, rb: Rulebook, goals: Sequence[Atom], facts: list) -> int:
        """The index of the first of these sentences `holds` says holds, or -1; one scenario."""
        return self._guarded("gaps_engine:first_holding(M, F, G, I)", M=rb.module,
                             F=self._facts(facts), G=[atom_data(g) for g in goals])["I"]

    def holds(self, rb: Rulebook, goal: Atom, facts: list) -> bool:
        """Plain yes/no for one sentence: the fastest question."""
        self._on_thread()
        try:
            return self._janus.apply_once("gaps_engine", "holds", rb.module, self._facts(facts),
                                          atom_data(goal)) == "true"
        except self._janus.PrologError as exc:
            raise QuestionError(_prolog_message(exc)) from None

    def holds_each(self, rb: Rulebook, atoms: Sequence[Atom],
                   questions: Sequence[Sequence[int]]) -> list[bool | QuestionError]:
        """Plain yes/no for many sentences, each on its own scenario, in one Prolog call (a
        regression asks thousands; a call each was a janus round trip and every fact shipped
        and built again for each question it is in). A question is the places among `atoms` of
        its goal and then of its facts; each is asked as `holds` asks it, and where `holds` would
        raise, its answer is the QuestionError it would raise (the caller raises it where it
        would have asked: the others are answered all the same)."""
        data = [atom_data(a) for a in atoms]
        self._on_thread()
        try:
            answers = self._janus.apply_once("gaps_engine", "holds_each", rb.module, data, questions)
        except self._janus.PrologError as exc:
            raise QuestionError(_prolog_message(exc)) from None
        return [a == "true" if type(a) is str else QuestionError(_message(a["error"])) for a in answers]

    def answers(self, rb: Rulebook, body: list, facts: list, explain: bool = False, *,
                texts: bool = True) -> QueryResult:
        """Every way the conditions hold (answers rendered as LE, unless `texts` is False: a caller
        that reads only the bindings), with proofs if `explain`."""
        conds = body_data(body)
        facts_d = self._facts(facts)
        if not explain:
            result = self._guarded("gaps_engine:ask_plain(M, F, C, A)", M=rb.module, F=facts_d, C=conds)
            data = result["A"]
            return QueryResult([self._answer_text(rb, d) for d in data] if texts else [], data)
        result = self._guarded("gaps_engine:ask_proofs(M, F, C, A, W)", M=rb.module, F=facts_d, C=conds)
        found = _proved(result["A"], result["W"])
        found.answers = [self._answer_text(rb, d) for d in found.bindings]
        return found

    def answers_all(self, rb: Rulebook, questions: Sequence[tuple[list, bool]], facts: list) -> list[QueryResult]:
        """Several questions (conditions, explain) on one scenario, each answered as `answers`
        answers it with `texts` False; the facts are sent and indexed once."""
        data = [("proofs" if explain else "plain", body_data(body)) for body, explain in questions]
        results = self._guarded("gaps_engine:ask_all(M, F, Q, R)", M=rb.module, F=self._facts(facts), Q=data)["R"]
        return [_proved(*result) if explain else QueryResult([], result)
                for (_, explain), result in zip(questions, results)]

    def query(self, rb: Rulebook, query: str, scenario: str | None = None,
              facts: list | None = None, explain: bool = False) -> QueryResult:
        """A query of the document by name, on one of its scenarios (and/or extra facts)."""
        q = rb.query(query)
        statements = list(rb.scenario(scenario)) if scenario is not None else []
        return self.answers(rb, q.body, statements + list(facts or []), explain)

    def prolog_text(self, rb: Rulebook) -> str:
        """The rulebook's clauses as Prolog text, each after the LE line it came from."""
        out = [f"% {rb.name} (sha256 {rb.sha256}), module {rb.module}"]
        for i, rule in enumerate(rb.document.rules):
            text = self._call("gaps_engine:clause_text(M, I, T)", M=rb.module, I=i)["T"]
            label = f" [{rule.label}]" if rule.label else ""
            out.append(f"% {rb.name}:{rule.line}{label}\n{text.rstrip()}")
        return "\n".join(out) + "\n"

    # -- helpers --------------------------------------------------------------------------
    @staticmethod
    def _facts(facts: list) -> list:
        out = []
        for i, f in enumerate(facts):
            if isinstance(f, Atom):
                out.append(atom_data(f))
            elif isinstance(f, Rule):
                out.append(fact_data(f, f"s{i}"))
            else:
                raise TypeError(f"a fact is an Atom or a scenario Rule, not {type(f).__name__}")
        return out

    @staticmethod
    def _answer_text(rb: Rulebook, conds_data: list) -> str:
        return " and ".join(rb.render(c) for c in conds_data)

    def _guarded(self, query: str, **inputs):
        try:
            return self._call(query, **inputs)
        except self._janus.PrologError as exc:
            raise QuestionError(_prolog_message(exc)) from None

    def _on_thread(self) -> None:
        """This thread's own Prolog engine, attached on its first question (see _Threads)."""
        if not self._threads.attached:
            self._janus.attach_engine()
            self._threads.attached = True

    def _call(self, query: str, **inputs):
        self._on_thread()
        result = self._janus.query_once(query, inputs)
        if not result.get("truth"):
            raise RuntimeError(f"Prolog query failed: {query}")
        return result


def _proved(pairs: list, why) -> QueryResult:
    """ask_proofs' answer (Data-Trees pairs, and why not: @none when there are answers), without texts."""
    return QueryResult([], [p[0] for p in pairs], [p[1] for p in pairs], why if isinstance(why, list) else None)


def _prolog_message(exc) -> str:
    return _message(str(exc))


def _message(text: str) -> str:
    """What a QuestionError says of a Prolog error, from the error's text."""
    if "integer_bits" in text:
        return ("the question computed an integer of more than 4096 bits, the engine's limit "
                "(a rule may multiply without end)")
    if "le_limit" in text:
        return "the question ran past the engine's inference limit (a rule may recurse without end)"
    if "le_resource" in text or "resource_error" in text:
        return "the question ran out of Prolog stack (a rule may recurse without end)"
    return f"the engine could not answer: {text[:300]}"


_engine: Engine | None = None
_starting = threading.Lock()


def get_engine() -> Engine:
    """The process's engine, started on first use so that commands without rules stay fast (and
    once, when two threads ask for it first at the same moment)."""
    global _engine
    if _engine is None:
        with _starting:
            if _engine is None:
                _engine = Engine()
    return _engine
