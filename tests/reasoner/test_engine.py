"""The engine over janus_swi: answers, proofs, why-not, isolation, and facts that stay data."""
from reasoner.bundled import bundled
from reasoner.engine import get_engine
from reasoner.le.render import sentence_text
from reasoner.le.sentences import parse_fact
from reasoner.le.terms import Atom

ENTER = "enter the junction"


def load():
    return get_engine().load(bundled("paper.le"), "paper.le")


def facts(rb, *sentences):
    return [parse_fact(s, rb.document.templates) for s in sentences]


def test_car_at_red_may_not_enter_and_why_not_names_both_rules():
    rb = load()
    answer = get_engine().ask(rb, Atom("can", (173, ENTER)), facts(rb, "173 is of type car", "173 has red light"))
    assert not answer.holds
    attempts = answer.why_not["children"]
    assert sorted(a["rule"] for a in attempts) == [0, 1]
    failed = {tuple(a["children"][-1]["sentence"]) for a in attempts}
    assert failed == {("is_of_type", 173, "ambulance"), ("has_light", 173, "green")}


def test_ambulance_may_enter_with_a_proof_from_its_facts():
    rb = load()
    answer = get_engine().ask(rb, Atom("can", (253, ENTER)), facts(rb, "253 is of type ambulance"))
    assert answer.holds
    proof = answer.proofs[0]
    assert proof["rule"] == 0 and proof["children"][0]["status"] == "fact"
    assert proof["children"][1]["sentence"][0] == "$not"


def test_scenarios_do_not_leak_between_questions():
    rb = load()
    engine = get_engine()
    assert engine.ask(rb, Atom("can", (1, ENTER)), facts(rb, "1 has green light")).holds
    assert not engine.ask(rb, Atom("can", (1, ENTER)), []).holds


def test_same_text_loads_once_and_other_versions_coexist():
    engine = get_engine()
    a = load()
    assert load() is a
    changed = bundled("paper.le").replace("has green light\n", "has green light\n    and the vehicle is stopped\n", 1)
    b = engine.load(changed, "paper-v2.le")
    assert b.module != a.module
    scenario = facts(a, "9 has green light")
    assert engine.ask(a, Atom("can", (9, ENTER)), scenario).holds
    assert not engine.ask(b, Atom("can", (9, ENTER)), scenario).holds


def test_hostile_fact_strings_are_constants_not_code(tmp_path):
    rb = load()
    marker = tmp_path / "pwned"
    hostile = [
        f"173 has red'), shell('touch {marker}'), ('x light",
        "173 has X light",
        ":- halt. has red light",
        "173 has \" ), halt, ( \" light",
        "173 has " + "a" * 100_000 + " light",
    ]
    atoms = facts(rb, *hostile)
    assert all(a is not None and a.functor == "has_light" for a in atoms)
    answer = get_engine().ask(rb, Atom("can", (173, ENTER)), atoms)
    assert not answer.holds and not marker.exists()
    # the engine is still alive and answering
    assert get_engine().ask(rb, Atom("can", (173, ENTER)), facts(rb, "173 has green light")).holds


def test_a_sentence_of_words_renders_the_same_when_remembered():
    rb = load()
    for data in (["has_light", "c12", "red"], ["is_of_type", "c12", "ambulance"], ["has_light", "c12", "red"]):
        assert rb.render(data) == sentence_text(data, rb.document)
    assert rb.render(["is_of_type", "173", "car"]) != rb.render(["is_of_type", "174", "car"])


def test_remembered_sentences_keep_numbers_words_and_truth_apart():
    rb = load()
    for data in (["is_of_type", 173, "car"], ["is_of_type", "173", "car"], ["is_of_type", 1, "car"],
                 ["is_of_type", True, "car"], ["is_of_type", 173, "car"]):
        assert rb.render(data) == sentence_text(data, rb.document)


def test_a_rulebook_is_named_as_its_caller_names_it_whatever_the_process_loaded_first():
    """One text loaded as reasoner/rules/paper.le and then as paper.le (a regression's --rules path,
    then a recorded rulebook) is one Prolog module, but each caller sees its own name: reports and
    citations (`paper.le:12`) did depend on which load came first (test_regress before
    test_incidents_golden)."""
    text = bundled("paper.le").replace("the knowledge base", "\n\nthe knowledge base", 1)   # a text of its own
    by_path = get_engine().load(text, "reasoner/rules/paper-copy.le")
    by_name = get_engine().load(text, "paper-copy.le")
    assert (by_path.name, by_name.name) == ("reasoner/rules/paper-copy.le", "paper-copy.le")
    assert by_name.module == by_path.module and by_name.sha256 == by_path.sha256
    assert get_engine().load(text, "paper-copy.le") is by_name
    answer = get_engine().ask(by_name, Atom("can", (173, ENTER)), facts(by_name, "173 is of type car",
                                                                          "173 has red light"))
    assert answer == get_engine().ask(by_path, Atom("can", (173, ENTER)),
                                      facts(by_path, "173 is of type car", "173 has red light"))
