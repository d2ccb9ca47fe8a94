"""`gaps verify`'s verdict is the store's (store/verify_outcome.py): check_store answers what the
command prints, so a script and the command cannot disagree. A store of unsigned events whose
chains hold: the chains' report says ok, and only the whole check, asked that all be signed, fails."""
from __future__ import annotations

import json
from pathlib import Path

from store import Store, check_store
from tests.helpers.cli import gaps
from tests.helpers.store_testkit import event


def _store(tmp_path: Path) -> Path:
    path = tmp_path / "gaps.db"
    with Store(path) as kept:
        kept.append([event(i) for i in range(20)])
    return path


def test_the_verdict_is_the_stores_and_the_command_only_renders_it(tmp_path):
    db = _store(tmp_path)
    with Store.open_read_only(db) as kept:
        loose = check_store(kept, all_signed=False)
        strict = check_store(kept, all_signed=True)
        chains = kept.verify()
    assert chains.ok and loose.ok and not strict.ok and not strict.signatures_ok
    said = gaps("verify", "--all-signed", "--json", db=db)
    assert said.exit_code == 1 and json.loads(said.stdout) == json.loads(json.dumps(strict.to_json(), default=str))
    assert json.loads(gaps("verify", "--json", db=db).stdout)["ok"] is True
