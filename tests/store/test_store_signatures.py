"""Ed25519 signatures on events: what is signed, what the envelope accepts, how keys are kept and
trusted, and that verify catches a signature stripped, replaced or forged (store/signatures.py,
store/keyfiles.py, docs/store.md "Signatures")."""
from __future__ import annotations

import base64
import json
import shutil
import sqlite3
import subprocess
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from store import EventError, Store, canonical_json, decode_event, encode_event
from store.keys import KeyFolder, KeysError, Signer, TrustedKeys, signed_bytes
from store.transfer import export_run, import_file

RUN = "signed-run"
T0 = 1_732_184_100_000_000_000


def event(src: str = "vehicle/173", seq: int = 0, facts: list[str] | None = None) -> dict:
    body = {"facts": facts if facts is not None else [f"{src[8:]} has red light"]}
    kind = "vehicle.perception" if src.startswith("vehicle/") else "entity.despawn"
    return {"v": 1, "run": RUN, "src": src, "seq": seq, "t": T0 + seq, "kind": kind,
            "body": body if kind == "vehicle.perception" else {}}


@pytest.fixture(scope="module")
def keys(tmp_path_factory) -> KeyFolder:
    folder = KeyFolder(tmp_path_factory.mktemp("keys"))
    for src in ("vehicle/173", "vehicle/174", "monitor/m1"):
        folder.create(src)
    return folder


@pytest.fixture(scope="module")
def signer(keys) -> Signer:
    return Signer(keys)


@pytest.fixture(scope="module")
def trusted(keys) -> TrustedKeys:
    return TrustedKeys.load(keys.write_public_keys())


# --- what is signed, and the envelope ----------------------------------------------------------------


def test_the_signature_covers_the_canonical_event_without_sig(signer, keys):
    from nacl.signing import VerifyKey
    signed = signer.sign(event())
    assert signed_bytes(signed) == canonical_json(event())
    VerifyKey(keys.public_key("vehicle/173")).verify(canonical_json(event()),
                                                     base64.b64decode(signed["sig"]["ed25519"]))


def test_a_signed_event_is_accepted_and_stored_with_its_signature(signer, tmp_path):
    signed = signer.sign(event())
    raw = canonical_json(signed)
    assert decode_event(raw) == (signed, raw)                         # the fast path
    spaced = json.dumps(signed, indent=1).encode()
    assert decode_event(spaced) == (signed, raw)                      # the careful path
    with Store(tmp_path / "s.db") as store:
        assert store.append([signed]).stored == 1
        assert list(store.events(RUN)) == [signed]


@pytest.mark.parametrize("sig, complaint", [
    ("abc", "sig must be an object"),
    ({"key": "0" * 16}, "exactly the fields ed25519 and key"),
    ({"key": "0" * 16, "ed25519": "A" * 86 + "==", "by": "me"}, "exactly the fields"),
    ({"key": "ABCDEF0123456789", "ed25519": "A" * 86 + "=="}, "sig.key must be 16 lowercase hex"),
    ({"key": "0" * 15, "ed25519": "A" * 86 + "=="}, "sig.key must be 16"),
    ({"key": "0" * 16, "ed25519": "A" * 85 + "B=="}, "sig.ed25519 must be a 64-byte signature"),  # a 2nd spelling
    ({"key": "0" * 16, "ed25519": "A" * 84 + "=="}, "sig.ed25519 must be a 64-byte signature"),
    ({"key": "0" * 16, "ed25519": 7}, "sig.ed25519 must be"),
])
def test_a_malformed_signature_is_refused_naming_the_event(sig, complaint):
    with pytest.raises(EventError, match=complaint) as caught:
        encode_event({**event(seq=4), "sig": sig})
    assert caught.value.field == "sig"
    assert str(caught.value).startswith(f"event run={RUN} src=vehicle/173 seq=4: ")


def test_any_other_extra_envelope_field_is_still_refused():
    with pytest.raises(EventError, match="unknown envelope field"):
        encode_event({**event(), "signature": "x"})


# --- judging an event against the trusted keys ---------------------------------------------------------


def test_a_signature_by_the_sources_own_key_is_valid(signer, trusted):
    assert trusted.reason(signer.sign(event())) is None


def test_unsigned_is_refused_when_signatures_are_required(trusted):
    assert trusted.reason(event(seq=3)) == f"event run={RUN} src=vehicle/173 seq=3: unsigned, and signatures are required"


def test_an_event_altered_after_signing_is_refused(signer, trusted):
    altered = signer.sign(event())
    altered["body"] = {"facts": ["173 has green light"]}
    assert "the signature does not match the event" in trusted.reason(altered)


def test_a_signature_by_another_sources_key_is_refused(signer, trusted, keys):
    from nacl.signing import SigningKey
    from store.keys import sign_event
    forged = sign_event(event(), SigningKey(keys.seed("vehicle/174")))   # 174 signs as 173
    assert "trusted for vehicle/174, not for vehicle/173" in trusted.reason(forged)


def test_a_key_nobody_trusts_is_refused_naming_it(trusted):
    from nacl.signing import SigningKey
    from store.keys import key_id, sign_event
    stranger = SigningKey.generate()
    reason = trusted.reason(sign_event(event(), stranger))
    assert f"signed with key {key_id(bytes(stranger.verify_key))}, which is not in" in reason


def test_patterns_and_rotated_keys(tmp_path):
    folder = KeyFolder(tmp_path)
    old, new = folder.create("monitor/m1"), folder.create("monitor/m2")
    public = folder.public_keys()
    trusted = TrustedKeys.from_json({"monitor/*": [public["monitor/m1"], public["monitor/m2"]]}, "fleet")
    signer = Signer(folder)
    assert trusted.reason(signer.sign(event("monitor/m1"))) is None
    assert trusted.reason(signer.sign(event("monitor/m2"))) is None
    other = TrustedKeys.from_json({"monitor/m9": public["monitor/m1"]}, "one")
    assert "not for monitor/m1" in other.reason(signer.sign(event("monitor/m1")))
    assert old.exists() and new.exists()


@pytest.mark.parametrize("content, complaint", [
    ("[]", "is a JSON object"),
    ("{}", "at least one entry"),
    ('{"car/1 x": "AAAA"}', "is not a source or a pattern"),
    ('{"vehicle/1": "not base64!"}', "the key of vehicle/1 is not base64"),
    ('{"vehicle/1": "AAAA"}', "is 3 bytes; an Ed25519 public key is 32"),
    ('{"vehicle/1": 5}', "must be a base64 string"),
    ("{not json", "cannot read the public keys file"),
])
def test_a_bad_public_keys_file_names_the_file_and_the_entry(tmp_path, content, complaint):
    path = tmp_path / "keys.json"
    path.write_text(content)
    with pytest.raises(KeysError, match=complaint) as caught:
        TrustedKeys.load(path)
    assert str(path) in str(caught.value) and caught.value.exit_code == 2


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(facts=st.lists(st.text(min_size=1, max_size=30), max_size=4), seq=st.integers(0, 2**63 - 1),
       which=st.sampled_from(["seq", "t", "body", "run", "src"]))
def test_any_change_to_a_signed_event_breaks_its_signature(signer, trusted, facts, seq, which):
    signed = signer.sign(event(seq=seq, facts=facts))
    assert trusted.reason(signed) is None
    changed = dict(signed)
    changed[which] = {"seq": seq ^ 1, "t": signed["t"] + 1, "body": {"facts": facts + ["x"]},
                      "run": "other", "src": "vehicle/174"}[which]
    assert trusted.reason(changed) is not None


# --- key files -----------------------------------------------------------------------------------------


def test_a_key_is_never_overwritten_and_is_readable_by_its_owner_only(tmp_path):
    folder = KeyFolder(tmp_path)
    path = folder.create("vehicle/1")
    assert path == tmp_path / "vehicle" / "1.key" and path.stat().st_mode & 0o777 == 0o600
    before = path.read_bytes()
    with pytest.raises(KeysError, match="never overwritten"):
        folder.create("vehicle/1")
    assert path.read_bytes() == before
    with pytest.raises(KeysError, match="is not a source"):
        folder.create("car/1")


@pytest.mark.skipif(shutil.which("openssl") is None, reason="no openssl on this machine")
def test_keys_are_pkcs8_pem_as_openssl_writes_and_reads_them(tmp_path):
    folder = KeyFolder(tmp_path)
    folder.create("vehicle/1")
    der = subprocess.run(["openssl", "pkey", "-in", str(folder.key_path("vehicle/1")), "-pubout", "-outform", "DER"],
                         capture_output=True, check=True).stdout
    assert der[-32:] == folder.public_key("vehicle/1")
    (tmp_path / "monitor").mkdir()
    subprocess.run(["openssl", "genpkey", "-algorithm", "ed25519", "-out", str(tmp_path / "monitor" / "m1.key")],
                   check=True, capture_output=True)
    der = subprocess.run(["openssl", "pkey", "-in", str(tmp_path / "monitor" / "m1.key"), "-pubout", "-outform", "DER"],
                         capture_output=True, check=True).stdout
    assert folder.sources() == ["monitor/m1", "vehicle/1"] and folder.public_key("monitor/m1") == der[-32:]


def test_a_signer_without_a_key_says_how_to_make_one(tmp_path):
    with pytest.raises(KeysError, match="gaps keys new"):
        Signer(KeyFolder(tmp_path)).sign(event())
    assert Signer(KeyFolder(tmp_path), create=True).sign(event())["sig"]["key"]
    assert (tmp_path / "vehicle" / "173.key").is_file()


# --- stored, verified, exported and imported ------------------------------------------------------------


@pytest.fixture
def signed_store(tmp_path, signer) -> Path:
    path = tmp_path / "signed.db"
    with Store(path) as store:
        events = [signer.sign(event("vehicle/173", seq)) for seq in range(5)]
        events += [event("vehicle/174", 0)]                                      # one unsigned
        assert store.append(events).stored == 6
    return path


def test_verify_counts_signatures_and_checks_them_with_keys(signed_store, trusted):
    with Store.open_read_only(signed_store) as store:
        counted = store.verify().signatures
        checked = store.verify(keys=trusted).signatures
    assert (counted.signed, counted.unsigned, counted.checked, counted.valid) == (5, 1, False, None)
    assert (checked.signed, checked.valid, checked.invalid, checked.first_invalid) == (5, 5, 0, None)


def test_a_forged_event_stored_without_checks_is_named_by_verify(tmp_path, keys, trusted):
    from nacl.signing import SigningKey
    from store.keys import sign_event
    path = tmp_path / "forged.db"
    with Store(path) as store:
        store.append([Signer(keys).sign(event(seq=0)), sign_event(event(seq=1), SigningKey(keys.seed("vehicle/174")))])
        report = store.verify(keys=trusted)
    assert report.ok                                        # the chain is intact: it recorded what came
    s = report.signatures
    assert (s.valid, s.invalid) == (1, 1)
    assert s.first_invalid.src == "vehicle/173" and s.first_invalid.seq == 1
    assert s.first_invalid.chain_pos == 1 and "not for vehicle/173" in s.first_invalid.what


def _rewrite(path: Path, seq: int, change) -> None:
    """An attacker with the file: drop the append-only trigger, rewrite one event's text."""
    conn = sqlite3.connect(path)
    conn.execute("DROP TRIGGER events_no_update")
    (text,) = conn.execute("SELECT event FROM events WHERE src = 'vehicle/173' AND seq = ?", (seq,)).fetchone()
    conn.execute("UPDATE events SET event = ? WHERE src = 'vehicle/173' AND seq = ?",
                 (canonical_json(change(json.loads(text))).decode(), seq))
    conn.commit()
    conn.close()


def test_a_signature_stripped_in_the_store_file_is_caught(signed_store, tmp_path, trusted):
    copy = tmp_path / "stripped.db"
    shutil.copy(signed_store, copy)
    _rewrite(copy, 2, lambda ev: {k: v for k, v in ev.items() if k != "sig"})
    with Store.open_read_only(copy) as store:
        report = store.verify(keys=trusted)
    assert not report.ok and report.problem.seq == 2 and "hash does not match" in report.problem.what
    assert report.signatures.signed == 4 and report.signatures.unsigned == 2


def test_a_signature_replaced_in_the_store_file_is_caught(signed_store, tmp_path, trusted, keys):
    from nacl.signing import SigningKey
    from store.keys import sign_event
    copy = tmp_path / "replaced.db"
    shutil.copy(signed_store, copy)
    _rewrite(copy, 3, lambda ev: sign_event(ev, SigningKey.generate()))
    with Store.open_read_only(copy) as store:
        report = store.verify(keys=trusted)
    assert not report.ok and report.problem.seq == 3
    assert report.signatures.invalid == 1 and report.signatures.first_invalid.seq == 3


@pytest.mark.parametrize("suffix", [".jsonl", ".mcap"])
def test_signatures_travel_in_exports_and_back(signed_store, tmp_path, trusted, suffix):
    exported = tmp_path / f"run{suffix}"
    with Store.open_read_only(signed_store) as store:
        export_run(store, RUN, exported)
        original = list(store.events(RUN))
    with Store(tmp_path / "back.db") as back:
        assert import_file(back, exported).stored == 6
        assert list(back.events(RUN)) == original
        report = back.verify(keys=trusted)
    assert report.ok and (report.signatures.valid, report.signatures.invalid) == (5, 0)
