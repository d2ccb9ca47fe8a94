"""The trust root of signed checkpoints: what decides, from outside the store file, whether a run
must be signed and which signed head its tail must extend (issue 37).

Nothing in the store may decide that: the file's holder can change a checkpoint's id, null its
key id or replace it by an unsigned one, and did, to make `gaps verify --key` take a rewritten run
for one written before signing began, and to have the ingest sign a checkpoint over forged events.
Two things the holder of the store does not hold decide it instead:

- **The public key file** (`KEY.pub`, beside the checkpoint key). Its first line is the key (one
  line of base64, as before); each further line is the first signed tree head of a run, appended
  (and fsynced) by the writer that signed it, once per run: a run listed there was signed from
  that head on, and every checkpoint of it from that head on must be signed by the key. An
  investigator's copy of the file is what `gaps verify --key` trusts; a head in it whose signature
  does not hold is refused with the file's line.
- **The witness file** (`gaps serve --witness`): the last head of each run in it is the run's last
  signed head; the ingest reads it when it opens the store and, from then on, keeps each head it
  signs. A run's tail must extend that head before the ingest extends the run.

The key file records a run by its name, as heads do; a key that signs runs of one name in two
stores records a first head for each (a run must extend one of them). A run neither names (no line
in the key file, no head in the witness) and whose checkpoints carry no signature was never signed
by this key: a writer with the key may begin signing it (its first signed head then goes into the
key file). A run with signed checkpoints that neither names (a key file from before its runs were
recorded) must end on a checkpoint signed by the key.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Iterable

from .files import KeysError
from .signatures import key_id
from .tree_heads import TreeHead


class SignedRuns:
    """Each run's first signed heads the key file records and last signed head known outside the
    store, for one checkpoint key and one store."""

    def __init__(self, public: bytes, ledger: Path | None = None, witness: Path | None = None) -> None:
        self.public = public
        self.ledger = ledger
        self.first: dict[str, list[TreeHead]] = {}  # run -> its first signed heads (one per store it was signed in)
        self.last: dict[str, tuple[TreeHead, str]] = {}  # run -> (head, where it was read)
        self.here: set[str] = set()  # runs whose first signed head in this store the key file holds
        self.problem: str | None = None  # why the key file could not record a run's first signed head
        if ledger is not None:
            for head in recorded_heads(ledger, public):
                self.first.setdefault(head.run, []).append(head)
        if witness is not None and Path(witness).exists() and Path(witness).stat().st_size > 0:
            self._read_witness(Path(witness))

    def where(self) -> str:
        return f"the key file {self.ledger}"

    def signed(self, heads: Iterable[TreeHead]) -> None:
        """Heads this writer signed and committed: each is its run's last; the first of a run the key
        file does not yet hold for this store goes into it. The commit is done, so a key file that
        cannot be written does not fail the append: `problem` says why, the run's next head is tried
        again, and a later writer still demands the run's tail be signed (its checkpoints carry
        signatures)."""
        new: dict[str, TreeHead] = {}
        self.problem = None
        for head in heads:
            self.last[head.run] = (head, "this writer's last signed head")
            if head.run not in self.here:
                new.setdefault(head.run, head)
        if not new:
            return
        if self.ledger is not None:
            try:
                append_heads(self.ledger, list(new.values()))
            except KeysError as exc:
                self.problem = str(exc)
                return
        for run, head in new.items():
            self.first.setdefault(run, []).append(head)
            self.here.add(run)

    def _read_witness(self, path: Path) -> None:
        from .witness import read_heads

        latest: dict[str, TreeHead] = {}
        for head in read_heads(path):
            if head.key == key_id(self.public):
                latest[head.run] = head
        for run, head in latest.items():
            problem = head.signature_problem(self.public)
            if problem is not None:
                raise KeysError(f"{path}: the last head of run {run} is not signed by the checkpoint key: {problem}")
            self.last[run] = (head, f"the witness file {path}")


def recorded_heads(path: str | os.PathLike, public: bytes) -> list[TreeHead]:
    """The runs' first signed heads a public key file records (its lines after the key), each
    checked against the key; a KeysError names the line that is wrong."""
    try:
        lines = Path(path).read_text("utf-8").splitlines()
    except FileNotFoundError:
        return []
    except (OSError, UnicodeDecodeError) as exc:
        raise KeysError(f"cannot read the public key file {path}: {getattr(exc, 'strerror', None) or exc}") from None
    heads = []
    for number, line in enumerate(lines[1:], 2):
        if not line.strip():
            continue
        where = f"{path}:{number}"
        try:
            head = TreeHead.from_json(json.loads(line), where)
        except ValueError as exc:
            raise KeysError(f"{where}: not a JSON line ({exc})") from None
        problem = head.signature_problem(public)
        if problem is not None:
            raise KeysError(f"{where}: the first signed head of run {head.run} is not signed by this file's key: "
                            f"{problem}")
        heads.append(head)
    return heads


def append_heads(path: Path, heads: list[TreeHead]) -> None:
    """Append runs' first signed heads to the public key file, one JSON line each, fsynced."""
    data = "".join(json.dumps(head.to_json(), sort_keys=True, separators=(",", ":")) + "\n" for head in heads)
    try:
        fd = os.open(path, os.O_RDWR | os.O_APPEND)
    except OSError as exc:
        raise KeysError(f"cannot record the first signed heads in the public key file {path}: "
                        f"{exc.strerror or exc}") from None
    try:
        if os.lseek(fd, 0, os.SEEK_END) > 0 and os.pread(fd, 1, os.lseek(fd, 0, os.SEEK_END) - 1) != b"\n":
            data = "\n" + data  # a key line written without its newline
        os.write(fd, data.encode("utf-8"))
        os.fsync(fd)
    except OSError as exc:
        raise KeysError(f"cannot write the public key file {path}: {exc.strerror or exc}") from None
    finally:
        os.close(fd)
