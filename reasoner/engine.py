"""The Prolog side of the reasoner: rulebooks loaded into SWI-Prolog through janus_swi.

One engine per process (janus embeds a single Prolog).  Rulebooks are compiled to data in
Python and built into clauses by `prolog/engine.pl`; each lives in a module named by the
sha256 of its LE text, so a run can be judged by exactly the rules it recorded while other
versions stay loaded beside it.
"""
from __future__ import annotations

import hashlib
from dataclasses import dataclass
from pathlib import Path

from .le.document import parse_document
from .le.terms import Atom, Cond, Document, Var
from .prolog_home import import_janus

ENGINE_PL = Path(__file__).with_name("prolog") / "engine.pl"


@dataclass
class Rulebook:
    """A loaded rulebook: its parsed document and the Prolog module holding it."""

    name: str
    sha256: str
    module: str
    document: Document

    def rule(self, rule_id):
        return None if rule_id is None else self.document.rules[rule_id]


@dataclass
class Answer:
    """Every proof of a question (JSON-ready trees), or why it has none."""

    proofs: list[dict]
    why_not: dict | None

    @property
    def holds(self) -> bool:
        return bool(self.proofs)


def sha256_text(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def atom_data(atom: Atom) -> list:
    return [atom.functor, *(("var", a.name) if isinstance(a, Var) else a for a in atom.args)]


def cond_data(cond: Cond):
    if cond.atom is not None:
        return ("pos", atom_data(cond.atom))
    return ("not", [cond_data(c) for c in cond.negated])


class Engine:
    """Loads rulebooks once each and answers questions against a scenario of facts."""

    def __init__(self) -> None:
        self._janus = import_janus()
        self._call("load_files(F, [if(not_loaded)]), gaps_engine:new_rulebook(gaps_probe, [])",
                   F=str(ENGINE_PL))
        self._loaded: dict[str, Rulebook] = {}

    def load(self, text: str, name: str = "<le>") -> Rulebook:
        sha = sha256_text(text)
        if sha in self._loaded:
            return self._loaded[sha]
        doc = parse_document(text, name)
        rb = Rulebook(name, sha, f"le_{sha[:16]}", doc)
        decls = [(t.functor, t.arity) for t in doc.templates.values()]
        self._call("gaps_engine:new_rulebook(M, D)", M=rb.module, D=decls)
        for rule_id, rule in enumerate(doc.rules):
            body = [cond_data(c) for c in rule.body]
            self._call("gaps_engine:add_rule(M, I, H, B)", M=rb.module, I=rule_id,
                       H=atom_data(rule.head), B=body)
        self._loaded[sha] = rb
        return rb

    def ask(self, rb: Rulebook, goal: Atom, facts: list[Atom]) -> Answer:
        result = self._call("gaps_engine:ask(M, F, G, P, W)", M=rb.module,
                            F=[atom_data(f) for f in facts], G=atom_data(goal))
        return Answer(result["P"], result["W"])

    def _call(self, query: str, **inputs):
        result = self._janus.query_once(query, inputs)
        if not result.get("truth"):
            raise RuntimeError(f"Prolog query failed: {query}")
        return result


_engine: Engine | None = None


def get_engine() -> Engine:
    """The process's engine, started on first use so that commands without rules stay fast."""
    global _engine
    if _engine is None:
        _engine = Engine()
    return _engine
