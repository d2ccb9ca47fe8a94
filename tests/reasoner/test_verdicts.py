"""The verdict words and rule ids the code names (reasoner/verdicts.py) are the bundled rulebooks'
own: each verdict the validator is asked for is a query of validators.le by that name, asking
the sentence the code asks it as, and no other "... violates" sentence is concluded there; each
rule id the code picks something by labels a rule of validators.le (whose proof gives an
incident its rule) and of highway_code.le. A rename in LE fails here, not in a verdict. And no room spells a verdict word or a rule id
loose: they are named in reasoner/verdicts.py and used from there.

The check reads reasoner/rules/*.le with the LE parser alone (no Prolog), so it takes a moment."""
import ast
import re
import shutil
from pathlib import Path

import pytest

from reasoner.bundled import RULES_DIR
from reasoner.le.document import parse_document
from reasoner.verdicts import ASKED, NAMED_RULES, QUESTION, Verdict

ROOT = Path(__file__).parents[2]
VALIDATORS, HIGHWAY_CODE = "validators.le", "highway_code.le"
# every room names its verdicts through reasoner/verdicts.py now; a module that may not yet would be listed here
NOT_YET: set[str] = set()


def documents(rules: Path = RULES_DIR) -> dict:
    return {p.name: parse_document(p.read_text(encoding="utf-8"), p.name) for p in sorted(rules.glob("*.le"))}


def labels(doc) -> set[str]:
    return {r.label for r in doc.rules if r.label}


def problems(rules: Path = RULES_DIR) -> list[str]:
    """What in the rulebooks no longer matches the verdicts and rule ids the code names."""
    docs = documents(rules)
    found = []
    validators = docs[VALIDATORS]
    for verdict in ASKED:
        query = validators.queries.get(verdict.value)
        asked = [c.atom.functor for c in query.body if c.atom is not None] if query else []
        if asked != [QUESTION[verdict].functor]:
            found.append(f"{VALIDATORS} has no query {verdict.value} asking {QUESTION[verdict].template!r}")
    concluded = {r.head.functor for r in validators.rules if r.section == "kb" and r.head.functor.endswith("_violates")}
    found += [f"{VALIDATORS} concludes {f}, no verdict the code knows"
              for f in sorted(concluded - {QUESTION[v].functor for v in ASKED})]
    for name in (VALIDATORS, HIGHWAY_CODE):
        found += [f"no rule of {name} is labelled {rule}" for rule in NAMED_RULES if rule not in labels(docs[name])]
    return found


def test_the_rulebooks_name_every_verdict_and_rule_id_the_code_names():
    assert problems() == []


@pytest.mark.parametrize("file, old, new, problem", [
    (HIGHWAY_CODE, "% HC 176:", "% HC 176A:", "no rule of highway_code.le is labelled HC 176"),
    (VALIDATORS, "% HC 174:", "% HC 147:", "no rule of validators.le is labelled HC 174"),
    (VALIDATORS, "query mitigated is:", "query lenient is:", "validators.le has no query mitigated"),
    (VALIDATORS, "punishably violates", "culpably violates", "validators.le has no query punishable"),
])
def test_a_rename_in_a_copy_of_the_rulebooks_fails(tmp_path, file, old, new, problem):
    rules = tmp_path / "rules"
    shutil.copytree(RULES_DIR, rules)
    path = rules / file
    text = path.read_text(encoding="utf-8")
    assert old in text
    path.write_text(text.replace(old, new), encoding="utf-8")
    assert any(p.startswith(problem) for p in problems(rules)), problems(rules)


def test_a_new_verdict_sentence_in_the_validators_fails(tmp_path):
    rules = tmp_path / "rules"
    shutil.copytree(RULES_DIR, rules)
    path = rules / VALIDATORS
    text = path.read_text(encoding="utf-8")
    text = text.replace("*a vehicle* mitigately violates *an action*.\n",
                        "*a vehicle* mitigately violates *an action*.\n*a vehicle* leniently violates *an action*.\n")
    text = text.replace("a vehicle mitigately violates an action if", "a vehicle leniently violates an action if", 1)
    path.write_text(text, encoding="utf-8")
    assert "validators.le concludes leniently_violates, no verdict the code knows" in problems(rules)


def loose(path: Path) -> list[str]:
    """The verdict words and rule ids one file spells as a whole string of its own."""
    words = {v.value for v in Verdict}
    return [f"{path.relative_to(ROOT)}:{node.lineno} {node.value!r}"
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path)))
            if isinstance(node, ast.Constant) and isinstance(node.value, str)
            and (node.value in words or re.fullmatch(r"HC \d+", node.value))]


def test_no_room_spells_a_verdict_or_a_rule_id_loose():
    files = [p for room in ("reasoner", "explain", "cli", "sim_replay", "ingest", "store") for p in (ROOT / room).rglob("*.py")
             if p.relative_to(ROOT).as_posix() not in NOT_YET | {"reasoner/verdicts.py"}]
    assert [hit for path in files for hit in loose(path)] == []


def test_the_loose_check_sees_one(tmp_path, monkeypatch):
    monkeypatch.setattr(__import__(__name__), "ROOT", tmp_path)
    sample = tmp_path / "x.py"
    sample.write_text('if inc.verdict == "punishable" and inc.rule in ("HC 176",):\n    """HC 176 applies"""\n')
    assert [h.split(" ", 1)[1] for h in loose(sample)] == ["'punishable'", "'HC 176'"]


def test_a_verdict_is_its_word():
    """A StrEnum: printed, compared and written as JSON, a verdict is the word it always was."""
    import json
    assert [str(v) for v in Verdict] == ["punishable", "mitigated", "dismissed"]
    assert json.dumps({"verdict": Verdict.MITIGATED}) == '{"verdict": "mitigated"}'
    assert Verdict.DISMISSED == "dismissed" and {"punishable": 1}[Verdict.PUNISHABLE] == 1
