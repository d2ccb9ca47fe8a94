"""`gaps keys` and `gaps verify --keys`: keys made and never overwritten, the public keys file,
and verify's account of signatures in text and JSON, with exit 1 on an invalid one."""
from __future__ import annotations

import json

import pytest

from store import Store
from store.keys import KeyFolder, Signer, sign_event
from tests.helpers.cli import gaps

RUN = "signed"


def event(src: str, seq: int) -> dict:
    return {"v": 1, "run": RUN, "src": src, "seq": seq, "t": 1_000 + seq, "kind": "entity.despawn", "body": {}}


@pytest.fixture
def keys_dir(tmp_path):
    made = gaps("keys", "new", tmp_path / "keys", "vehicle/173", "vehicle/174")
    assert made.exit_code == 0, made.output
    return tmp_path / "keys"


def store_of(path, events):
    with Store(path) as store:
        store.append(events)
    return path


def test_keys_new_makes_keys_and_the_public_keys_file(keys_dir):
    public = json.loads((keys_dir / "public-keys.json").read_text())
    assert sorted(public) == ["vehicle/173", "vehicle/174"]
    shown = gaps("keys", "public", keys_dir, "-o", "-")
    assert shown.exit_code == 0 and json.loads(shown.stdout) == public


@pytest.mark.parametrize("source, message", [("vehicle/173", "exists: a source's key is never overwritten"),
                                             ("car/1", "'car/1' is not a source")])
def test_keys_new_refuses_in_one_line(keys_dir, source, message):
    before = (keys_dir / "vehicle" / "173.key").read_bytes()
    result = gaps("keys", "new", keys_dir, source)
    assert result.exit_code == 2 and message in result.stderr and result.stderr.count("\n") == 1
    assert (keys_dir / "vehicle" / "173.key").read_bytes() == before


def test_verify_says_every_signature_is_valid(keys_dir, tmp_path):
    signer = Signer(KeyFolder(keys_dir))
    db = store_of(tmp_path / "s.db", [signer.sign(event("vehicle/173", 0)), event("vehicle/174", 0)])
    counted = gaps("verify", db=db)
    assert counted.exit_code == 0 and "1 signed, 1 unsigned (not checked: give --keys KEYS)" in counted.stdout
    checked = gaps("verify", "--keys", keys_dir / "public-keys.json", db=db)
    assert checked.exit_code == 0 and "1 signed, 1 unsigned; every signature is valid" in checked.stdout
    strict = gaps("verify", "--keys", keys_dir / "public-keys.json", "--all-signed", "--json", db=db)
    assert strict.exit_code == 1 and json.loads(strict.stdout)["signatures"]["ok"] is False


def test_verify_names_the_first_invalid_signature_and_exits_1(keys_dir, tmp_path):
    from nacl.signing import SigningKey
    folder = KeyFolder(keys_dir)
    forged = sign_event(event("vehicle/173", 1), SigningKey(folder.seed("vehicle/174")))
    db = store_of(tmp_path / "f.db", [Signer(folder).sign(event("vehicle/173", 0)), forged])
    text = gaps("verify", "--keys", keys_dir / "public-keys.json", db=db)
    assert text.exit_code == 1
    assert "verified: every chain and checkpoint matches" in text.stdout
    assert "2 signed, 0 unsigned; 1 valid, 1 INVALID" in text.stdout
    assert "INVALID SIGNATURE at run signed src vehicle/173 seq 1 (chain position 1)" in text.stdout
    data = json.loads(gaps("verify", "--keys", keys_dir / "public-keys.json", "--json", db=db).stdout)
    assert data["ok"] is False and data["signatures"]["first_invalid"]["seq"] == 1


def test_verify_with_a_bad_keys_file_is_a_usage_error(tmp_path):
    db = store_of(tmp_path / "s.db", [event("vehicle/173", 0)])
    (tmp_path / "k.json").write_text("[]")
    result = gaps("verify", "--keys", tmp_path / "k.json", db=db)
    assert result.exit_code == 2 and "is a JSON object" in result.stderr
    missing = gaps("verify", "--keys", tmp_path / "none.json", db=db)
    assert missing.exit_code == 2 and "no public keys file at" in missing.stderr
