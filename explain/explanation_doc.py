"""One incident's explanation worded as a JSON-ready document: the verdict in a sentence, a plain
summary, then why, section by section (DESIGN "Reasoning", the paper's Figure 1).

    explanation = inv.explanation(incident)                      # inv = Investigation(store)
    doc = document(incident, explanation, store)
    print(render(doc, "text", "standard"))                       # explain.explanation_formats

This module only words what it is given: the incident's proof trees and scenarios, and what the
reasoner answered about it beyond the verdict (reasoner.explanation: lawful actions, why-not,
counterfactuals, the chain's status). With a store, the evidence table gets chain positions. The
document holds recorded strings as they were recorded; the renderers escape them.
"""
from __future__ import annotations

from typing import Any, Iterable, Mapping

from reasoner import Counterfactual, Explanation
from reasoner.model import FASTEST_MEASURED, Decision, Incident
from reasoner.verdicts import NOT_PROVEN, Verdict
from reasoner.vocabulary import CAN, HAS_SPEED_OF, MUST_NOT, POTENTIALLY_VIOLATES, WOULD_ENDANGER, WOULD_FORCE
from reasoner.wording import term
from store import EventRef

from . import phrases as ph
from . import trees
from .evidence import EvidenceIndex, chain_json, key

IN_CONTROL = {"driver": "a human driver was in control (no automated driving feature was engaged)",
              "self-driving feature": "the self-driving feature was engaged and driving",
              "user-in-charge": "the user-in-charge was driving"}


def document(inc: Incident, explanation: Explanation, store: Any = None) -> dict:
    """The explanation of one incident (Investigation.incidents) from what the reasoner answered
    about it (Investigation.explanation)."""
    return _Builder(inc, explanation, store).build()


class _Builder:
    def __init__(self, inc: Incident, explanation: Explanation, store: Any) -> None:
        self.inc = inc
        self.ex = explanation
        self.store = store
        self.me = term(inc.vehicle)                # the vehicle as proof trees name it
        self.pv_tree = _first_tree(inc.proofs.potential_violation.trees)
        self.verdict_tree = _first_tree(inc.proofs.verdict.trees if inc.proofs.verdict else ())

    # -- the whole document ----------------------------------------------------------------------
    def build(self) -> dict:
        inc = self.inc
        anchor = _anchor_ref(inc)
        self.extra = {self.ex.potential_violation: anchor} if anchor else {}
        self.index = EvidenceIndex(self._all_refs(anchor), self.store, inc.run)
        chain = chain_json(self.ex.chain)
        self._annotate()
        doc: dict[str, Any] = {
            "incident": {"id": inc.id, "run": inc.run, "t": inc.t, "time": ph.clock(inc.t),
                         "day": ph.day(inc.t), "vehicle": inc.vehicle, "action": inc.action,
                         "monitor": inc.monitor, "verdict": inc.verdict, "rule": inc.rule,
                         "rule_name": ph.rule_name(inc.rule), "law": inc.law},
            "potential_violation": self._potential_violation(),
            "measured": self._measured(),
            "validation": self._validation(),
            "penalty": self._penalty(),
            "liability": self._liability(),
            "findings": [{**{k: v for k, v in f.to_json().items() if k != "evidence"},
                          "evidence": self._ids(r.to_json() for r in f.evidence)} for f in inc.findings],
            "why_not": self._why_not(),
            "counterfactuals": self._counterfactuals(),
            "rulebooks": {stage: b.to_json() for stage, b in inc.rulebooks.items()},
        }
        doc["verdict"] = self._verdict_sentence(doc)
        doc["evidence"] = {"chain": chain, "events": self.index.table(self._uses(anchor), self.ex.chain)}
        doc["summary"] = self._summary(doc)
        return doc

    # -- sections -----------------------------------------------------------------------------------
    def _potential_violation(self) -> dict:
        inc = self.inc
        if inc.recorded:
            how = (f"recorded by {ph.who(inc.monitor)} and re-derived from its observation" if inc.rederived
                   else f"recorded by {ph.who(inc.monitor)}, but not re-derivable from its observation")
        else:
            how = f"re-derived from the observations of {ph.who(inc.monitor)}, which recorded none"
        sources = inc.sources
        if sources and inc.found_in == "own-record":
            how = f"found in the vehicle's own record ({sources[0].id}) only: no monitor recorded it"
        elif len(sources) > 1:
            how += (f"; one act, {len(sources)} records of it, judged as one: "
                    + ", ".join(f"{s.id} ({s.how})" for s in sources))
        return {"monitor": inc.monitor, "recorded": inc.recorded, "rederived": inc.rederived,
                "how": how, "found_in": inc.found_in, "sources": [s.to_json() for s in sources],
                "observed": self._facts(inc.scenarios.monitor),
                "rule": inc.rule, "law": inc.law, "tree": self.pv_tree,
                "rulebook": self.ex.monitor_rulebook}

    def _measured(self) -> dict:
        """What the vehicle's history showed (derived facts, each with its method and the
        measurements it rests on) and the margin of the act."""
        m = self.inc.margin
        out: dict[str, Any] = {
            "facts": [{"fact": f.sentence, "method": f.method, "uncertain": f.uncertain,
                       "evidence": self._ids(r.to_json() for r in f.evidence)} for f in self.inc.derived],
            "margin": None if m is None else {**m.to_json(), "text": ph.margin_text(m),
                                              "evidence": self._ids(r.to_json() for r in m.evidence)}}
        if self.inc.second_limb:        # why the act forced or endangered none of them (reasoner/second_limb.py)
            out["second_limb"] = [{**{k: v for k, v in u.to_json().items() if k != "evidence"},
                                   "sentences": list(u.sentences),
                                   "evidence": self._ids(r.to_json() for r in u.evidence)}
                                  for u in self.inc.second_limb]
        return out

    def _validation(self) -> dict | None:
        inc = self.inc
        if inc.proofs.verdict is None:
            return None
        decision = inc.scenarios.action
        return {"judged_on": inc.judged_on, "scenario": self._facts(inc.scenarios.validator),
                "action": inc.action, "lawful": list(self.ex.lawful), "not_lawful": list(self.ex.not_lawful),
                "among_lawful": inc.verdict == Verdict.MITIGATED if inc.verdict != Verdict.DISMISSED else None,
                "why": inc.why, "tree": self.verdict_tree,
                "decision": _decision(decision, self.index) if decision else None,
                "rulebook": self.ex.validator_rulebook}

    def _penalty(self) -> dict | None:
        p = self.inc.penalty
        if not p:
            return None
        points = p.points
        by_law = points if p.points_by_law is None else p.points_by_law
        named = list(p.regulatory_sanctions or ())
        sanctions = ph.join([f"the {n}" for n in named])
        verb = "faces" if len(named) == 1 else "face"
        instead = f" ({sanctions} {verb} regulatory sanctions instead)" if sanctions else ""
        if p.fine_gbp is None and p.fine_gbp_by_law is not None:     # liability.le: offered to no one
            law_sets = f"£{p.fine_gbp_by_law}" + (f" and {by_law} penalty points" if by_law else "")
            text = (f"{ph.with_a(p.offence)} under {p.law or 'the law'}: the fixed penalty the law sets "
                    f"({law_sets}) is a driver's; the {self.inc.liable} is offered none and holds no "
                    f"licence{instead}")
            return {**p.to_json(), "text": text}
        text = f"{ph.with_a(p.offence)} under {p.law or 'the law'}: a fixed penalty of £{p.fine_gbp}"
        if points:
            text += f" and {points} penalty points"
        elif by_law:
            text += (f"; the {by_law} penalty points the law sets are not endorsed on anyone's licence, as "
                     f"the {self.inc.liable} holds none{instead}")
        return {**p.to_json(), "text": text}

    def _liability(self) -> dict:
        inc = self.inc
        control, lia = inc.control, inc.liability
        in_control = control.in_control
        text = IN_CONTROL.get(in_control, f"in control: {in_control}")
        last = control.last_ads_event
        if in_control == "driver" and control.automated:
            text = "the driver was in control: the vehicle's automated driving feature was not engaged"
            if last:
                text += (f" (its last ADS event: {str(last.event).replace('_', ' ')} at "
                         f"{ph.clock(last.t)}{self.index.cite([last.ref(inc.run)])})")
        return {"liable": inc.liable, "parties": list(lia.parties) if lia else [], "in_control": in_control,
                "in_control_text": text,
                "licence_points": list(lia.licence_points) if lia else [],
                "sanctions": list(lia.sanctions) if lia else [],
                "tree": self.liability_tree, "control_evidence": self._ids(
                    [r.to_json() for r in lia.evidence.values()] if lia else [])}

    def _why_not(self) -> list[dict]:
        """The reasoner's answers, each proof node citing its events (the potential violation's own
        tree, for a dismissal, as the section above shows it)."""
        out = []
        for w in self.ex.why_not:
            found = w.to_json()
            if "trees" in found:
                found["trees"] = [self.pv_tree if w.on == "monitor scenario" else self._cited(t) for t in w.trees]
            out.append(found)
        return out

    def _cited(self, node: Mapping[str, Any]) -> dict:
        return {**node, "cites": self._ids(node.get("evidence") or []),
                "children": [self._cited(k) for k in node["children"]]}

    def _counterfactuals(self) -> dict | None:
        if self.ex.counterfactuals is None:
            return None
        return {question: [_worded(cf) for cf in found] for question, found in self.ex.counterfactuals.items()}

    # -- the sentences on top ------------------------------------------------------------------------
    def _manner(self) -> str:
        """How the action was done, from the conditions the potential violation rests on."""
        if self.pv_tree is None or self.pv_tree["status"] == "failed":
            return ""
        bits = [self._measured_speed(data, negated) or ph.manner(data, self.me, negated, text)
                for data, negated, text in self._deciding(trees.conditions(self.pv_tree))]
        said = [b for b in bits if b]
        return (" " + " ".join(said)) if said else ""

    def _measured_speed(self, data: list, negated: bool) -> str | None:
        """A stated speed in the headline gives way to the one that decided: the fastest measured
        speed of the act's stretch (the margin's figure), the stated one beside it where the two
        differ ("at up to 39.3 mph measured (stated: 31 mph)")."""
        m = self.inc.margin
        if negated or data[:1] != [HAS_SPEED_OF.functor] or m is None:
            return None
        fastest = next((v for q, v, _ in m.figures if q == FASTEST_MEASURED), None)
        if fastest is None:
            return None
        stated = ph.value(data[2]) if len(data) > 2 else None
        said = "" if stated in (None, f"{round(fastest):g}") else f" (stated: {stated} mph)"
        return f"at up to {fastest:g} mph measured{said}"

    def _deciding(self, conditions: list[tuple[list, bool, str]]) -> list[tuple[list, bool, str]]:
        """The potential violation's conditions, with its second limb (who was forced or
        endangered) the one the verdict's prohibition rests on: the headline's ground is the
        deciding ground (a Stop raised for forcing one road user and punished for endangering
        another names the other)."""
        limb = {WOULD_FORCE.functor, WOULD_ENDANGER.functor}
        if self.inc.verdict != Verdict.PUNISHABLE or self.verdict_tree is None \
                or not any(data[:1] and data[0] in limb for data, _, _ in conditions):
            return conditions
        prohibition = trees.first(self.verdict_tree, lambda n: n["sentence"][:1] == [MUST_NOT.functor]
                                  and n["status"] == "proved")
        found = [c for c in trees.conditions(prohibition) if c[0][:1] and c[0][0] in limb] if prohibition else []
        if not found:
            return conditions
        return [c for c in conditions if not (c[0][:1] and c[0][0] in limb)] + found

    def _exceptions(self) -> list[str]:
        if self.verdict_tree is None:
            return []
        return [_with_grounds(n) for n in trees.exceptions(self.verdict_tree, MUST_NOT.functor)]

    def _permission(self) -> str:
        """Where no prohibition met an exception, the permission itself: the conditions of the
        rule that proved "V can A" (the paper's "can enter the junction if ... ambulance")."""
        can = trees.first(self.verdict_tree, lambda n: bool(n["sentence"][:1] == [CAN.functor] and n["status"] == "proved"
                          and n.get("label"))) if self.verdict_tree else None
        return " and ".join(k["text"] for k in can["children"]) if can else ""

    def _verdict_sentence(self, doc: dict) -> str:
        inc = self.inc
        v, rule, when = inc.vehicle, ph.rule_name(inc.rule), ph.clock(inc.t)
        did = f"it {ph.past(inc.action)}{self._manner()}"
        if inc.verdict == Verdict.PUNISHABLE:
            return f"Vehicle {v} committed a punishable violation of {rule} at {when}: {did}."
        if inc.verdict == Verdict.MITIGATED:
            because = ph.join(self._exceptions()) or self._permission()
            allowed = (f"which the rules allow because {because}" if because else
                       "which was among the lawful actions open to it there")
            return f"Vehicle {v} committed a mitigated violation of {rule} at {when}: {did}, {allowed}."
        of = f" of {rule}" if inc.rule else ""
        return (f"The potential violation{of} by vehicle {v} ({inc.action}) that {ph.who(inc.monitor)} "
                f"{'recorded' if inc.recorded else 'observed'} at {when} was dismissed: {self._dismissal()}.")

    def _dismissal(self) -> str:
        if self.pv_tree is not None and self.pv_tree["status"] == "failed":
            held = [n["text"] for n in trees.exceptions(self.pv_tree, POTENTIALLY_VIOLATES.functor)]
            if held:
                return f"the monitor's own observation shows that {ph.join(held)}"
        return self.inc.why or "the rules establish no violation"

    def _summary(self, doc: dict) -> list[str]:
        inc = self.inc
        v = inc.vehicle
        out = []
        when = f"{doc['incident']['time']} on {doc['incident']['day']}"
        if inc.verdict == Verdict.DISMISSED:
            out.append(f"{ph.who(inc.monitor, True)} recorded that vehicle {v} potentially violated “{inc.action}” at "
                       f"{when}, but {self._dismissal()}, so there is no violation to answer for.")
        elif inc.sources and inc.found_in == "own-record":
            out.append(f"Vehicle {v}'s own record shows that it {ph.past(inc.action)}{self._manner()} at {when}; "
                       "no monitor recorded it.")
        else:
            seen = "recorded" if inc.recorded else "observed"
            unrecorded = "" if inc.recorded else ", but recorded no potential violation"
            out.append(f"{ph.who(inc.monitor, True)} {seen} vehicle {v} as it {ph.past(inc.action)}"
                       f"{self._manner()} at {when}{unrecorded}.")
        if inc.verdict == Verdict.PUNISHABLE:
            ban = trees.first(self.verdict_tree or {"children": [], "status": "", "sentence": []},
                              lambda n: n["sentence"][:1] == [MUST_NOT.functor] and n["status"] == "proved")
            if ban is not None:
                because = " and ".join(k["text"] for k in ban["children"])
                out.append(f"Nothing recorded made that lawful: under {ph.rule_name(ban.get('label'))}, "
                           f"{ban['text']} when {because}.")
            else:
                out.append(f"Nothing recorded made that lawful: {inc.why}.")
        elif inc.verdict == Verdict.MITIGATED:
            because = ph.join(self._exceptions()) or self._permission()
            out.append(f"That was lawful for {v} there" + (f", because {because}" if because else "") +
                       ", so the violation is mitigated and no penalty follows.")
        if doc["penalty"]:
            out.append(f"It is {doc['penalty']['text']}.")
        if inc.verdict == Verdict.PUNISHABLE:
            lia = doc["liability"]
            out.append(f"The {lia['liable']} is liable: {lia['in_control_text']}.")
        if inc.margin is not None and (inc.verdict != Verdict.DISMISSED or (inc.why or "").startswith(NOT_PROVEN)):
            out.append(f"Measured margin: {ph.margin_text(inc.margin)}.")
        out += self._doubts()
        if inc.findings:
            kinds = ph.join(sorted({f.kind for f in inc.findings}))
            out.append(f"Also found: {kinds} (see Findings).")
        cf = doc.get("counterfactuals") or {}
        if inc.verdict == Verdict.PUNISHABLE:
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
            out.append(f"The record is intact: the run's hash chain verified over all {chain['events']:,} events.")
        else:
            out.append(("WARNING: " if chain["checked"] else "Note: ") + chain["text"] + ".")
        return out

    def _doubts(self) -> list[str]:
        """The contradictions the verdict's proof uses, said in the summary rather than left among
        the findings: a stated fact the measurements contradict stays in the scenario (DESIGN
        "Reasoning": a finding, not a silent override). A verdict that turned on one is not proven
        (dismissed, DESIGN "Weighing"), so one said here is a claim the verdict would reach on the
        measurements too."""
        if self.inc.verdict == Verdict.DISMISSED:
            return []
        used = trees.facts_used(self.pv_tree) | trees.facts_used(self.verdict_tree)
        if self.verdict_tree is not None:     # an exception that held sits under a failed prohibition
            for node in trees.exceptions(self.verdict_tree, MUST_NOT.functor):
                used |= trees.facts_used(node)
        return [f"In doubt: the verdict rests on “{f.fact}”, and the record's measurements contradict it: "
                f"{f.detail.split(', but ', 1)[-1]}. The verdict is the same on what the measurements show, so it "
                "stands; the contradiction is for whoever weighs the evidence (see Findings)."
                for f in self.inc.findings if f.kind == "contradiction" and f.fact in used]

    # -- helpers --------------------------------------------------------------------------------------
    def _facts(self, facts: Iterable[tuple[Any, EventRef]]) -> list[dict]:
        measured = {f.sentence for f in self.inc.derived}
        return [{"fact": s, "evidence": self.index.ids.get(ev.key) if ev else None,
                 **({"measured": True} if s in measured else {})} for s, ev in facts]

    def _ids(self, refs: Iterable[dict]) -> list[str]:
        return [self.index.ids[key(r)] for r in refs if r and key(r) in self.index.ids]

    def _all_refs(self, anchor: dict | None) -> list[dict]:
        inc = self.inc
        refs = [r.to_json() for r in inc.evidence]
        refs += [anchor] if anchor else []
        for stage in (inc.proofs.potential_violation, inc.proofs.verdict):
            for tree in stage.trees if stage else ():
                refs += trees.events_of(tree)
        if inc.liability:
            refs += [r.to_json() for r in inc.liability.evidence.values()]
        for f in inc.findings:
            refs += [r.to_json() for r in f.evidence]
        for u in inc.second_limb:
            refs += [r.to_json() for r in u.evidence]
        return refs

    def _uses(self, anchor: dict | None) -> dict[tuple[str, int], list[str]]:
        inc = self.inc
        uses: dict[tuple[str, int], list[str]] = {}

        def note(ref: EventRef | dict | None, what: str) -> None:
            if ref is None:
                return
            at = ref.key if isinstance(ref, EventRef) else key(ref)
            if what not in uses.setdefault(at, []):
                uses[at].append(what)
        if anchor:
            note(anchor, "the recorded potential violation" if inc.recorded else "the first observation")
        measured = {f.sentence for f in inc.derived}
        for part in (inc.scenarios.monitor, inc.scenarios.vehicle, inc.scenarios.validator):
            for s, ev in part:
                if s not in measured:
                    note(ev, f"“{s}”")
        for f in inc.derived:
            for ev in f.evidence:
                note(ev, f"“{f.sentence}” (measured)")
        if inc.margin is not None:
            for ev in inc.margin.evidence:
                note(ev, "the margin")
        for u in inc.second_limb:
            for ev in u.evidence:
                note(ev, f"the second limb: {u.user}")
        decision = inc.scenarios.action
        if decision:
            note(decision.evidence, f"the decision “{decision.goal}”")
        for s, ev in (inc.liability.evidence.items() if inc.liability else ()):
            note(ev, f"“{s}”")
        for finding in inc.findings:
            for ev in finding.evidence:
                note(ev, f"{finding.kind}")
        return uses

    def _annotate(self) -> None:
        """Copies of the trees whose nodes carry `cites`: the ids (E1, ...) of their events, the
        recorded potential violation for the fact "V potentially violates A"."""
        def copy(node: Mapping[str, Any] | None) -> dict | None:
            if node is None:
                return None
            refs = list(node.get("evidence") or [])
            if not refs and node["status"] == "fact" and node["text"] in self.extra:
                refs = [self.extra[node["text"]]]
            return {**node, "cites": self._ids(refs), "children": [copy(k) for k in node["children"]]}
        self.pv_tree = copy(self.pv_tree)
        self.verdict_tree = copy(self.verdict_tree)
        lia = self.inc.liability
        self.liability_tree = copy(lia.trees[0] if lia and lia.trees else None)


def _first_tree(found: tuple) -> dict | None:
    return found[0] if found else None


def _anchor_ref(inc: Incident) -> dict | None:
    if inc.anchor is not None:
        return inc.anchor.to_json()
    src, _, seq = inc.id.rpartition(":")
    kind = "monitor.potential_violation" if inc.recorded else "monitor.observation"
    return {"run": inc.run, "src": src, "seq": int(seq), "t": inc.t, "kind": kind} if seq.isdigit() else None


def _decision(decision: Decision, index: EvidenceIndex) -> dict:
    return {"goal": decision.goal, "action": decision.action, "permitted": decision.permitted,
            "proceeds": decision.proceeds, "evidence": index.ids.get(decision.evidence.key)}


def _worded(cf: Counterfactual) -> dict:
    changes = [{**c.to_json(), "text": ph.change_clause(c.kind, list(c.data), c.fact,
                                                         list(c.new_data) if c.new_data else None, c.new or "")}
               for c in cf.changes]
    return {"kind": cf.kind, "changes": changes, "text": " and ".join(c["text"] for c in changes)}


def _with_grounds(node: dict) -> str:
    """"253 is used for an emergency purpose (253 is of type ambulance and 253 is on an emergency
    call)": an exception with the facts that made it hold."""
    facts = [k["text"] for k in node["children"] if k["status"] in ("fact", "proved")]
    return node["text"] + (f" ({' and '.join(facts)})" if facts and node.get("rule") is not None else "")
