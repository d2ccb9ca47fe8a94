"""Ed25519 signatures on events: what is signed, how a signature travels, and how it is checked.

A source that signs adds one field to the envelope, beside `body`:

    "sig": {"key": "<key id>", "ed25519": "<signature, standard base64 of 64 bytes>"}

The signature covers the event's canonical JSON *without* the `sig` field: exactly the bytes the
store would keep for the same event unsigned (store/canonical.py). It travels inside the event,
not as a Zenoh attachment, so the one JSON object that is published, stored, hash-chained,
exported to JSONL or MCAP and imported again carries its own proof of origin: a file or a store
row can be checked with nothing but the source's public key, and a stripped or replaced
signature changes the stored text that the hash chain covers.

The key id is the first 16 hex digits of the sha256 of the raw 32-byte public key: it tells a
verifier which of a source's keys to try (keys are rotated) and makes "signed with a key we do
not know" a precise reason. It is a hint, not trust: the signature is checked only against keys
the verifier was given for the event's source (`TrustedKeys`, store/keyfiles.py).

PyNaCl (libsodium) does the cryptography; it is imported on first use, so that commands which
never sign or check do not load it.
"""

from __future__ import annotations

import base64
import binascii
import hashlib
import re
from typing import Any

from ..canonical import canonical_json

SIG_FIELD = "sig"
KEY_ID_HEX = 16
_KEY_ID = re.compile(rf"[0-9a-f]{{{KEY_ID_HEX}}}")
# 64 bytes in standard base64: 85 full characters, one holding the last 2 bits (its other 4 bits
# zero: A, Q, g or w), and the padding. Only this one spelling is accepted, so that no second text
# of the same signature exists (the chain and duplicate detection compare text).
_ED25519 = re.compile(r"[A-Za-z0-9+/]{85}[AQgw]==")

__all__ = ["KEY_ID_HEX", "SIG_FIELD", "key_id", "sig_problem", "sign_event", "signature_reason", "signed_bytes"]


def key_id(public_key: bytes) -> str:
    """The id a signature names its key by: 16 hex digits of the sha256 of the raw public key."""
    return hashlib.sha256(public_key).hexdigest()[:KEY_ID_HEX]


def signed_bytes(event: dict) -> bytes:
    """The bytes a signature covers: the canonical JSON of the event without its `sig` field."""
    if SIG_FIELD not in event:
        return canonical_json(event)
    return canonical_json({name: value for name, value in event.items() if name != SIG_FIELD})


def sig_problem(sig: Any) -> str | None:
    """What is wrong with the shape of a `sig` field, or None; no cryptography (the envelope's check)."""
    if type(sig) is not dict:
        return f"sig must be an object {{key, ed25519}}, got {_json_type(sig)}"
    names = sorted(sig)
    if names != ["ed25519", "key"]:
        return f"sig must have exactly the fields ed25519 and key, got {', '.join(map(repr, names)) or 'none'}"
    if not (type(sig["key"]) is str and _KEY_ID.fullmatch(sig["key"])):
        return f"sig.key must be {KEY_ID_HEX} lowercase hex digits (the key id), got {_brief(sig['key'])}"
    if not (type(sig["ed25519"]) is str and _ED25519.fullmatch(sig["ed25519"])):
        return f"sig.ed25519 must be a 64-byte signature in standard base64 (88 characters), got {_brief(sig['ed25519'])}"
    return None


def sig_ok(sig: Any) -> bool:
    """sig_problem(sig) is None, in one pass (the append path's fast check)."""
    return (type(sig) is dict and len(sig) == 2 and type(sig.get("key")) is str and type(sig.get("ed25519")) is str
            and _KEY_ID.fullmatch(sig["key"]) is not None and _ED25519.fullmatch(sig["ed25519"]) is not None)


def sign_event(event: dict, signing_key: Any, kid: str | None = None) -> dict:
    """A copy of the event with its `sig`, made with `signing_key` (a nacl SigningKey); `kid`, its
    key id, if the caller has it at hand. An existing `sig` is replaced: a signature never covers
    another signature."""
    unsigned = {name: value for name, value in event.items() if name != SIG_FIELD}
    signature = signing_key.sign(canonical_json(unsigned)).signature
    kid = kid or key_id(bytes(signing_key.verify_key))
    return {**unsigned, SIG_FIELD: {"key": kid, "ed25519": base64.b64encode(signature).decode("ascii")}}


def signature_reason(event: dict, verify_key: Any) -> str | None:
    """None if the event's signature verifies with this key (a nacl VerifyKey), else what is wrong.

    The event's `sig` must have passed sig_problem (the envelope's check) first."""
    from nacl.exceptions import BadSignatureError

    try:
        signature = base64.b64decode(event[SIG_FIELD]["ed25519"], validate=True)
        verify_key.verify(signed_bytes(event), signature)
    except (BadSignatureError, binascii.Error, ValueError):
        return "the signature does not match the event: the event was altered after signing, or forged"
    return None


def _json_type(value: Any) -> str:
    return {dict: "object", list: "array", str: "string", bool: "boolean", type(None): "null"}.get(
        type(value), "number")


def _brief(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:39] + "…"
