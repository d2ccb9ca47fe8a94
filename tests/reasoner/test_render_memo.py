"""A sentence rendered from its shape's text reads exactly as rendering it afresh would
(reasoner/le/render_memo.py), whatever its numbers: ids, negative numbers, numbers in a date slot,
text that looks like a placeholder, nested conditions."""

from hypothesis import given, settings, strategies as st

from reasoner.bundled import bundled
from reasoner.engine import get_engine
from reasoner.le.document import parse_document
from reasoner.le.render import sentence_text
from reasoner.le.render_memo import PLACEHOLDER, ShapeMemo

DATED = parse_document("""the templates are:
*a vehicle* has speed of *a speed*.
*a vehicle* was seen on *a date*.
*a vehicle* is approaching *an other vehicle*.
*a vehicle* crossed the stop line on *a colour* light.

the knowledge base dated includes:
a vehicle is approaching an other vehicle if the vehicle has speed of 3.
""", "dated.le")

numbers = st.one_of(st.integers(-10**20, 10**20), st.just(PLACEHOLDER), st.just(PLACEHOLDER + 1),
                    st.integers(0, 400))
values = st.one_of(numbers, st.sampled_from(["red", "p7", str(PLACEHOLDER), "the main road"]),
                   st.floats(-1e6, 1e6, allow_nan=False), st.booleans(),
                   st.builds(lambda n: {"var": n}, st.sampled_from(["vehicle", "_", "speed"])))
atoms = st.one_of(
    st.builds(lambda a, b: ["has_speed_of", a, b], values, values),
    st.builds(lambda a, b: ["was_seen_on", a, b], values, numbers),
    st.builds(lambda a, b: ["is_approaching", a, b], values, values),
    st.builds(lambda a, b: ["crossed_the_stop_line_on_light", a, b], values, values))
conditions = st.recursive(atoms, lambda inner: st.one_of(
    st.builds(lambda c: ["$not", c], st.lists(inner, min_size=1, max_size=3)),
    st.builds(lambda c: ["$and", c], st.lists(inner, min_size=1, max_size=3))), max_leaves=6)


@settings(max_examples=400, deadline=None)
@given(st.lists(conditions, min_size=1, max_size=6))
def test_every_sentence_reads_as_rendering_it_afresh(sentences):
    memo = ShapeMemo()
    render = lambda data: sentence_text(data, DATED)  # noqa: E731
    for data in sentences + sentences:
        assert memo.text(data, render) == render(data), data


def test_a_judgement_renders_each_shape_once():
    rb = get_engine().load(bundled("validators.le"), "validators.le")
    rendered, memo = [], ShapeMemo()
    for vehicle in range(100, 160):
        data = ["$not", [["can", vehicle, "exceed the speed limit"]]]
        rendered.append(memo.text(data, lambda d: rendered.append(None) or sentence_text(d, rb.document)))
    texts = [t for t in rendered if t is not None]
    assert texts[0] == "it is not the case that 100 can exceed the speed limit" and texts[-1].startswith(
        "it is not the case that 159 ")
    assert rendered.count(None) == 1


def test_a_number_in_a_date_slot_is_rendered_afresh():
    memo = ShapeMemo()
    render = lambda data: sentence_text(data, DATED)  # noqa: E731
    for day in (1_700_000_000, 1_800_000_000):
        data = ["was_seen_on", 7, day]
        assert memo.text(data, render) == render(data) and "1700000000" not in memo.text(data, render)


def test_an_unknown_before_its_own_noun_in_the_plural_reads_any():
    """Issue 39: "126 is being used for a purpose purposes: not recorded" in the why-not; the
    template is "*a vehicle* is being used for *a purpose* purposes"."""
    from reasoner.bundled import RULES_DIR
    from reasoner.engine import get_engine
    from reasoner.le.render import sentence_text
    doc = get_engine().load((RULES_DIR / "validators.le").read_text(encoding="utf-8"), "validators.le").document
    assert sentence_text(["is_being_used_for_purposes", "126", {"var": "purpose"}], doc) == \
        "126 is being used for any purposes"
    assert sentence_text(["is_being_used_for_purposes", "126", "police"], doc) == "126 is being used for police purposes"
