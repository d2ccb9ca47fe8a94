"""From a recorded run to validated verdicts (the paper's Figure 1).

For each potential violation a monitor recorded: rebuild the Monitor Scenario and re-derive
the potential violation; rebuild the Vehicle Scenario and the Vehicle Action; ask the
validator rules whether the action was among the lawful ones (mitigated) or not (punishable).
"""
from __future__ import annotations

from dataclasses import dataclass

from store import Store

from .engine import Answer, Engine, Rulebook, enrich, get_engine, sha256_text
from .le.sentences import constant, parse_fact
from .le.terms import Atom
from .rulebooks import CURRENT, bundled
from .scenarios import Scenario, monitor_scenario, ref, vehicle_action, vehicle_scenario


@dataclass
class RulebookChoice:
    rulebook: Rulebook
    source: str          # "recorded" (the run's own rules) or "current" (the project's)


class Investigation:
    """Verdicts for the runs of one store; rulebooks are loaded once and shared."""

    def __init__(self, store: Store, engine: Engine | None = None) -> None:
        self.store = store
        self.engine = engine or get_engine()

    def incidents(self, run: str) -> list[dict]:
        pvs = list(self.store.events(run, kinds=["monitor.potential_violation"]))
        return [self.judge(run, pv) for pv in pvs]

    def rulebook_for(self, run: str, sha: str | None) -> RulebookChoice:
        for start in self.store.events(run, kinds=["run.start"]):
            for rb in start["body"].get("rulebooks", []):
                text = rb.get("text")
                if text and (sha is None or sha256_text(text) == sha):
                    return RulebookChoice(self.engine.load(text, rb.get("name", "<recorded>")), "recorded")
        if sha and (stored := self.store.get_rulebook(sha)):
            return RulebookChoice(self.engine.load(stored["text"], stored["name"]), "recorded")
        return RulebookChoice(self.engine.load(bundled(CURRENT), CURRENT), "current")

    def judge(self, run: str, pv: dict) -> dict:
        body = pv["body"]
        vehicle, action, t = str(body["vehicle"]), body["action"], pv["t"]
        choice = self.rulebook_for(run, body.get("rulebook"))
        rb = choice.rulebook
        findings: list[dict] = []
        monitor = monitor_scenario(self.store, run, pv["src"], vehicle, t)
        vscen = vehicle_scenario(self.store, run, vehicle, t)
        decision = vehicle_action(self.store, run, vehicle, t)
        pv_atom = Atom("potentially_violates", (constant([vehicle]), action))

        rederived = self.engine.ask(rb, pv_atom, self._atoms(rb, monitor, findings))
        if not rederived.holds:
            findings.append({"kind": "monitor disagreement", "evidence": [ref(pv)],
                             "detail": "the recorded potential violation does not follow from the "
                                       "monitor's own observation"})
        facts = self._atoms(rb, vscen, findings) + [pv_atom]
        punishable = self._ask(rb, "punishably_violates", vehicle, action, facts)
        mitigated = self._ask(rb, "mitigately_violates", vehicle, action, facts)
        verdict = "punishable" if punishable.holds else "mitigated" if mitigated.holds else "dismissed"
        rule = rb.rule(rederived.proofs[0]["rule"]) if rederived.holds else None
        spawn = next(iter(self.store.events(run, kinds=["entity.spawn"], srcs=[f"vehicle/{vehicle}"])), None)
        return {
            "id": f"{pv['src']}:{pv['seq']}", "run": run, "t": t, "vehicle": vehicle, "action": action,
            "rule": rule.label if rule else None, "law": rule.law if rule else None,
            "verdict": verdict, "penalty": None, "liable": _liable(verdict, spawn),
            "findings": findings,
            "evidence": [ref(e) for e in (pv, decision, spawn) if e] + _fact_refs(monitor, vscen),
            "rulebook": {"name": rb.name, "sha256": rb.sha256, "source": choice.source},
            "scenarios": {"vehicle": vscen.facts, "monitor": monitor.facts,
                          "action": decision["body"] if decision else None},
            "proofs": {"potential_violation": [enrich(t, rb, dict(monitor.facts)) for t in
                                               rederived.proofs[:1] or [rederived.why_not]],
                       "verdict": [enrich(t, rb, dict(vscen.facts)) for t in
                                   (punishable if punishable.holds else mitigated).proofs[:1]
                                   or [punishable.why_not]]},
        }

    def _ask(self, rb: Rulebook, functor: str, vehicle: str, action: str, facts: list[Atom]) -> Answer:
        return self.engine.ask(rb, Atom(functor, (constant([vehicle]), action)), facts)

    @staticmethod
    def _atoms(rb: Rulebook, scenario: Scenario, findings: list[dict]) -> list[Atom]:
        atoms = []
        for sentence, evidence in scenario.facts:
            atom = parse_fact(sentence, rb.document.templates)
            if atom is None:
                findings.append({"kind": "unknown fact", "fact": sentence, "evidence": [evidence],
                                 "detail": "no template of the rulebook fits this sentence"})
            else:
                atoms.append(atom)
        return atoms


def _fact_refs(*scenarios: Scenario) -> list[dict]:
    seen, refs = set(), []
    for scenario in scenarios:
        for _, r in scenario.facts:
            key = (r["src"], r["seq"])
            if key not in seen:
                seen.add(key)
                refs.append(r)
    return refs


def _liable(verdict: str, spawn: dict | None) -> str:
    """Skeleton rule: a punishable violation by a human-driven vehicle is the driver's.

    Liability in LE over the ads.event history (driver, user-in-charge, ASDE, operator) is
    issue 5's `liability.le`; until then an automated vehicle's case is left undetermined.
    """
    if verdict != "punishable":
        return "none"
    driver = (spawn or {}).get("body", {}).get("driver", "human")
    return "driver" if driver == "human" else "undetermined"
