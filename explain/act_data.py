"""What the report's pictures need of an incident beyond the store's state at one moment: the road
users the incident names (they must be in its scene picture), the distance to the stop line along
the vehicle's passage, and, for a forcing or an endangering, the other road user's speed (both on
the act's timeline).

Read, not reasoned: the names are the words of the incident's own facts (its scenarios and the
facts its history derived), the other road user is the one its "V would force U ..." or "V would
endanger U" fact names (the rulebook's template, reasoner/vocabulary.py), and the distances are
the reasoner's own: its passage's samples measured to its stop line (reasoner.junctions.StopLine),
the same figures its margins were read from. Nothing here decides anything; a fact the incident
does not carry is simply not drawn.
"""
from __future__ import annotations

import re
from typing import Any, Iterable, cast

from reasoner import acts, history
from reasoner.model import Incident
from reasoner.history import Passage
from reasoner.vocabulary import WOULD_ENDANGER, WOULD_FORCE, Sentence
from store import Store

from .picture_parts import Picture
from .report_data import number
from .timeline_parts import LinePoint, OtherParty, OtherSpeed, ToLine

# the facts naming the road user the act put at risk, and how the timeline's legend says it
RISKS: tuple[tuple[Sentence, str], ...] = ((WOULD_FORCE, "would force to change speed or course"),
                                           (WOULD_ENDANGER, "would endanger"))


def sentences(inc: Incident) -> list[str]:
    """Every sentence the incident was judged with: its scenarios' facts and the derived ones."""
    facts = [fact for group in (inc.scenarios.monitor, inc.scenarios.validator, inc.scenarios.vehicle)
             for fact, _ in group]
    return [s for s in facts + [d.sentence for d in inc.derived] if isinstance(s, str)]


def named_users(inc: Incident, picture: Picture) -> list[str]:
    """The picture's road users (its own ids: "110", "pedestrian/p8") that the incident's facts
    name as a whole word ("110 is approaching 116", "p8 is of type pedestrian"), the incident's
    vehicle first."""
    said = sentences(inc)
    out = []
    for u in picture.movers:
        uid = str(u.id)
        if u.incident or any(_names(s, uid) or _names(s, history.user_id(uid)) for s in said):
            out.append(uid)
    return sorted(out, key=lambda uid: uid != str(inc.vehicle))


def _names(sentence: str, word: str) -> bool:
    return bool(word) and re.search(rf"(?<!\S){re.escape(word)}(?!\S)", sentence) is not None


def other_party(inc: Incident) -> tuple[str, str] | None:
    """The road user the incident's vehicle would force or endanger, as its fact names it, and
    the legend's words for how (a forcing first); None when no such fact was judged."""
    said = sentences(inc)
    for sentence, words in RISKS:
        pattern = re.compile("^" + re.escape(sentence.pattern).replace(re.escape("{}"), "(.+)") + "$")
        for s in said:
            found = pattern.match(s)
            if found and found.group(1) == str(inc.vehicle):
                return found.group(2), words
    return None


def act_track(store: Store, inc: Incident, picture: Picture, t_from: int, t_to: int,
              context: history.RunContext | None = None) -> tuple[ToLine | None, OtherParty | None]:
    """The timeline's rows of the act from t_from to t_to: `to_line` (the approach, the line's
    kind and the distance before it at each sample of the passage, negative past it; None
    without a passage or a stop line) and `other` (the road user it would force or endanger, with
    its speed; None without such a fact)."""
    passage = acts.of(history.passage(store, inc.run, inc.vehicle, inc.t, context=context), inc.t)
    return _to_line(passage, t_from, t_to), _other(store, inc, picture, passage, t_from, t_to)


def _to_line(passage: Passage | None, t_from: int, t_to: int) -> ToLine | None:
    if passage is None or passage.line is None:
        return None
    line = passage.line
    points = tuple(LinePoint(s.t, round(line.to_line(cast(float, s.x), cast(float, s.y)), 2),  # placed: x and y
                             s.ref.src, s.ref.seq)
                   for s in passage.samples if s.placed and t_from <= s.t <= t_to)
    if not points:
        return None
    return ToLine(passage.junction.id, line.approach, line.kind, points)


def _other(store: Store, inc: Incident, picture: Picture, passage: Passage | None, t_from: int,
           t_to: int) -> OtherParty | None:
    """The other road user's speed over the window: its own reports (entity.state of the source
    the picture knows it by), else the samples the passage read of it (a monitor's)."""
    named = other_party(inc)
    if named is None:
        return None
    user, how = named
    seen = next((o for o in (passage.others if passage else ()) if o.user == user), None)
    vehicle = next((v for v in picture.vehicles if str(v.id) == user), None)
    walker = next((u for u in picture.road_users if history.user_id(str(u.id)) == user), None)
    src = str(walker.id) if walker is not None and vehicle is None else history.vehicle_src(user)
    speed = [OtherSpeed(ev["t"], mps, src, ev["seq"])      # the store's events, read as recorded
             for ev in store.events(inc.run, kinds=["entity.state"], srcs=[src], t_from=t_from, t_to=t_to)
             if (mps := number(ev["body"].get("speed_mps"))) is not None]
    if not speed and seen is not None:
        samples: Iterable[Any] = sorted({s.t: s for s in seen.samples + seen.path}.values(), key=lambda s: s.t)
        speed = [OtherSpeed(s.t, s.speed_mps, s.ref.src, s.ref.seq) for s in samples
                 if s.speed_mps is not None and t_from <= s.t <= t_to]
    drawn = vehicle or walker
    kind = (seen.type if seen is not None else None) or (drawn.type if drawn is not None else None)
    return OtherParty(user, kind, how, inc.vehicle, tuple(speed))
