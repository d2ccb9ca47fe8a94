"""Seals on the cache file's entries: a derived cache can make reads faster, never different.

The cache file (store/cache.py) sits beside the store, and whoever holds the folder can write it:
one inserted state snapshot turned a mitigated verdict punishable while the chains verified
(issue 15, finding 2). So every entry is sealed with an HMAC-SHA256 under a secret key that is
kept outside the store's folder (`$XDG_CONFIG_HOME/mind-the-gaps/cache.key`, default
`~/.config/...`, created 0600 on first use): an entry whose seal does not open was not written by
this code under this key, so it is dropped and rebuilt, never believed, and counted.

The seal covers the entry's table, its key (run, chain length, head hash, and whatever else
names it) and its payload, each length-prefixed, so that no entry's bytes can be moved under
another key or table. A holder of the key file (the same user's account) can still forge a
seal; the cache is then no weaker than the store itself, whose chains anyone can recompute.

Where the key cannot be kept (no writable config home), the cache lives in memory with a key made
for this process: a persistent cache that any process could seal would protect nothing.
"""
from __future__ import annotations

import hmac
import os
import secrets
import struct
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable

KEY_BYTES = 32
SEAL_BYTES = 32
_KEY_NAME = "cache.key"


def key_path() -> str:
    """Where the cache key is kept: outside every store's folder, in the user's config home."""
    home = os.environ.get("XDG_CONFIG_HOME") or os.path.join(Path.home(), ".config")
    return os.path.join(home, "mind-the-gaps", _KEY_NAME)


def load_or_create_key(path: str | None = None) -> bytes | None:
    """The persistent cache key, created (0600, atomically: two processes starting together end
    with one key) if there is none; None when it can be neither read nor made, or the file is not
    a key (then no persistent cache is kept: the caller falls back to memory)."""
    path = path or key_path()
    try:
        return _read_key(path)
    except FileNotFoundError:
        pass
    except OSError:
        return None
    try:
        _create_key(path)
        return _read_key(path)
    except OSError:
        return None


def _read_key(path: str) -> bytes | None:
    with open(path, "rb") as handle:
        data = handle.read(KEY_BYTES + 1)
    return data if len(data) == KEY_BYTES else None


def _create_key(path: str) -> None:
    """Write a fresh key under a temporary name, then link it into place: the key file appears
    whole or not at all, and a key another process linked first wins."""
    folder = os.path.dirname(path)
    os.makedirs(folder, mode=0o700, exist_ok=True)
    temp = os.path.join(folder, f".{_KEY_NAME}.{os.getpid()}.{secrets.token_hex(4)}")
    fd = os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    try:
        os.write(fd, secrets.token_bytes(KEY_BYTES))
        os.fsync(fd)
    finally:
        os.close(fd)
    try:
        os.link(temp, path)
    except FileExistsError:
        pass
    finally:
        os.unlink(temp)


def memory_key() -> bytes:
    """A key for a cache that lives in memory only: it dies with the process, as the cache does."""
    return secrets.token_bytes(KEY_BYTES)


_LENGTH = struct.Struct(">Q").pack


def _framed(parts: Iterable[Any], start: bytes = b"") -> bytes:
    """Each part typed and length-prefixed, so that different tuples never frame alike; after
    `start` (parts framed already). (Joined once at the end: a judgement opens thousands of
    kept entries, each framed here.)"""
    out: list[bytes] = [start]
    for part in parts:
        if type(part) is str:
            tag, data = b"s", part.encode("utf-8", "surrogatepass")
        elif isinstance(part, bytes):
            tag, data = b"b", part
        elif isinstance(part, bool) or part is None:
            tag, data = b"n", repr(part).encode()
        elif isinstance(part, int):
            tag, data = b"i", str(part).encode()
        elif isinstance(part, float):
            tag, data = b"f", part.hex().encode()
        else:
            tag, data = b"s", str(part).encode("utf-8", "surrogatepass")
        out += (tag, _LENGTH(len(data)), data)
    return b"".join(out)


@dataclass
class Sealer:
    """Seals and opens the entries of one cache under its key, and counts what it had to drop."""

    key: bytes
    dropped: Counter[str] = field(default_factory=Counter)
    """Entries whose seal did not open, per table, since this cache was opened."""
    on_drop: Callable[[], None] | None = None
    """Told of each entry dropped (store/cache.py counts them per cache file for the warning)."""

    def seal(self, table: str, key_parts: tuple[Any, ...], payload: Any) -> bytes:
        """The seal of one entry: its table, what names it (run, chain length, head, ...) and its
        payload (bytes, text, a number, or a tuple of them)."""
        values = payload if isinstance(payload, tuple) else (payload,)
        message = _framed((table, len(key_parts), *key_parts, *values))
        return hmac.digest(self.key, message, "sha256")     # one call into OpenSSL, not an HMAC object

    def opens(self, table: str, key_parts: tuple[Any, ...], payload: Any, seal: Any, *, count: bool = True) -> bool:
        """Does the entry carry its own seal? A failure is counted against the table (unless
        `count` is False: a check that reports rather than reads): the caller must then treat the
        entry as absent (and should delete it)."""
        return self._checked(table, self.seal(table, key_parts, payload), seal, count)

    def prefix(self, table: str, key_parts: tuple[Any, ...]) -> bytes:
        """The framed start of the seal of every entry of the table named by `key_parts` and
        one part more (a run's kept entries of one kind share all but their key): framed once
        for them all, not once an entry (`opens_after`)."""
        return _framed((table, len(key_parts) + 1, *key_parts))

    def opens_after(self, table: str, prefix: bytes, last: Any, payload: Any, seal: Any) -> bool:
        """`opens` of the entry named by the parts `prefix` framed and `last`: the very seal
        `opens` checks, as framing is part by part."""
        values = payload if isinstance(payload, tuple) else (payload,)
        return self._checked(table, hmac.digest(self.key, _framed((last, *values), prefix), "sha256"), seal)

    def _checked(self, table: str, expected: bytes, seal: Any, count: bool = True) -> bool:
        """Whether the entry's seal is the one expected; a failure counted against the table."""
        good = isinstance(seal, bytes) and hmac.compare_digest(expected, seal)
        if not good and count:
            self.dropped[table] += 1
            if self.on_drop is not None:
                self.on_drop()
        return good

    def tampered(self) -> dict[str, int]:
        """Entries dropped so far, per table."""
        return dict(self.dropped)


def xor(a: bytes, b: bytes) -> bytes:
    """Two seals combined: the digest of a set of entries is the XOR of their seals, updated as one
    entry is replaced (XOR the old seal out, the new in), so that an entry removed from the set,
    or one put back from an older set, shows without sealing the whole set again."""
    return (int.from_bytes(a, "big") ^ int.from_bytes(b, "big")).to_bytes(SEAL_BYTES, "big")


NO_ENTRIES = bytes(SEAL_BYTES)  # the digest of an empty set
