"""What a vehicle's passage shows at an act, cut loose from the passage (DESIGN "Reasoning").

Judging a case uses its passage in a few ways: the facts it shows at the act (beside those
stated), the stated facts it contradicts, the moments an investigator places the act by, the
signals it read, the margin of the act under whichever rule judges it, and the vehicle's own
beliefs it contradicts. All of them are worked out here at once, so that the result is a small
value that can be kept (reasoner/case_memo.py) and used under any rulebook without the passage:
the margins for every rule that picks one, the beliefs for every perceived fact.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Iterable

from store import EventRef

from . import acts
from .derived import Contradiction, _match, beside, checked, facts, unmeasured
from .margins import BY_RULE, margin
from .model import Act, DerivedFact, Margin
from .history import Passage
from .second_limb import second_limb
from .stretches import Stretch
from .unforced import Unforced
from .vocabulary import HAS_SPEED_OF, IS_APPROACHING, WOULD_ENDANGER, WOULD_FORCE

Belief = tuple[str, str, int, tuple[Contradiction, ...]]        # (sentence, src, seq, what contradicts it)


@dataclass(frozen=True)
class Measurement:
    present: bool                                    # the act fell in a passage of the vehicle's
    at: int | None = None                            # when the act happened in it
    derived: tuple[DerivedFact, ...] = ()            # what it shows beside what was stated
    contradictions: tuple[Contradiction, ...] = ()   # stated facts it contradicts
    moments: tuple[tuple[str, int], ...] = ()
    signals: tuple[str, ...] = ()                    # the signals whose reports it read
    margins: tuple[tuple[str | None, Margin | None], ...] = ()   # by rule (None: no rule that picks one)
    beliefs: tuple[Belief, ...] = ()                 # each perceived fact, and what contradicts it
    unmeasured: tuple[tuple[str, EventRef, str], ...] = ()   # stated predictions about a road user nothing of
                                                             # which was measured: (sentence, by, road user)
    act: Act | None = None                           # the act as the record delimits it (reasoner/oneact.py)
    readings: tuple[tuple[str, EventRef], ...] = ()  # how the map's words were read for it (junctions.py)
    unforced: tuple[Unforced, ...] = ()              # road users the second limb does not reach, and why
                                                     # (reasoner/second_limb.py)

    @property
    def contested(self) -> tuple[tuple[str, str, tuple[str, ...]], ...]:
        """Every stated or perceived sentence the measurements contradict beyond tolerance, with
        what they show instead, in words and as the sentences they derive: a claim that cannot
        decide a verdict alone (investigation: weighing)."""
        found = [(c.stated, c.detail, c.shown) for c in self.contradictions]
        found += [(c.stated, c.detail, c.shown) for _, _, _, cs in self.beliefs for c in cs]
        return tuple(dict.fromkeys(found))

    def unproven(self) -> tuple[tuple[str | None, str], ...]:
        """By rule, why the act's margin does not prove it (within its uncertainty)."""
        return tuple((r, m.unproven) for r, m in self.margins if m is not None and m.unproven)

    def margin(self, rule: str | None) -> Margin | None:
        """The margin of the act under this rule (margins.margin(passage, action, rule))."""
        wanted = rule_key(rule)
        return next((m for r, m in self.margins if r == wanted), None)

    @property
    def overruled(self) -> frozenset[str]:
        """The stated predictions ("V would force U", "V would endanger U", and a pedestrian's or
        cyclist's "P is approaching V", which the rules read as endangering) that the measurements
        of U contradict: a claim of what its maker believed, weighed against what U did and left
        out of the scenarios the act is judged on (its contradiction is a finding)."""
        found = [*self.contradictions, *(c for *_, cs in self.beliefs for c in cs)]
        return frozenset(c.stated for c in found if _predicts(c.stated))

    def contradicted(self, own: Iterable[tuple[str, EventRef]]) -> tuple[Contradiction, ...] | None:
        """What contradicts these perceived facts (derived.checked(passage, at, own)[1]); None
        when one of them was not among those measured (the passage must be asked)."""
        table = {(_said(text), src, seq): found for text, src, seq, found in self.beliefs}
        out: list[Contradiction] = []
        for text, ref in own:
            found = table.get((_said(text), ref.src, ref.seq))
            if found is None:
                return None
            out += found
        return tuple(out)


def measure(passage: Passage | None, t: int, action: str, stated: list[tuple[Any, EventRef]],
            sentences: Iterable[Any], perceived: Iterable[tuple[Any, EventRef | None]],
            stretch: Stretch | None = None) -> Measurement:
    """The measurement of the act of `action` at t: `stated` the Monitor Scenario's facts,
    `sentences` its sentences, `perceived` the vehicle's own facts (its Vehicle Scenario),
    `stretch` the speeding stretch around t (reasoner/stretches.py) for a speeding act."""
    found = acts.of(passage, t)
    over = stretch if action == acts.SPEEDING else None     # the speeding stretch, for a speeding act
    if found is None:
        if over is not None:          # a stretch away from any junction: what the stretch shows, no passage
            return Measurement(True, over.peak.t, beside(over.facts(), sentences),
                               margins=((None, over.margin()),), act=over.act())
        return Measurement(False)
    at = acts.moment(found, t, action)
    derived = facts(found, at)
    agreed, contradictions = checked(found, at, stated, derived)
    if over is not None:
        agreed, contradictions = _over_the_stretch(over, agreed, contradictions)
    beliefs = tuple((text, ref.src, ref.seq, checked(found, at, [(text, ref)], derived)[1])
                    for text, ref in perceived
                    if isinstance(text, str) and ref is not None and ref.kind == "vehicle.perception")
    claims = [(text, ref) for text, ref in [*stated, *perceived]
              if isinstance(text, str) and ref is not None and _predicts(text)]
    alone = tuple(dict.fromkeys((_said(text), ref, user) for text, ref in claims
                                if (user := unmeasured(found, _said(text))) is not None))
    return Measurement(True, at, beside(agreed, sentences), contradictions, acts.moments(found),
                       tuple(sorted({light.ref.src for light in found.lights})),
                       tuple((rule, over.margin() if over is not None else margin(found, action, rule, at)) for rule in (None, *BY_RULE)), beliefs, alone,
                       act=over.act() if over is not None else _passage_act(found),
                       readings=((found.line.reading, found.map_ref),) if found.line and found.line.reading
                       and found.map_ref else (),
                       unforced=() if over is not None else second_limb(found))


def _over_the_stretch(stretch: Stretch, agreed: tuple[DerivedFact, ...], contradictions: tuple[Contradiction, ...]
                      ) -> tuple[tuple[DerivedFact, ...], tuple[Contradiction, ...]]:
    """A speeding act is its stretch (one act, one offence): what the measurements show of the
    speed is the stretch's peak, not the speed at the moment a camera flagged it. A camera's
    "489 has speed of 31" where the car's own record had 24.0 mph then is still contradicted (its
    finding stays), but in its place the rules are asked on the stretch's "489 has speed of 39":
    the verdict rests on what is proved, and a stretch proved over the limit is not dismissed
    for the camera's wrong reading (DESIGN "Weighing"). Only a contested speed moves: what the
    measurements agree with is as the passage shows it at the act's moment."""
    shown = tuple(f.sentence for f in stretch.facts())
    return agreed, tuple(replace(c, shown=shown) if _match(HAS_SPEED_OF, c.stated) else c for c in contradictions)


def _passage_act(p: Passage) -> Act:
    """A junction act is the passage it happened in: from the first sample near the junction to
    the last (reasoner/rebuild.py), the record's own edges said as open."""
    read = " ".join(p.uncertain)
    return Act(acts.PASSAGE, p.junction.id, p.start, p.end,
               f"the passage through {p.junction.id}" + (f" from the {p.approach}" if p.approach else "")
               + f" ({p.series})", "begins with the first sample read" in read,
               "ends with the last sample read" in read)


def rule_key(rule: str | None) -> str | None:
    key = rule.strip().upper() if isinstance(rule, str) else None
    return key if key in BY_RULE else None


def _predicts(text: str) -> bool:
    return any(_match(kind, text) is not None for kind in (WOULD_FORCE, WOULD_ENDANGER, IS_APPROACHING))


def _said(text: str) -> str:
    return text.strip().rstrip(".").strip()
