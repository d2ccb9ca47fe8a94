"""From a recorded run to validated verdicts (the paper's Figure 1), from the store alone.

    inv = Investigation(store)                 # or Investigation(store, rules=["my.le"])
    for incident in inv.incidents("demo-001"):
        print(incident["verdict"], incident["rule"], incident["liable"])

An incident is a potential violation: recorded on line by a monitor, or re-derived off line from
the monitor's observations (episodes.py); both, normally. For each, at its time t, from the
store's state at t (store.state.state_at):

1. the Monitor Scenario re-derives the potential violation (monitor stage); a recorded one that
   the monitor's own observation does not support is *dismissed*;
2. the Validator Scenario (the Vehicle Scenario with what the monitor witnessed, perception.py)
   decides *punishable* (the action is not among the lawful ones) or *mitigated* (it is);
3. a punishable one gets its penalty (penalties stage) and who is liable (liability stage, over
   the ads.event history: control.py);
4. findings (perception fault, decision fault, monitor disagreement, missing evidence, unknown
   fact), each with the events it rests on.

The verdicts depend only on the events, never on the order or batches they arrived in: the state
is a fold in (t, seq, src) order and the episodes are read in that order too.
"""
from __future__ import annotations

from typing import Any, Callable, Iterable

from store import CollectorPaused, Store, Timeline

from .control import ROLE, control_at, liability_facts, role
from .engine import Answer, Engine, Rulebook, enrich, get_engine
from .episodes import Episode, Rederiver, episodes, match
from .facts import FactReader
from .findings import Gaps, decision_fault, missing_evidence
from .le.render import arg_text
from .le.sentences import constant
from .le.terms import Atom, Cond, Var
from .perception import corrected, dispute_finding, witnessed_functors
from .stages import RuleSet, current_rulebooks, given_rulebooks, recorded_rulebooks
from .scenarios import (Scenario, entity, has_perception, monitor_scenario, ref, spawn_facts,
                        vehicle_action, vehicle_scenario)

LIABLE_ORDER = tuple(ROLE.values())   # who is named `liable` when several parties are


class Investigation:
    """Verdicts for the runs of one store. Rulebooks and parsed facts are loaded once and shared."""

    def __init__(self, store: Store, engine: Engine | None = None, rules: Iterable[str] | None = None) -> None:
        self.store = store
        self.engine = engine or get_engine()
        self.reader = FactReader()
        self._given = given_rulebooks(self.engine, rules or [])
        self._current = current_rulebooks(self.engine)
        self._rulesets: dict[str, RuleSet] = {}
        self._witnessed: dict[str, set[str]] = {}
        self.problems: dict[str, list[str]] = {}

    # -- public ---------------------------------------------------------------------------
    def incidents(self, run: str, progress: Callable[[int, int], None] | None = None) -> list[dict]:
        """Every potential violation of the run, judged; ordered by time. `progress(done, total)`
        is called as the incidents are judged (after the pass over the observations)."""
        recorded = list(self.store.events(run, kinds=["monitor.potential_violation"]))
        rs = self.ruleset(run, recorded)
        monitor = rs["monitor"]
        eps: list[Episode] = []
        if monitor is not None:
            rederiver = Rederiver(self.engine, monitor.rulebook, self.reader)
            with CollectorPaused():    # hundreds of thousands of parsed observations, no cycles
                eps = list(episodes(self.store.events(run, kinds=["monitor.observation"]), rederiver))
        todo = [(pv["t"], pv["src"], pv, episode) for pv, episode in match(eps, recorded)]
        todo += [(ep.first["t"], ep.monitor, None, ep) for ep in eps if not ep.recorded]
        todo.sort(key=lambda item: (item[0], _anchor_key(item[2], item[3])))
        timeline, gaps = Timeline(self.store, run), Gaps(self.store, run)
        found = []
        for t, src, pv, ep in todo:
            found.append(self._judge(run, rs, gaps, timeline.at(t), t, src, pv, ep))
            if progress is not None:
                progress(len(found), len(todo))
        return found

    def ruleset(self, run: str, recorded: list[dict] | None = None) -> RuleSet:
        """The rulebooks each stage of this run is judged with (given, recorded, current).
        `recorded`: the run's potential violations, if the caller has read them already."""
        if run not in self._rulesets:
            problems: list[str] = []
            if recorded is None:
                recorded = list(self.store.events(run, kinds=["monitor.potential_violation"]))
            shas = {e["body"].get("rulebook") for e in recorded if isinstance(e["body"].get("rulebook"), str)}
            books = recorded_rulebooks(self.engine, self.store, run, sorted(shas), problems)
            self._rulesets[run] = RuleSet(self.engine, self._given, books, self._current)
            self.problems[run] = problems
        return self._rulesets[run]

    def rulebook(self, sha256: str) -> Rulebook | None:
        """A rulebook any stage used, by its sha256 (for rendering proofs)."""
        for rs in self._rulesets.values():
            if sha256 in rs.by_sha:
                return rs.by_sha[sha256]
        return None

    # -- one incident ---------------------------------------------------------------------
    def _judge(self, run: str, rs: RuleSet, gaps: Gaps, state: dict, t: int, monitor_src: str,
               pv: dict | None, episode: Episode | None) -> dict:
        body = pv["body"] if pv else {}
        vehicle = str(body.get("vehicle")) if pv else episode.vehicle
        action = str(body.get("action")) if pv else episode.action
        anchor = pv if pv else episode.first
        findings: list[dict] = []
        unknown: list[dict] = []
        me, act = constant([vehicle]), constant(action.split())

        mscen = self._monitor_scenario(state, monitor_src, vehicle, t, pv, episode)
        pv_answer, rule = self._rederive(rs, mscen, me, act, unknown)
        rederived = pv_answer is not None and pv_answer.holds
        if pv and not rederived:
            findings.append(_disagreement(pv, mscen, recorded=True))
        if not pv:
            findings.append(_disagreement(episode.first, mscen, recorded=False))

        vscen = vehicle_scenario(state, vehicle)
        decision = vehicle_action(state, vehicle)
        control = control_at(entity(state, vehicle), t)
        incident: dict[str, Any] = {
            "id": f"{anchor['src']}:{anchor['seq']}", "run": run, "t": t, "vehicle": vehicle,
            "action": action, "monitor": monitor_src, "recorded": pv is not None, "rederived": rederived,
            "rule": rule.label if rule else None, "law": rule.law if rule else None,
            "verdict": "dismissed", "why": None, "penalty": None, "liable": "none", "liability": None,
            "control": control, "findings": findings, "evidence": [],
            "judged_on": "vehicle scenario" if has_perception(state, vehicle) else "monitor scenario",
            "rulebook": None, "rulebooks": rs.describe(),
            "scenarios": {"vehicle": vscen.facts, "monitor": mscen.facts, "validator": [], "action": decision},
            "proofs": {"potential_violation": _proofs(pv_answer, rs["monitor"], mscen)},
        }
        if self.problems.get(run):
            incident["rulebook_problems"] = self.problems[run]
        if not rederived and pv:
            incident["why"] = ("the monitor's own observation does not show the potential violation it "
                               "recorded" if mscen.facts else
                               "no observation of the vehicle by the monitor supports the potential "
                               "violation it recorded")
        else:
            self._validate(incident, rs, state, vehicle, me, act, vscen, mscen, unknown)
        fault = decision_fault(self.engine, self.reader, rs.vehicle_rulebook((decision or {}).get("rulebook")),
                               vehicle, decision if decision and decision.get("action") == action else None,
                               vscen.facts, unknown)
        if fault:
            findings.append(fault)
        findings += missing_evidence(gaps, [f"vehicle/{vehicle}", monitor_src], t,
                                     {f"vehicle/{vehicle}": _last_seen(state, vehicle)})
        findings += _dedup_unknown(unknown)
        incident["evidence"] = _evidence(anchor, run, mscen, vscen, decision, control, incident)
        return incident

    def _monitor_scenario(self, state: dict, monitor_src: str, vehicle: str, t: int,
                          pv: dict | None, episode: Episode | None) -> Scenario:
        if episode is not None:
            obs = episode.observation_at(t)
            scenario = Scenario()
            scenario.add(obs["body"].get("facts"), ref(obs))
            return scenario
        scenario = monitor_scenario(state, monitor_src, vehicle)
        if not scenario.facts and pv is not None and isinstance(pv["body"].get("facts"), list):
            scenario.add(pv["body"]["facts"], ref(pv))
        return scenario

    def _rederive(self, rs: RuleSet, mscen: Scenario, me: Any, act: Any,
                  unknown: list[dict]) -> tuple[Answer | None, Any]:
        monitor = rs["monitor"]
        if monitor is None:
            return None, None
        rb = monitor.rulebook
        answer = self.engine.ask(rb, Atom("potentially_violates", (me, act)), self.reader.atoms(rb, mscen.facts, unknown))
        rule = rb.rule(answer.proofs[0]["rule"]) if answer.holds else None
        return answer, rule

    def _validate(self, incident: dict, rs: RuleSet, state: dict, vehicle: str, me: Any, act: Any,
                  vscen: Scenario, mscen: Scenario, unknown: list[dict]) -> None:
        choice = rs["validator"]
        if choice is None:
            incident["why"] = "no rulebook defines punishable and mitigated violations"
            return
        rb = choice.rulebook
        incident["rulebook"] = choice.describe()
        mine = self.reader.pairs(rb, vscen.facts, unknown)
        seen = self.reader.pairs(rb, mscen.facts, unknown)
        pv_atom = Atom("potentially_violates", (me, act))
        if incident["judged_on"] == "vehicle scenario":
            monitor_rb = rs["monitor"].rulebook if rs["monitor"] else rb
            others = {constant([src.split("/", 1)[1]]) for src in state["entities"] if "/" in src} - {me}
            facts, disputes = corrected(mine, seen, self._witnessed_by(monitor_rb), me, others)
        else:
            spawn = (entity(state, vehicle) or {}).get("spawn")
            facts = ([(a, ref(spawn, state["run"], "entity.spawn")) for a in self.reader.known(rb, spawn_facts(
                vehicle, spawn["body"]))] if spawn else []) + seen
            disputes = []
        verdict, answer = self._verdict(rb, me, act, [a for a, _ in facts] + [pv_atom], proofs=True)
        incident["verdict"] = verdict
        rendered = [(rb.render(a), ev) for a, ev in facts]
        incident["scenarios"]["validator"] = rendered
        evidence = dict(rendered)
        incident["proofs"]["verdict"] = {"rulebook": rb.sha256, "trees": [
            enrich(tree, rb, evidence) for tree in (answer.proofs[:1] or [answer.why_not] if answer else [])]}
        if disputes:
            alt, _ = self._verdict(rb, me, act, [a for a, _ in mine] + [pv_atom], proofs=False)
            if alt != verdict:
                incident["findings"].append(dispute_finding(disputes, rb, alt, verdict))
        if incident["rule"] is None and answer and answer.holds:
            rule = rb.rule(answer.proofs[0]["rule"])
            incident["rule"], incident["law"] = (rule.label, rule.law) if rule else (None, None)
        incident["why"] = {
            "punishable": f"\"{action_text(rb, me, act)}\" is not among the lawful actions of the Validator Scenario",
            "mitigated": f"\"{action_text(rb, me, act)}\" is among the lawful actions of the Validator Scenario",
            "dismissed": "the validator rules establish neither a punishable nor a mitigated violation",
        }[verdict]
        if verdict == "punishable":
            self._penalty_and_liability(incident, rs, vehicle, me, act, [s for s, _ in rendered])

    def _witnessed_by(self, monitor_rb: Rulebook) -> set[str]:
        if monitor_rb.sha256 not in self._witnessed:
            self._witnessed[monitor_rb.sha256] = witnessed_functors(monitor_rb)
        return self._witnessed[monitor_rb.sha256]

    def _verdict(self, rb: Rulebook, me: Any, act: Any, atoms: list[Atom], proofs: bool) -> tuple[str, Answer | None]:
        if not proofs:
            if self.engine.holds(rb, Atom("punishably_violates", (me, act)), atoms):
                return "punishable", None
            return ("mitigated" if self.engine.holds(rb, Atom("mitigately_violates", (me, act)), atoms)
                    else "dismissed"), None
        punishable = self.engine.ask(rb, Atom("punishably_violates", (me, act)), atoms)
        if punishable.holds:
            return "punishable", punishable
        mitigated = self.engine.ask(rb, Atom("mitigately_violates", (me, act)), atoms)
        return ("mitigated" if mitigated.holds else "dismissed"), (mitigated if mitigated.holds else punishable)

    def _penalty_and_liability(self, incident: dict, rs: RuleSet, vehicle: str, me: Any, act: Any,
                               sentences: list[str]) -> None:
        punish = Atom("punishably_violates", (me, act))
        penalty = None
        if (pen := rs["penalties"]) is not None:
            penalty = self._penalty(pen.rulebook, me, self.reader.known(pen.rulebook, sentences) + [punish])
        liability = None
        if (lia := rs["liability"]) is not None:
            shown = [(s, self._control_ref(incident, basis)) for s, basis in
                     liability_facts(vehicle, incident["control"])]
            facts = self.reader.known(lia.rulebook, [s for s, _ in shown]) + [punish]
            liability = self._liability(lia.rulebook, me, act, facts, {s: r for s, r in shown if r})
            incident["liable"] = next((r for r in LIABLE_ORDER if r in liability["parties"]),
                                      liability["parties"][0] if liability["parties"] else "none")
            incident["liability"] = liability
        if penalty is not None:
            if liability is not None:
                penalty["points_by_law"] = penalty["points"]
                penalty["points"] = penalty["points"] if liability["licence_points"] else 0
                penalty["regulatory_sanctions"] = liability["sanctions"]
            incident["penalty"] = penalty

    def _penalty(self, rb: Rulebook, me: Any, facts: list[Atom]) -> dict | None:
        question = [Cond(atom=Atom("incurs_a_fixed_penalty_of_pounds_and_penalty_points_for",
                                   (me, Var("amount"), Var("points"), Var("offence"))))]
        found = []
        for binding in self.engine.answers(rb, question, facts).bindings:
            _, _, amount, points, offence = binding[0]
            law = self.engine.answers(rb, [Cond(atom=Atom("is_an_offence_under", (offence, Var("law"))))], facts)
            found.append({"offence": arg_text(offence), "law": arg_text(law.bindings[0][0][2]) if law.bindings
                          else None, "fine_gbp": amount, "points": points})
        if not found:
            return None
        found.sort(key=lambda p: (-_num(p["fine_gbp"]), -_num(p["points"]), p["offence"]))
        return {**found[0], "offences": found} if len(found) > 1 else found[0]

    @staticmethod
    def _control_ref(incident: dict, basis: str) -> dict | None:
        """The event behind a liability fact: the spawn, or an ads.event of the control status."""
        if basis == "spawn":
            return next((ev for _, ev in incident["scenarios"]["vehicle"] if ev["kind"] == "entity.spawn"), None)
        piece = incident["control"].get(basis)
        return ref(piece, incident["run"], "ads.event") if piece else None

    def _liability(self, rb: Rulebook, me: Any, act: Any, facts: list[Atom], evidence: dict) -> dict:
        def parties(functor: str) -> list[str]:
            question = [Cond(atom=Atom(functor, (Var("party"), act, me)))]
            return [role(arg_text(b[0][1])) for b in self.engine.answers(rb, question, facts).bindings]

        liable = self.engine.answers(rb, [Cond(atom=Atom("is_liable_for_the_violation_of_by",
                                                         (Var("party"), act, me)))], facts, explain=True)
        return {"parties": [role(arg_text(b[0][1])) for b in liable.bindings],
                "licence_points": parties("gets_licence_penalty_points_for_the_violation_of_by"),
                "sanctions": parties("faces_regulatory_sanctions_for_the_violation_of_by"),
                "facts": [rb.render(a) for a in facts],
                "rulebook": rb.sha256,
                "evidence": evidence,
                "trees": [enrich(tree, rb, evidence) for trees in liable.proofs[:1] for tree in trees]}

def action_text(rb: Rulebook, me: Any, act: Any) -> str:
    return rb.render(Atom("can", (me, act))) if "can" in rb.document.templates else f"{me} can {act}"


def _dedup_unknown(unknown: list[dict]) -> list[dict]:
    """One finding per unknown sentence and event, however many stages tried to read it."""
    seen, out = set(), []
    for f in unknown:
        key = (f["fact"], tuple((e["src"], e["seq"]) for e in f["evidence"]))
        if key not in seen:
            seen.add(key)
            out.append(f)
    return out


def _disagreement(event: dict, mscen: Scenario, recorded: bool) -> dict:
    if recorded:
        detail = ("the monitor recorded this potential violation, but the monitor rules do not derive it from "
                  "its own observation of the vehicle" if mscen.facts else
                  "the monitor recorded this potential violation without any observation of the vehicle to "
                  "support it")
    else:
        detail = ("the monitor rules derive a potential violation from the monitor's observations, but the "
                  "monitor did not record one")
    return {"kind": "monitor disagreement", "detail": detail,
            "evidence": [ref(event)] + [ev for _, ev in mscen.facts[:1]]}


def _proofs(answer: Answer | None, choice, scenario: Scenario) -> dict:
    if answer is None or choice is None:
        return {"rulebook": None, "trees": []}
    rb = choice.rulebook
    trees = answer.proofs[:1] or ([answer.why_not] if answer.why_not else [])
    return {"rulebook": rb.sha256, "trees": [enrich(tree, rb, scenario.evidence) for tree in trees]}


def _last_seen(state: dict, vehicle: str) -> int | None:
    record = entity(state, vehicle) or {}
    times = [record[k]["t"] for k in ("state", "perception", "decision") if record.get(k)]
    return max(times) if times and not record.get("despawned") else None


def _anchor_key(pv: dict | None, episode: Episode | None) -> str:
    anchor = pv if pv else episode.first
    return f"{anchor['src']}:{anchor['seq']:020d}"


def _num(value: Any) -> float:
    return value if isinstance(value, (int, float)) else 0


def _evidence(anchor: dict, run: str, mscen: Scenario, vscen: Scenario, decision: dict | None,
              control: dict, incident: dict) -> list[dict]:
    refs = [ref(anchor)] + [ev for _, ev in (*mscen.facts, *vscen.facts)]
    if decision:
        refs.append(decision["evidence"])
    if control.get("last_ads_event"):
        refs.append(ref(control["last_ads_event"], run, "ads.event"))
    for f in incident["findings"]:
        refs += f.get("evidence", [])
    seen, out = set(), []
    for r in refs:
        key = (r["src"], r["seq"])
        if key not in seen:
            seen.add(key)
            out.append(r)
    return out
