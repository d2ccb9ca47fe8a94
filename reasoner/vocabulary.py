"""The sentences the code asks the rulebooks or writes for them, in one place, in the rulebooks' words.

Code that asks "does V potentially violate A?" or writes "V is of type T" depends on a template of
a rulebook in `reasoner/rules/`. Each such sentence is named here once, declared exactly as the
rulebook declares its template, with the file that defines it; `tests/reasoner/test_vocabulary.py`
fails when a rulebook renames or drops one, so a rename in LE breaks the build, not a verdict.

Three kinds are named:
- the stages' questions and their answers (`potentially_violates`, `punishably_violates`, `can`,
  the penalty and the liability sentences), which the rulebooks conclude;
- the input sentences the code writes: DESIGN's core vocabulary ("Facts are Logical English
  sentences"), which every producer may state, and the further ones the reasoner or the
  simulation states (docs/vocabulary.md lists them for producers);
- the sentences an explanation words in its own way (explain/phrases.py: "against a red light"),
  where the rulebook's template alone does not give the English a verdict needs.

`S.atom(*args)` is the term the engine is asked with (data, never Prolog text); `S.text(*args)` is
the sentence as a producer records it; `S.functor` is what a parsed fact or proof node carries.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from .le.templates import Template, parse_template, render
from .le.terms import Atom

# What other rooms take from here (tests/architecture/test_walls.py): a sentence's type, and each
# sentence the simulation's agents write or ask (sim_replay/av.py, watchers.py, simulation.py,
# paper.py) or an explanation words in its own way (explain/phrases.py, explanation_doc.py,
# act_data.py); the rest are the reasoner's own questions and statements
__all__ = [
    "CAN", "CROSSED_THE_STOP_LINE_ON", "EXIT_OF_THE_BOX_JUNCTION_IS_CLEAR", "HAS_CROSSED_THE_STOP_LINE", "HAS_LIGHT",
    "HAS_SIGN", "HAS_SPEED_OF", "HAS_STOPPED_AT_THE_STOP_LINE", "HAS_STOPPED_BEFORE_ENTERING_THE_MAJOR_ROAD",
    "IS_APPROACHING", "IS_AT_A_BOX_JUNCTION", "IS_DRIVING_ITSELF", "IS_IN_THE_JUNCTION", "IS_OF_TYPE",
    "IS_ON_AN_EMERGENCY_CALL", "IS_ON_THE_MAIN_ROAD", "IS_STOPPED", "IS_STOPPED_IN_THE_BOX_JUNCTION",
    "IS_TOO_CLOSE_TO_STOP", "MUST_NOT", "POTENTIALLY_VIOLATES", "SPEED_LIMIT_IS", "STOP_LINE_NOT_CLEARLY_VISIBLE",
    "Sentence", "WOULD_ENDANGER", "WOULD_FORCE",
]


@dataclass(frozen=True)
class Sentence:
    """One template of a bundled rulebook the code relies on; `doc` says what it means there."""

    template: str               # as the rulebook declares it: "*a vehicle* is of type *a type*"
    rulebook: str               # the file in reasoner/rules/ that defines it
    doc: str
    parsed: Template = field(init=False, repr=False, compare=False)
    pattern: str = field(init=False, repr=False, compare=False)
    arity: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        parsed = parse_template(self.template)
        if any(isinstance(p, str) and ("{" in p or "}" in p) for p in parsed.parts):
            raise ValueError(f"a template with braces cannot be written by Sentence.text: {self.template!r}")
        object.__setattr__(self, "parsed", parsed)
        object.__setattr__(self, "pattern", render(parsed, ["{}"] * parsed.arity))
        object.__setattr__(self, "arity", parsed.arity)     # text() runs millions of times in sim_replay

    @property
    def functor(self) -> str:
        return self.parsed.functor

    def atom(self, *args: object) -> Atom:
        """The sentence as a term for the engine, one argument per slot."""
        if len(args) != self.arity:
            raise TypeError(f"{self.template!r} takes {self.arity} arguments, not {len(args)}")
        return Atom(self.functor, tuple(args))

    def text(self, *args: object) -> str:
        """The sentence as a producer records it (no full stop)."""
        if len(args) != self.arity:
            raise TypeError(f"{self.template!r} takes {self.arity} arguments, not {len(args)}")
        return self.pattern.format(*args)


# --- the stages' questions and answers ------------------------------------------------------

POTENTIALLY_VIOLATES = Sentence(
    "*a vehicle* potentially violates *an action*", "monitors.le",
    "the monitor stage's question: the Monitor Scenario shows V doing A where a rule forbids it")
PUNISHABLY_VIOLATES = Sentence(
    "*a vehicle* punishably violates *an action*", "validators.le",
    "the validator stage's verdict: a potential violation no exception excuses")
MITIGATELY_VIOLATES = Sentence(
    "*a vehicle* mitigately violates *an action*", "validators.le",
    "the validator stage's verdict: a potential violation an exception of the Highway Code excuses")
CAN = Sentence(
    "*a vehicle* can *an action*", "highway_code.le",
    "the vehicle stage's question: whether the Highway Code permits V to do A (the goal of a vehicle.decision)")
MUST_NOT = Sentence(
    "*a vehicle* must not *an action*", "highway_code.le",
    "a prohibition of the Highway Code, the rules `can` is the exception to")
INCURS_FIXED_PENALTY = Sentence(
    "*a vehicle* incurs a fixed penalty of *an amount* pounds and *a number* penalty points for *an offence*",
    "penalties.le",
    "the penalties stage's question: the fine and points a punishable violation carries, and the offence")
IS_AN_OFFENCE_UNDER = Sentence(
    "*an offence* is an offence under *a law*", "penalties.le",
    "the statute that makes an offence an offence")
IS_LIABLE = Sentence(
    "*a party* is liable for the violation of *an action* by *a vehicle*", "liability.le",
    "the liability stage's question: who answers for a punishable violation")
GETS_LICENCE_POINTS = Sentence(
    "*a party* gets licence penalty points for the violation of *an action* by *a vehicle*", "liability.le",
    "the party whose licence takes the points (a human driver, not the self-driving entity)")
IS_OFFERED_A_FIXED_PENALTY = Sentence(
    "*a party* is offered a fixed penalty for the violation of *an action* by *a vehicle*", "liability.le",
    "the party offered the fixed penalty (the driver; a self-driving entity or operator is sanctioned instead)")
FACES_REGULATORY_SANCTIONS = Sentence(
    "*a party* faces regulatory sanctions for the violation of *an action* by *a vehicle*", "liability.le",
    "the party the regulator sanctions (Automated Vehicles Act 2024: the self-driving entity or operator)")

# The question each stage of an investigation asks (reasoner/stages.py: a stage is answered by
# the rulebook that has a rule concluding its sentence).
STAGES: dict[str, Sentence] = {
    "monitor": POTENTIALLY_VIOLATES,
    "validator": PUNISHABLY_VIOLATES,
    "vehicle": CAN,
    "penalties": INCURS_FIXED_PENALTY,
    "liability": IS_LIABLE,
}

# --- DESIGN's core vocabulary ---------------------------------------------------------------

IS_OF_TYPE = Sentence(
    "*a vehicle* is of type *a type*", "highway_code.le",
    "V's type: car, ambulance, fire_engine, police_car, bus, cyclist, pedestrian")
IS_ON_AN_EMERGENCY_CALL = Sentence(
    "*a vehicle* is on an emergency call", "highway_code.le",
    "V is being used for an emergency purpose (TSRGD 2016 Sch 14 Pt 1 para 5(6))")
HAS_LIGHT = Sentence(
    "*a vehicle* has *a colour* light", "highway_code.le",
    "the signal facing V shows C (red and amber together: both sentences)")
HAS_SIGN = Sentence(
    "*a vehicle* has a *a sign* sign", "highway_code.le",
    "a sign faces V: stop, give way")
IS_STOPPED = Sentence(
    "*a vehicle* is stopped", "highway_code.le",
    "V's speed is 0")
HAS_CROSSED_THE_STOP_LINE = Sentence(
    "*a vehicle* has crossed the stop line", "highway_code.le",
    "V is over the stop line")
IS_IN_THE_JUNCTION = Sentence(
    "*a vehicle* is in the junction", "highway_code.le",
    "V is inside the junction")
IS_APPROACHING = Sentence(
    "*a road user* is approaching *a vehicle*", "highway_code.le",
    "road user U approaches V: evidence for give way and for TSRGD para 5(5)")
HAS_SPEED_OF = Sentence(
    "*a vehicle* has speed of *a number*", "highway_code.le",
    "V's speed in mph")
SPEED_LIMIT_IS = Sentence(
    "the speed limit is *a number*", "highway_code.le",
    "the speed limit where V is, in mph")
IS_DRIVING_ITSELF = Sentence(
    "*a vehicle* is driving itself", "highway_code.le",
    "an automated driving system is engaged and in control of V")

CORE: tuple[Sentence, ...] = (IS_OF_TYPE, IS_ON_AN_EMERGENCY_CALL, HAS_LIGHT, HAS_SIGN, IS_STOPPED,
                              HAS_CROSSED_THE_STOP_LINE, IS_IN_THE_JUNCTION, IS_APPROACHING, HAS_SPEED_OF,
                              SPEED_LIMIT_IS, IS_DRIVING_ITSELF)

# --- further input sentences the code writes (docs/vocabulary.md) ----------------------------

CROSSED_THE_STOP_LINE_ON = Sentence(
    "*a vehicle* crossed the stop line on *a colour* light", "highway_code.le",
    "the signal facing V showed C when V crossed its stop line (red and amber together: both sentences); "
    "the act a signal's prohibition judges (TSRGD 2016 Sch 14 Pt 1 para 5(3), HC 175's amber exception)")
HAS_STOPPED_BEFORE_ENTERING_THE_MAJOR_ROAD = Sentence(
    "*a vehicle* has stopped before entering the major road", "highway_code.le",
    "V stopped before entering the major road, where a Stop sign's line is not clearly visible (HC 171)")
STOP_LINE_NOT_CLEARLY_VISIBLE = Sentence(
    "the stop line is not clearly visible for *a vehicle*", "highway_code.le",
    "the transverse line of V's Stop sign is worn or hidden (TSRGD 2016 Sch 9 Pt 7 para 1)")
IS_TOO_CLOSE_TO_STOP = Sentence(
    "*a vehicle* is too close to the stop line to stop safely", "highway_code.le",
    "stopping might cause a collision, so V may go on at amber (HC 175)")
HAS_STOPPED_AT_THE_STOP_LINE = Sentence(
    "*a vehicle* has stopped at the stop line", "highway_code.le",
    "V came to a complete stop at a Stop sign's line before crossing it (HC 171)")
WOULD_FORCE = Sentence(
    "*a vehicle* would force *a road user* to change speed or course", "highway_code.le",
    "V proceeding would cause U to change speed or course to avoid an accident (TSRGD Sch 14 para 5(5))")
WOULD_ENDANGER = Sentence(
    "*a vehicle* would endanger *a person*", "highway_code.le",
    "V proceeding would be likely to endanger P (TSRGD Sch 14 para 5(5), Sch 9 Pt 7 para 1)")
MONITOR_OBSERVED_LIGHT = Sentence(
    "the monitor observed *a colour* light for *a vehicle*", "validators.le",
    "the light the monitor recorded for V, beside the vehicle's own perception of it")
HAS_A_LIGHT_PERCEPTION_FAULT = Sentence(
    "*a vehicle* has a perception fault about the light", "validators.le",
    "the light V perceived differs from the one the monitor observed")

# Judgements about what V's proceeding would cause, or whether it could still stop: open texture
# (DESIGN "Reasoning"), no camera's observation of a moment. The history measures them
# (reasoner/derived.py) and a vehicle that asks its rulebook states them as its own predictions; a
# monitor's silence on one is therefore no evidence against the vehicle's (reasoner/perception.py).
OPEN_TEXTURE: tuple[Sentence, ...] = (WOULD_FORCE, WOULD_ENDANGER, IS_TOO_CLOSE_TO_STOP)

# liability.le's inputs, stated from the vehicle's spawn and ads.event history (reasoner/control.py)
IS_THE_DRIVER_OF = Sentence(
    "*a person* is the driver of *a vehicle*", "liability.le",
    "P is driving V (no self-driving feature engaged)")
IS_THE_USER_IN_CHARGE_OF = Sentence(
    "*a person* is the user-in-charge of *a vehicle*", "liability.le",
    "P sits in V's driving seat while its self-driving feature drives (Automated Vehicles Act 2024)")
IS_THE_AUTHORISED_SELF_DRIVING_ENTITY_FOR = Sentence(
    "*an entity* is the authorised self-driving entity for *a vehicle*", "liability.le",
    "E answers for how V's self-driving feature drives (Automated Vehicles Act 2024)")
IS_THE_NO_USER_IN_CHARGE_OPERATOR_OF = Sentence(
    "*an entity* is the no-user-in-charge operator of *a vehicle*", "liability.le",
    "E operates V, which needs no user-in-charge (Automated Vehicles Act 2024)")
TRANSITION_DEMAND_EXPIRED = Sentence(
    "a transition demand for *a vehicle* has expired unanswered", "liability.le",
    "V asked its user to take over and the time to respond ran out: the user is now the driver")

# --- sentences an explanation words beside the action (explain/phrases.py) -------------------

IS_ON_THE_MAIN_ROAD = Sentence(
    "*a road user* is on the main road", "highway_code.le",
    "U is on the major road at a junction (HC 172: give way to it)")
IS_AT_A_BOX_JUNCTION = Sentence(
    "*a vehicle* is at a box junction", "monitors.le",
    "V is at a junction marked with yellow criss-cross lines (HC 174)")
IS_STOPPED_IN_THE_BOX_JUNCTION = Sentence(
    "*a vehicle* is stopped in the box junction", "monitors.le",
    "V has stopped inside the yellow box (HC 174)")
EXIT_OF_THE_BOX_JUNCTION_IS_CLEAR = Sentence(
    "the exit of the box junction is clear for *a vehicle*", "monitors.le",
    "V's exit road beyond the box is clear (HC 174)")
EXPLAINED: tuple[Sentence, ...] = (IS_ON_THE_MAIN_ROAD, IS_AT_A_BOX_JUNCTION, IS_STOPPED_IN_THE_BOX_JUNCTION,
                                   EXIT_OF_THE_BOX_JUNCTION_IS_CLEAR)

SENTENCES: tuple[Sentence, ...] = (
    *STAGES.values(), MITIGATELY_VIOLATES, MUST_NOT, IS_AN_OFFENCE_UNDER, GETS_LICENCE_POINTS,
    IS_OFFERED_A_FIXED_PENALTY, FACES_REGULATORY_SANCTIONS, *CORE, CROSSED_THE_STOP_LINE_ON,
    HAS_STOPPED_BEFORE_ENTERING_THE_MAJOR_ROAD, STOP_LINE_NOT_CLEARLY_VISIBLE, IS_TOO_CLOSE_TO_STOP,
    HAS_STOPPED_AT_THE_STOP_LINE, WOULD_FORCE, WOULD_ENDANGER,
    MONITOR_OBSERVED_LIGHT, HAS_A_LIGHT_PERCEPTION_FAULT, IS_THE_DRIVER_OF, IS_THE_USER_IN_CHARGE_OF,
    IS_THE_AUTHORISED_SELF_DRIVING_ENTITY_FOR, IS_THE_NO_USER_IN_CHARGE_OPERATOR_OF, TRANSITION_DEMAND_EXPIRED, *EXPLAINED)
