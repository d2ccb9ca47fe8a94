"""One incident's explanation as a JSON-ready document: the verdict in a sentence, a plain summary,
then why, section by section (DESIGN "Reasoning", the paper's Figure 1).

    doc = explanation(incident, inv.rulebook, store)            # inv = Investigation(store)
    print(render(doc, "text", "standard"))                       # explain.render

Everything is taken from the incident's proof trees and scenarios, re-asking the rulebooks only for
what the incident does not carry: the lawful actions of the Validator Scenario, why-not questions
and counterfactuals (reasoner.counterfactuals). The document holds recorded strings as they were
recorded; the renderers escape them.
"""
from __future__ import annotations

from typing import Any, Callable, Iterable

from reasoner.counterfactuals import Counterfactual, QuestionUnreadable, search, why_not
from reasoner.engine import Engine, Rulebook, get_engine
from reasoner.le.render import sentence_text
from reasoner.le.sentences import constant, parse_fact
from reasoner.le.terms import Atom

from . import phrases as ph
from . import trees
from .evidence import EvidenceIndex, chain_status, key

Rulebooks = Callable[[str], "Rulebook | None"]

# DESIGN's core vocabulary: the colours a signal shows (a counterfactual may swap one for another)
COLOURS = ["red", "amber", "green"]
# a vehicle is never imagined a pedestrian
NOT_SWAPPED_IN = {"type": {"pedestrian"}}
IN_CONTROL = {"driver": "a human driver was in control (no automated driving feature was engaged)",
              "self-driving feature": "the self-driving feature was engaged and driving",
              "user-in-charge": "the user-in-charge was driving"}


def explanation(inc: dict, rulebooks: Rulebooks, store: Any = None, *, engine: Engine | None = None,
                why_not_questions: Iterable[str] = (), counterfactuals: bool = True,
                chain: dict | None = None) -> dict:
    """The explanation of one incident (from reasoner.investigation.Investigation.incidents).
    `chain` (evidence.chain_status) saves verifying a run again for each of its incidents."""
    return _Builder(inc, rulebooks, store, engine, counterfactuals).build(list(why_not_questions), chain)


class _Builder:
    def __init__(self, inc: dict, rulebooks: Rulebooks, store: Any, engine: Engine | None,
                 counterfactuals: bool) -> None:
        self.inc = inc
        self.books = rulebooks
        self.store = store
        self.engine = engine
        self.want_cf = counterfactuals
        self.me = constant([inc["vehicle"]])
        self.act = constant(str(inc["action"]).split())
        self.pv_tree = _first_tree(inc["proofs"].get("potential_violation"))
        self.verdict_tree = _first_tree(inc["proofs"].get("verdict"))
        self.validator = self._book("verdict")
        self.monitor = self._book("potential_violation")

    # -- the whole document ----------------------------------------------------------------------
    def build(self, questions: list[str], chain: dict | None = None) -> dict:
        inc = self.inc
        anchor = _anchor_ref(inc)
        extra = {self._pv_text(): anchor} if anchor else {}
        self.index = EvidenceIndex(self._all_refs(anchor), self.store, inc["run"])
        self.extra = extra
        chain = chain if chain is not None else chain_status(self.store, inc["run"])
        self._annotate()
        doc: dict[str, Any] = {
            "incident": {"id": inc["id"], "run": inc["run"], "t": inc["t"], "time": ph.clock(inc["t"]),
                         "day": ph.day(inc["t"]), "vehicle": inc["vehicle"], "action": inc["action"],
                         "monitor": inc["monitor"], "verdict": inc["verdict"], "rule": inc["rule"],
                         "rule_name": ph.rule_name(inc["rule"]), "law": inc.get("law")},
            "potential_violation": self._potential_violation(),
            "validation": self._validation(),
            "penalty": self._penalty(),
            "liability": self._liability(),
            "findings": [{**{k: v for k, v in f.items() if k != "evidence"},
                          "evidence": self._ids(f.get("evidence", []))} for f in inc["findings"]],
            "why_not": self._why_not(questions),
            "counterfactuals": self._counterfactuals() if self.want_cf else None,
            "rulebooks": inc.get("rulebooks", {}),
        }
        doc["verdict"] = self._verdict_sentence(doc)
        doc["evidence"] = {"chain": chain, "events": self.index.table(self._uses(anchor), chain["problem"])}
        doc["summary"] = self._summary(doc)
        return doc

    # -- sections -----------------------------------------------------------------------------------
    def _potential_violation(self) -> dict:
        inc = self.inc
        if inc["recorded"]:
            how = (f"recorded by {ph.who(inc['monitor'])} and re-derived from its observation" if inc["rederived"]
                   else f"recorded by {ph.who(inc['monitor'])}, but not re-derivable from its observation")
        else:
            how = f"re-derived from the observations of {ph.who(inc['monitor'])}, which recorded none"
        return {"monitor": inc["monitor"], "recorded": inc["recorded"], "rederived": inc["rederived"],
                "how": how, "observed": self._facts(inc["scenarios"]["monitor"]),
                "rule": inc["rule"], "law": inc.get("law"), "tree": self.pv_tree,
                "rulebook": self.monitor.name if self.monitor else None}

    def _validation(self) -> dict | None:
        inc = self.inc
        if "verdict" not in inc["proofs"]:
            return None
        decision = inc["scenarios"].get("action")
        lawful, unlawful = self._lawful_actions()
        return {"judged_on": inc.get("judged_on"), "scenario": self._facts(inc["scenarios"]["validator"]),
                "action": inc["action"], "lawful": lawful, "not_lawful": unlawful,
                "among_lawful": inc["verdict"] == "mitigated" if inc["verdict"] != "dismissed" else None,
                "why": inc.get("why"), "tree": self.verdict_tree,
                "decision": _decision(decision, self.index) if decision else None,
                "rulebook": self.validator.name if self.validator else None}

    def _penalty(self) -> dict | None:
        p = self.inc.get("penalty")
        if not p:
            return None
        points = p.get("points", 0)
        by_law = p.get("points_by_law", points)
        text = f"{ph.with_a(p['offence'])} under {p.get('law') or 'the law'}: a fixed penalty of £{p['fine_gbp']}"
        if points:
            text += f" and {points} penalty points"
        elif by_law:
            named = list(p.get("regulatory_sanctions") or [])
            sanctions = ph.join([f"the {n}" for n in named])
            verb = "faces" if len(named) == 1 else "face"
            text += (f"; the {by_law} penalty points the law sets are not endorsed on anyone's licence, as "
                     f"the {self.inc['liable']} holds none" + (f" ({sanctions} {verb} regulatory sanctions "
                                                               "instead)" if sanctions else ""))
        return {**p, "text": text}

    def _liability(self) -> dict:
        inc = self.inc
        control = inc.get("control") or {}
        lia = inc.get("liability") or {}
        in_control = control.get("in_control", "unknown")
        text = IN_CONTROL.get(in_control, f"in control: {in_control}")
        last = control.get("last_ads_event")
        if in_control == "driver" and control.get("automated"):
            text = "the driver was in control: the vehicle's automated driving feature was not engaged"
            if last:
                text += (f" (its last ADS event: {str(last.get('event', '')).replace('_', ' ')} at "
                         f"{ph.clock(last['t'])}{self.index.cite([{**last, 'run': inc['run']}])})")
        return {"liable": inc["liable"], "parties": lia.get("parties", []), "in_control": in_control,
                "in_control_text": text,
                "licence_points": lia.get("licence_points", []), "sanctions": lia.get("sanctions", []),
                "tree": self.liability_tree, "control_evidence": self._ids(
                    [r for r in lia.get("evidence", {}).values() if r])}

    def _why_not(self, questions: list[str]) -> list[dict]:
        out = []
        inc = self.inc
        if not questions and inc["verdict"] == "mitigated" and self.validator is not None \
                and "must_not" in self.validator.document.templates:
            # why the prohibition did not apply: the question a reader of a mitigated verdict asks
            questions = [self.validator.render(Atom("must_not", (self.me, self.act)))]
        if not questions and inc["verdict"] == "dismissed" and self.pv_tree is not None:
            out.append({"question": self.pv_tree["text"], "holds": self.pv_tree["status"] != "failed",
                        "trees": [self.pv_tree], "rulebook": self.monitor.name if self.monitor else None,
                        "on": "monitor scenario"})
        for q in questions:
            out.append(self.ask(q))
        return out

    def ask(self, question: str) -> dict:
        """One why-not question on the Validator Scenario (an unreadable one says so)."""
        if self.validator is None:
            return {"question": question, "error": "no validator rulebook judged this incident"}
        try:
            found = why_not(self._engine(), self.validator, question, self._validator_atoms(),
                            self._evidence_map())
        except QuestionUnreadable as exc:
            return {"question": question, "error": str(exc)}
        found["trees"] = [self._cited(t) for t in found["trees"]]
        return {**found, "rulebook": self.validator.name, "on": "validator scenario"}

    def _cited(self, node: dict) -> dict:
        return {**node, "cites": self._ids(node.get("evidence") or []),
                "children": [self._cited(k) for k in node["children"]]}

    def _counterfactuals(self) -> dict | None:
        inc = self.inc
        if self.validator is None or inc["verdict"] == "dismissed":
            return None
        engine = self._engine()
        facts = self._validator_atoms()
        pv = Atom("potentially_violates", (self.me, self.act))
        can = Atom("can", (self.me, self.act))
        opts = {"values": {"colour": COLOURS}, "exclude": NOT_SWAPPED_IN}
        out: dict[str, list] = {}
        if inc["verdict"] == "punishable":
            out["lawful"] = self._cfs(search(engine, self.validator, facts, can, True, self.me, fixed=[pv], **opts),
                                      self.validator)
            if self.monitor is not None:
                mfacts = self._atoms(self.monitor, inc["scenarios"]["monitor"])
                found = search(engine, self.monitor, mfacts, pv, False, self.me, **opts)
                out["no_potential_violation"] = self._cfs(found, self.monitor)
        else:       # mitigated: only the cheap question, one change
            out["punishable"] = self._cfs(search(engine, self.validator, facts, can, False, self.me, fixed=[pv],
                                                 max_size=1, **opts), self.validator)
        return out

    def _cfs(self, found: list[Counterfactual], rb: Rulebook) -> list[dict]:
        out = []
        for cf in found:
            changes = []
            for c in cf.changes:
                old = [c.fact.functor, *c.fact.args]
                new = [c.new.functor, *c.new.args] if c.new else None
                changes.append({"kind": c.kind, "fact": rb.render(c.fact),
                                "new": rb.render(c.new) if c.new else None, "controlled": c.controlled,
                                "text": ph.change_clause(c.kind, old, rb.render(c.fact), new,
                                                         rb.render(c.new) if c.new else "")})
            out.append({"kind": cf.kind, "changes": changes, "text": " and ".join(c["text"] for c in changes)})
        return out

    # -- the sentences on top ------------------------------------------------------------------------
    def _manner(self) -> str:
        """How the action was done, from the conditions the potential violation rests on."""
        if self.pv_tree is None or self.pv_tree["status"] == "failed":
            return ""
        bits = [ph.manner(data, self.me, negated, text) for data, negated, text in trees.conditions(self.pv_tree)]
        bits = [b for b in bits if b]
        return (" " + " ".join(bits)) if bits else ""

    def _exceptions(self) -> list[str]:
        if self.verdict_tree is None:
            return []
        return [_with_grounds(n) for n in trees.exceptions(self.verdict_tree, "must_not")]

    def _permission(self) -> str:
        """Where no prohibition met an exception, the permission itself: the conditions of the
        rule that proved "V can A" (the paper's "can enter the junction if ... ambulance")."""
        can = trees.first(self.verdict_tree, lambda n: n["sentence"][:1] == ["can"] and n["status"] == "proved"
                          and n.get("label")) if self.verdict_tree else None
        return " and ".join(k["text"] for k in can["children"]) if can else ""

    def _verdict_sentence(self, doc: dict) -> str:
        inc = self.inc
        v, rule, when = inc["vehicle"], ph.rule_name(inc["rule"]), ph.clock(inc["t"])
        did = f"it {ph.past(inc['action'])}{self._manner()}"
        if inc["verdict"] == "punishable":
            return f"Vehicle {v} committed a punishable violation of {rule} at {when}: {did}."
        if inc["verdict"] == "mitigated":
            because = ph.join(self._exceptions()) or self._permission()
            allowed = (f"which the rules allow because {because}" if because else
                       "which was among the lawful actions open to it there")
            return f"Vehicle {v} committed a mitigated violation of {rule} at {when}: {did}, {allowed}."
        of = f" of {rule}" if inc["rule"] else ""
        return (f"The potential violation{of} by vehicle {v} ({inc['action']}) that {ph.who(inc['monitor'])} "
                f"{'recorded' if inc['recorded'] else 'observed'} at {when} was dismissed: {self._dismissal()}.")

    def _dismissal(self) -> str:
        if self.pv_tree is not None and self.pv_tree["status"] == "failed":
            held = [n["text"] for n in trees.exceptions(self.pv_tree, "potentially_violates")]
            if held:
                return f"the monitor's own observation shows that {ph.join(held)}"
        return self.inc.get("why") or "the rules establish no violation"

    def _summary(self, doc: dict) -> list[str]:
        inc = self.inc
        v = inc["vehicle"]
        out = []
        when = f"{doc['incident']['time']} on {doc['incident']['day']}"
        if inc["verdict"] == "dismissed":
            out.append(f"{ph.who(inc['monitor'], True)} recorded that vehicle {v} potentially violated “{inc['action']}” at "
                       f"{when}, but {self._dismissal()}, so there is no violation to answer for.")
        else:
            seen = "recorded" if inc["recorded"] else "observed"
            unrecorded = "" if inc["recorded"] else ", but recorded no potential violation"
            out.append(f"{ph.who(inc['monitor'], True)} {seen} vehicle {v} as it {ph.past(inc['action'])}"
                       f"{self._manner()} at {when}{unrecorded}.")
        if inc["verdict"] == "punishable":
            ban = trees.first(self.verdict_tree or {"children": [], "status": "", "sentence": []},
                              lambda n: n["sentence"][:1] == ["must_not"] and n["status"] == "proved")
            if ban is not None:
                because = " and ".join(k["text"] for k in ban["children"])
                out.append(f"Nothing recorded made that lawful: under {ph.rule_name(ban.get('label'))}, "
                           f"{ban['text']} when {because}.")
            else:
                out.append(f"Nothing recorded made that lawful: {inc.get('why')}.")
        elif inc["verdict"] == "mitigated":
            because = ph.join(self._exceptions()) or self._permission()
            out.append(f"That was lawful for {v} there" + (f", because {because}" if because else "") +
                       ", so the violation is mitigated and no penalty follows.")
        if doc["penalty"]:
            out.append(f"It is {doc['penalty']['text']}.")
        if inc["verdict"] == "punishable":
            lia = doc["liability"]
            out.append(f"The {lia['liable']} is liable: {lia['in_control_text']}.")
        if inc["findings"]:
            kinds = ph.join(sorted({f["kind"] for f in inc["findings"]}))
            out.append(f"Also found: {kinds} (see Findings).")
        cf = doc.get("counterfactuals") or {}
        if inc["verdict"] == "punishable":
            lawful = [c for c in cf.get("lawful", []) if c["kind"] == "circumstance"]
            own = [c for c in cf.get("lawful", []) + cf.get("no_potential_violation", []) if c["kind"] == "controlled"]
            if lawful:
                out.append(f"It would have been lawful {lawful[0]['text']}.")
            if own:
                then = ("it would have been lawful" if own[0] in cf.get("lawful", []) else
                        "there would have been no potential violation")
                out.append(f"Within {v}'s own control: {own[0]['text']}, {then}.")
        chain = doc["evidence"]["chain"]
        if chain["verified"]:
            out.append(f"The record is intact: the run's hash chain verified over all {chain['events']} events.")
        else:
            out.append(("WARNING: " if chain["checked"] else "Note: ") + chain["text"] + ".")
        return out

    # -- helpers --------------------------------------------------------------------------------------
    def _book(self, stage: str) -> Rulebook | None:
        sha = (self.inc["proofs"].get(stage) or {}).get("rulebook")
        return self.books(sha) if sha else None

    def _engine(self) -> Engine:
        if self.engine is None:
            self.engine = get_engine()
        return self.engine

    def _pv_text(self) -> str:
        rb = self.validator or self.monitor
        atom = Atom("potentially_violates", (self.me, self.act))
        return rb.render(atom) if rb else sentence_text(atom)

    def _atoms(self, rb: Rulebook, facts: list) -> list[Atom]:
        out = []
        for sentence, _ in facts:
            try:
                atom = parse_fact(sentence, rb.document.templates) if isinstance(sentence, str) else None
            except Exception:       # a hostile sentence: the investigation reported it as unknown
                atom = None
            if atom is not None:
                out.append(atom)
        return out

    def _validator_atoms(self) -> list[Atom]:
        return self._atoms(self.validator, self.inc["scenarios"]["validator"]) + [
            Atom("potentially_violates", (self.me, self.act))]

    def _evidence_map(self) -> dict:
        return {s: ev for s, ev in self.inc["scenarios"]["validator"]}

    def _lawful_actions(self) -> tuple[list[str], list[str]]:
        """The actions the validator rulebook speaks of, split by whether `V can A` holds on the
        Validator Scenario: the paper's Lawful Actions (of those the rules name)."""
        if self.validator is None:
            return [], []
        actions = [self.act]
        for rule in self.validator.document.rules:
            h = rule.head
            if h.functor in ("can", "must_not", "potentially_violates") and len(h.args) == 2 \
                    and isinstance(h.args[1], str) and h.args[1] not in actions:
                actions.append(h.args[1])
        facts = self._validator_atoms()
        lawful, unlawful = [], []
        for act in actions:
            (lawful if self._engine().holds(self.validator, Atom("can", (self.me, act)), facts)
             else unlawful).append(str(act))
        return lawful, unlawful

    def _facts(self, facts: list) -> list[dict]:
        return [{"fact": s, "evidence": self.index.ids.get(key(ev)) if ev else None} for s, ev in facts]

    def _ids(self, refs: Iterable[dict]) -> list[str]:
        return [self.index.ids[key(r)] for r in refs if r and key(r) in self.index.ids]

    def _all_refs(self, anchor: dict | None) -> list[dict]:
        inc = self.inc
        refs = list(inc.get("evidence", []))
        refs += [anchor] if anchor else []
        for stage in inc["proofs"].values():
            for tree in stage.get("trees", []):
                refs += trees.events_of(tree)
        lia = inc.get("liability") or {}
        refs += [r for r in (lia.get("evidence") or {}).values() if r]
        for f in inc["findings"]:
            refs += f.get("evidence", [])
        return refs

    def _uses(self, anchor: dict | None) -> dict[tuple[str, int], list[str]]:
        inc = self.inc
        uses: dict[tuple[str, int], list[str]] = {}

        def note(ref: dict | None, what: str) -> None:
            if ref and what not in uses.setdefault(key(ref), []):
                uses[key(ref)].append(what)
        if anchor:
            note(anchor, "the recorded potential violation" if inc["recorded"] else "the first observation")
        for part in ("monitor", "vehicle", "validator"):
            for s, ev in inc["scenarios"][part]:
                note(ev, f"“{s}”")
        decision = inc["scenarios"].get("action")
        if decision:
            note(decision.get("evidence"), f"the decision “{decision.get('goal')}”")
        for s, ev in ((inc.get("liability") or {}).get("evidence") or {}).items():
            note(ev, f"“{s}”")
        for f in inc["findings"]:
            for ev in f.get("evidence", []):
                note(ev, f"{f['kind']}")
        return uses

    def _annotate(self) -> None:
        """Copies of the trees whose nodes carry `cites`: the ids (E1, ...) of their events, the
        recorded potential violation for the fact "V potentially violates A"."""
        def copy(node: dict | None) -> dict | None:
            if node is None:
                return None
            refs = list(node.get("evidence") or [])
            if not refs and node["status"] == "fact" and node["text"] in self.extra:
                refs = [self.extra[node["text"]]]
            return {**node, "cites": self._ids(refs), "children": [copy(k) for k in node["children"]]}
        self.pv_tree = copy(self.pv_tree)
        self.verdict_tree = copy(self.verdict_tree)
        lia = self.inc.get("liability") or {}
        self.liability_tree = copy((lia.get("trees") or [None])[0])


def _first_tree(stage: dict | None) -> dict | None:
    if not stage or not stage.get("trees"):
        return None
    return stage["trees"][0]


def _anchor_ref(inc: dict) -> dict | None:
    src, _, seq = inc["id"].rpartition(":")
    kind = "monitor.potential_violation" if inc["recorded"] else "monitor.observation"
    for ref in inc.get("evidence", []):
        if ref["src"] == src and str(ref["seq"]) == seq:
            return ref
    return {"run": inc["run"], "src": src, "seq": int(seq), "t": inc["t"], "kind": kind} if seq.isdigit() else None


def _decision(decision: dict, index: EvidenceIndex) -> dict:
    ev = decision.get("evidence")
    return {"goal": decision.get("goal"), "action": decision.get("action"), "permitted": decision.get("permitted"),
            "proceeds": decision.get("proceeds"), "evidence": index.ids.get(key(ev)) if ev else None}


def _with_grounds(node: dict) -> str:
    """"253 is used for an emergency purpose (253 is of type ambulance and 253 is on an emergency
    call)": an exception with the facts that made it hold."""
    facts = [k["text"] for k in node["children"] if k["status"] in ("fact", "proved")]
    return node["text"] + (f" ({' and '.join(facts)})" if facts and node.get("rule") is not None else "")
