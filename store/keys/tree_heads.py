"""Signed tree heads: a checkpoint as a statement the ingest's key signs, and that key on disk.

A checkpoint written into the store proves nothing against someone who holds the file: they can
rewrite a run and write checkpoints to match. Signed by a key the holder of the file does not
have, and copied somewhere else (a witness file, a Zenoh key: store/witness.py), it does: the
statement names the run (by its name, which does not depend on the file), its size (events in
its chain), the Merkle root and chain head of those events, the size of the run's previous
checkpoint, when it was written, and the signing key's id. Its canonical JSON is what is signed,
so the same head read from a witness line or rebuilt from a checkpoint row checks the same way.
Since schema v8 a head also carries `wire`: where the wire tables' chains (liveliness changes,
wire misses) stood when the checkpoint was written (store/wire_ends.py), and is then the statement
`gaps.tree_head.v2`; a head without it (written before v8) is the v1 statement, checked as before
for the events it covers. The wire part may also carry `rulebooks`, the stored rulebooks' chain's
end (store/rulebook_chain.py), which every head written since records; the statement stays v2
(its canonical JSON is the part as recorded, so a part without the key signs and checks as it did).

The checkpoint key is an Ed25519 private key in PKCS#8 PEM, as a source's key is
(store/keyfiles.py), readable by its owner only; its public half is a text file beside it
(`<key>.pub`, the 32-byte public key in standard base64) for investigators (`gaps verify --key`).
"""

from __future__ import annotations

import base64
import binascii
import json
import os
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from ..canonical import canonical_json
from ..chain import is_digest_hex
from .files import KeysError, pem_of, seed_of
from ..output_files import check_output, create_new, write_text
from .signatures import key_id
from ..text_file import read_named
from ..wire.ends import WireEnd, from_part, to_part

STATEMENT = "gaps.tree_head.v1"
STATEMENT_WIRE = "gaps.tree_head.v2"  # the same, with the wire tables' ends
PUBLIC_SUFFIX = ".pub"


@dataclass(frozen=True)
class TreeHead:
    """One run's tree at one size, as a checkpoint records it; `sig` (base64) once signed."""

    run: str
    size: int
    root: str          # Merkle root of the first `size` events, hex
    head: str          # chain hash of event size-1, hex
    prev_size: int     # size of the run's previous checkpoint (0 for its first)
    created_at: int    # ns since the epoch, when the checkpoint was written
    key: str | None = None  # id of the signing key (16 hex digits)
    sig: str | None = None
    wire: tuple[WireEnd, ...] | None = None  # the wire tables' ends (v8 on); None in a head written before

    def statement(self) -> bytes:
        """The bytes the signature covers: every field but `sig`, with the statement's name (v2
        with the wire part, v1 without: a head written before v8 checks as it was signed)."""
        fields = {"run": self.run, "size": self.size, "root": self.root, "head": self.head,
                  "prev_size": self.prev_size, "created_at": self.created_at, "key": self.key}
        if self.wire is None:
            return canonical_json({"statement": STATEMENT, **fields})
        return canonical_json({"statement": STATEMENT_WIRE, **fields, "wire": to_part(self.wire)})

    def wire_part(self) -> dict[str, Any] | None:
        """The wire part as a witness line and a checkpoint row hold it (None: not covered)."""
        return None if self.wire is None else to_part(self.wire)

    def to_json(self) -> dict[str, Any]:
        found = {name: getattr(self, name) for name in ("run", "size", "root", "head", "prev_size", "created_at",
                                                       "key", "sig")}
        return found if self.wire is None else {**found, "wire": to_part(self.wire)}

    @classmethod
    def from_json(cls, data: Any, where: str) -> TreeHead:
        """A head read from a witness line; a KeysError naming `where` and the field that is wrong."""
        if not isinstance(data, dict):
            raise KeysError(f"{where}: a tree head is a JSON object, got {type(data).__name__}")
        try:
            head = cls(**{name: data[name] for name in ("run", "size", "root", "head", "prev_size", "created_at")},
                       key=data.get("key"), sig=data.get("sig"), wire=_wire_of(data.get("wire")))
        except KeyError as exc:
            raise KeysError(f"{where}: the tree head has no {exc.args[0]!r}") from None
        except ValueError as exc:
            raise KeysError(f"{where}: {exc}") from None
        problem = head.shape_problem()
        if problem:
            raise KeysError(f"{where}: {problem}")
        return head

    @classmethod
    def of_checkpoint(cls, run: str, count: Any, root: Any, head: Any, prev: Any, created_at: Any, key: Any,
                      sig: Any, wire: Any) -> TreeHead:
        """The head a checkpoint row records (its `wire` column is the part's JSON text, or NULL);
        ValueError if that column is not a wire part."""
        if wire is None:
            return cls(run, count, root, head, prev, created_at, key, sig)
        if not isinstance(wire, str):
            raise ValueError("the checkpoint's wire column is not text")
        return cls(run, count, root, head, prev, created_at, key, sig, from_part(json.loads(wire)))

    def shape_problem(self) -> str | None:
        checks = ((isinstance(self.run, str), "run must be text"),
                  (type(self.size) is int and self.size > 0, "size must be a positive integer"),
                  (is_digest_hex(self.root), "root must be 64 hex digits"),
                  (is_digest_hex(self.head), "head must be 64 hex digits"),
                  (type(self.prev_size) is int and 0 <= self.prev_size < self.size, "prev_size must be below size"),
                  (type(self.created_at) is int, "created_at must be an integer"),
                  (self.key is None or isinstance(self.key, str), "key must be text"),
                  (self.sig is None or isinstance(self.sig, str), "sig must be base64 text"))
        return next((what for ok, what in checks if not ok), None)

    def signature_problem(self, public: bytes) -> str | None:
        """None if the head is signed by this public key (32 bytes); else why not."""
        from nacl.exceptions import BadSignatureError
        from nacl.signing import VerifyKey

        if self.sig is None:
            return "unsigned"
        if self.key != key_id(public):
            return f"signed with key {self.key}, not {key_id(public)}"
        try:
            VerifyKey(public).verify(self.statement(), base64.b64decode(self.sig, validate=True))
        except (BadSignatureError, binascii.Error, ValueError):
            return f"the signature of key {self.key} does not match the head: it was altered or forged"
        return None


def _wire_of(data: Any) -> tuple[WireEnd, ...] | None:
    return None if data is None else from_part(data)


class CheckpointKey:
    """The ingest's private key that signs checkpoints."""

    def __init__(self, seed: bytes) -> None:
        from nacl.signing import SigningKey

        self._signing = SigningKey(seed)
        self.public = bytes(self._signing.verify_key)
        self.id = key_id(self.public)
        self.path: Path | None = None  # where it was read: its public key file (`<path>.pub`) records signed runs

    def public_file(self) -> Path | None:
        """The public key file beside the key (store/trust_root.py), if the key was read from a file."""
        return None if self.path is None else public_path_of(self.path)

    @classmethod
    def load(cls, path: str | os.PathLike) -> CheckpointKey:
        """Read a checkpoint key; a KeysError names the file and what is wrong with it."""
        text = read_named(path, "checkpoint key", KeysError, "ascii", f" (gaps keys checkpoint {path} makes one)")
        key = cls(seed_of(text, str(path)))
        key.path = Path(path)
        return key

    @classmethod
    def create(cls, path: str | os.PathLike) -> CheckpointKey:
        """A new key at `path` and its public half at `path`.pub; never overwrites a key."""
        from nacl.signing import SigningKey

        seed = bytes(SigningKey.generate())
        public_path = public_path_of(path)
        check_output(public_path)       # both halves checked before either is written
        try:
            fd = create_new(path, 0o600)
        except FileExistsError:
            raise KeysError(f"{path} exists: a checkpoint key is never overwritten") from None
        except OSError as exc:
            raise KeysError(f"cannot write {path}: {exc.strerror or exc}") from None
        with os.fdopen(fd, "w") as out:
            out.write(pem_of(seed))
        key = cls(seed)
        key.path = Path(path)
        try:
            write_text(public_path, base64.b64encode(key.public).decode("ascii") + "\n")
        except OSError as exc:
            raise KeysError(f"cannot write {public_path}: {exc.strerror or exc}") from None
        return key

    def sign(self, head: TreeHead) -> TreeHead:
        """The head with this key's id and signature."""
        named = replace(head, key=self.id, sig=None)
        signature = self._signing.sign(named.statement()).signature
        return replace(named, sig=base64.b64encode(signature).decode("ascii"))


def public_path_of(path: str | os.PathLike) -> Path:
    return Path(f"{os.fspath(path)}{PUBLIC_SUFFIX}")


def load_public(path: str | os.PathLike) -> bytes:
    """A checkpoint public key file's key (`<key>.pub`: its first line, standard base64 of 32 bytes;
    the lines after it record signed runs, store/trust_root.py); KeysError if not."""
    lines = read_named(path, "public key file", KeysError).strip().splitlines()
    text = lines[0].strip() if lines else ""
    try:
        public = base64.b64decode(text, validate=True)
    except binascii.Error:
        raise KeysError(f"{path}: not a public key (one line of base64, as `gaps keys checkpoint` writes)") from None
    if len(public) != 32:
        raise KeysError(f"{path}: the key is {len(public)} bytes; an Ed25519 public key is 32")
    return public
