"""A vehicle's question answered by shape (sim_replay.asking): the answer and proof are exactly what
asking the engine on the vehicle's own facts gives; facts that differ in anything but the road
users' names are other shapes; a rulebook that hands a road user to a built-in is never shaped."""
from __future__ import annotations

from reasoner.engine import enrich, get_engine
from reasoner.shapes import Shaper
from reasoner.vocabulary import (CAN, HAS_LIGHT, HAS_SIGN, HAS_SPEED_OF, HAS_STOPPED_AT_THE_STOP_LINE,
                                 IS_APPROACHING, IS_DRIVING_ITSELF, IS_OF_TYPE, IS_ON_AN_EMERGENCY_CALL,
                                 IS_ON_THE_MAIN_ROAD, IS_STOPPED, IS_TOO_CLOSE_TO_STOP, SPEED_LIMIT_IS,
                                 WOULD_FORCE)
from sim_replay.asking import Asked, Rulebooks, design_tree

BOOK = "highway_code.le"
ENTER = "enter the junction"


def _fresh(books: Rulebooks, vid: str, facts: list[str]) -> Asked:
    """What asking the engine on the facts themselves gives (the ask as it was before shapes)."""
    rb = books.books[BOOK]
    goal, atoms = books._atoms(rb, CAN.text(vid, ENTER), facts)
    answer = books.engine.ask(rb, goal, atoms)
    tree = answer.proofs[0] if answer.proofs else answer.why_not
    return Asked(CAN.text(vid, ENTER), answer.holds, design_tree(enrich(tree, rb)))


def _situations(vid: str, other: str) -> list[list[str]]:
    """Facts of the kinds a vehicle states, in several situations, for vehicle vid and road user other."""
    car = [IS_OF_TYPE.text(vid, "car"), IS_DRIVING_ITSELF.text(vid)]
    return [
        car + [HAS_LIGHT.text(vid, "green")],
        car + [HAS_LIGHT.text(vid, "red"), IS_STOPPED.text(vid)],
        car + [HAS_LIGHT.text(vid, "amber"), IS_TOO_CLOSE_TO_STOP.text(vid)],
        car + [HAS_LIGHT.text(vid, "red"), HAS_LIGHT.text(vid, "amber")],
        [IS_OF_TYPE.text(vid, "ambulance"), IS_ON_AN_EMERGENCY_CALL.text(vid), HAS_LIGHT.text(vid, "red"),
         IS_OF_TYPE.text(other, "car"), IS_APPROACHING.text(other, vid), WOULD_FORCE.text(vid, other)],
        [IS_OF_TYPE.text(vid, "ambulance"), IS_ON_AN_EMERGENCY_CALL.text(vid), HAS_LIGHT.text(vid, "red")],
        car + [HAS_SIGN.text(vid, "stop"), HAS_STOPPED_AT_THE_STOP_LINE.text(vid), IS_STOPPED.text(vid)],
        car + [HAS_SIGN.text(vid, "stop")],
        car + [HAS_SIGN.text(vid, "give way"), IS_OF_TYPE.text(other, "bus"), IS_APPROACHING.text(other, vid),
               IS_ON_THE_MAIN_ROAD.text(other), WOULD_FORCE.text(vid, other)],
        car + [HAS_SIGN.text(vid, "give way"), IS_OF_TYPE.text(other, "bus"), IS_APPROACHING.text(other, vid),
               IS_ON_THE_MAIN_ROAD.text(other)],
        car + [HAS_LIGHT.text(vid, "green"), HAS_SPEED_OF.text(vid, 30), SPEED_LIMIT_IS.text(30)],
    ]


def test_an_answer_by_shape_is_exactly_the_engines_answer_on_the_vehicles_own_facts() -> None:
    books = Rulebooks()
    # vehicle 30 at 30 mph under a 30 limit: a name that is also a number in other places
    pairs = [("173", "208"), ("30", "31"), ("car 9", "7"), ("253", "173")]
    asked = 0
    for vid, other in pairs:
        for facts in _situations(vid, other):
            got = books.ask(BOOK, CAN.text(vid, ENTER), facts)
            asked += 1
            assert got == _fresh(books, vid, facts), (vid, facts)
    answers = {books.ask(BOOK, CAN.text("173", ENTER), f).holds for f in _situations("173", "208")}
    assert answers == {True, False}, "the situations do not show both answers"
    shapes = len(_situations("1", "2"))
    assert books.engine_asks <= shapes + 2 and asked + shapes == books.queries     # the rest came from shapes


def test_facts_that_differ_in_anything_but_names_are_asked_afresh() -> None:
    """Each pair is one fact apart and the rulebook answers them differently: a key that left the
    fact out would hand the second vehicle the first one's answer."""
    books = Rulebooks()

    def car(v: str) -> list[str]:
        return [IS_OF_TYPE.text(v, "car"), IS_DRIVING_ITSELF.text(v)]
    pairs = [
        (car("5") + [HAS_LIGHT.text("5", "green")], car("6") + [HAS_LIGHT.text("6", "red")]),
        ([IS_OF_TYPE.text("5", "ambulance"), IS_ON_AN_EMERGENCY_CALL.text("5"), HAS_LIGHT.text("5", "red")],
         [IS_OF_TYPE.text("6", "ambulance"), HAS_LIGHT.text("6", "red")]),
        (car("5") + [HAS_SIGN.text("5", "stop"), HAS_STOPPED_AT_THE_STOP_LINE.text("5")],
         car("6") + [HAS_SIGN.text("6", "stop")]),
        (car("5") + [HAS_SIGN.text("5", "give way"), IS_OF_TYPE.text("8", "car"), IS_APPROACHING.text("8", "5"),
                     IS_ON_THE_MAIN_ROAD.text("8")],
         car("6") + [HAS_SIGN.text("6", "give way"), IS_OF_TYPE.text("9", "car"), IS_APPROACHING.text("9", "6"),
                     IS_ON_THE_MAIN_ROAD.text("9"), WOULD_FORCE.text("6", "9")]),
    ]
    for first, second in pairs:
        one = books.ask(BOOK, CAN.text("5", ENTER), first)
        two = books.ask(BOOK, CAN.text("6", ENTER), second)
        assert one.holds != two.holds, (first, second)
        assert (one, two) == (_fresh(books, "5", first), _fresh(books, "6", second))


SPECIAL = """the target language is: prolog.

the templates are:
*a vehicle* is of type *a type*.
*a vehicle* can go.

the knowledge base k includes:
a vehicle can go if
    the vehicle is of type car
    and the vehicle > 100.
"""


def test_a_rulebook_that_hands_a_road_user_to_a_built_in_keeps_no_proofs_by_shape() -> None:
    """Vehicles 150 and 50 have facts of one shape, and this rulebook answers them differently
    (it compares the id with a number): shaping would be wrong, and is not done."""
    engine = get_engine()
    rb = engine.load(SPECIAL, "special.le")
    assert not Shaper(rb).keeps_proofs
    plain = engine.load(SPECIAL.replace("\n    and the vehicle > 100.", "."), "plain.le")
    assert Shaper(plain).keeps_proofs
    books = Rulebooks(("highway_code.le",))
    books.books["special.le"], books._shapers["special.le"] = rb, Shaper(rb)
    answers = [books.ask("special.le", f"{vid} can go", [f"{vid} is of type car"]).holds for vid in ("150", "50")]
    assert answers == [True, False] and books.engine_asks == 2
