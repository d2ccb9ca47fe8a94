"""Keys on disk: a source's private key, the public keys file a verifier trusts, and the signer.

A key folder holds one private key per source, `<folder>/<role>/<id>.key` (`vehicle/173` in
`keys/vehicle/173.key`): an Ed25519 private key in PKCS#8 PEM (RFC 8410), the form
`openssl genpkey -algorithm ed25519` writes and `openssl pkey` reads, readable by its owner only.
`cryptography` reads and writes it (a hand-built DER prefix refused valid keys, such as RFC 8410's
own example carrying its public key); signing stays with PyNaCl, as it was measured (bench/signatures.py).

The public keys file is what an ingest (`gaps serve --require-signatures FILE`) and an
investigator (`gaps verify --keys FILE`) trust: a JSON object from a source, or a pattern of
sources (`monitor/*`, matched as shell patterns are, case-sensitive), to its public key in
standard base64 (32 bytes), or to a list of them (keys being rotated):

    {"vehicle/173": "9Vd2tZ0s…=", "monitor/*": ["mq3X…=", "0x7b…="]}

An event's signature is accepted only from a key listed for a pattern its `src` matches: a key
of vehicle/174 cannot sign for vehicle/173.
"""

from __future__ import annotations

import base64
import binascii
import json
import os
import re
from fnmatch import fnmatchcase
from pathlib import Path
from typing import Any, Iterable, cast

from ..envelope import is_source
from ..errors import GapsError
from ..output_files import write_text
from .signatures import SIG_FIELD, key_id, sign_event, signature_reason

PUBLIC_KEYS_FILE = "public-keys.json"
KEY_SUFFIX = ".key"
_PATTERN = re.compile(r"[A-Za-z0-9._*?\[\]!-]+/[A-Za-z0-9._*?\[\]!-]+")
_CACHE_LIMIT = 1 << 16

__all__ = ["KeyFolder", "KeysError", "PUBLIC_KEYS_FILE", "Signer", "TrustedKeys"]


class KeysError(GapsError):
    """A key file or folder that cannot be used as asked; the message names the file and what is wrong."""


# --- private keys ----------------------------------------------------------------------------------


def pem_of(seed: bytes) -> str:
    """The PKCS#8 PEM text of an Ed25519 private key (its 32-byte seed), as `cryptography`
    serialises it (RFC 8410, what `openssl genpkey -algorithm ed25519` writes)."""
    from cryptography.hazmat.primitives import serialization
    from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
    key = Ed25519PrivateKey.from_private_bytes(seed)
    return key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8,
                             serialization.NoEncryption()).decode("ascii")


def seed_of(pem: str, where: str) -> bytes:
    """The 32-byte seed of an Ed25519 private key in PKCS#8 PEM, or a KeysError naming `where`."""
    from cryptography.hazmat.primitives import serialization
    from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
    try:
        key = serialization.load_pem_private_key(pem.encode("utf-8", "surrogateescape"), password=None)
    except TypeError:
        raise KeysError(f"{where}: the private key is encrypted; give it unencrypted (the source's own "
                        "file, readable by its owner only)") from None
    except (ValueError, UnicodeError) as exc:
        raise KeysError(f"{where}: not a private key in PEM (-----BEGIN PRIVATE KEY----- ...): {exc}") from None
    except Exception as exc:    # an algorithm this cryptography does not support
        raise KeysError(f"{where}: not a key this can read: {exc}") from None
    if not isinstance(key, Ed25519PrivateKey):
        raise KeysError(f"{where}: not an Ed25519 private key (it is an {type(key).__name__.lstrip('_')})")
    return key.private_bytes(serialization.Encoding.Raw, serialization.PrivateFormat.Raw,
                             serialization.NoEncryption())


class KeyFolder:
    """One private key per source, `<folder>/<role>/<id>.key`."""

    def __init__(self, path: str | os.PathLike) -> None:
        self.path = Path(path)

    def key_path(self, src: str) -> Path:
        if not is_source(src):
            raise KeysError(f"{src!r} is not a source: write <role>/<id>, e.g. vehicle/173")
        role, _, ident = src.partition("/")
        return self.path / role / f"{ident}{KEY_SUFFIX}"

    def create(self, src: str) -> Path:
        """A new key for the source; refuses to overwrite one (a lost private key cannot be undone)."""
        from nacl.signing import SigningKey

        path = self.key_path(src)
        try:
            path.parent.mkdir(mode=0o700, parents=True, exist_ok=True)
            fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        except FileExistsError:
            raise KeysError(f"{path} exists: a source's key is never overwritten") from None
        except OSError as exc:
            raise KeysError(f"cannot write {path}: {exc.strerror or exc}") from None
        with os.fdopen(fd, "w") as out:
            out.write(pem_of(bytes(SigningKey.generate())))
        return path

    def seed(self, src: str) -> bytes | None:
        """The source's private key (32 bytes), or None if the folder has none for it."""
        path = self.key_path(src)
        try:
            text = path.read_text("ascii")
        except FileNotFoundError:
            return None
        except (OSError, UnicodeDecodeError) as exc:
            raise KeysError(f"cannot read {path}: {getattr(exc, 'strerror', None) or exc}") from None
        return seed_of(text, str(path))

    def sources(self) -> list[str]:
        """Every source with a key here, sorted."""
        if not self.path.is_dir():
            raise KeysError(f"no key folder at {self.path}")
        found = (f"{p.parent.name}/{p.name[:-len(KEY_SUFFIX)]}" for p in self.path.glob(f"*/*{KEY_SUFFIX}"))
        return sorted(src for src in found if is_source(src))

    def public_key(self, src: str) -> bytes:
        """The source's public key (32 bytes); a KeysError if the folder has no key for it."""
        from nacl.signing import SigningKey

        seed = self.seed(src)
        if seed is None:
            raise KeysError(f"no key for {src} in {self.path}")
        return bytes(SigningKey(seed).verify_key)

    def public_keys(self) -> dict[str, str]:
        """{src: public key in base64} for every key here: the public keys file's content."""
        return {src: base64.b64encode(self.public_key(src)).decode("ascii") for src in self.sources()}

    def write_public_keys(self, path: str | os.PathLike | None = None) -> Path:
        """Write the public keys file (default `<folder>/public-keys.json`); returns where."""
        target = Path(path) if path is not None else self.path / PUBLIC_KEYS_FILE
        try:
            return write_text(target, json.dumps(self.public_keys(), indent=2, sort_keys=True) + "\n")
        except OSError as exc:
            raise KeysError(f"cannot write {target}: {exc.strerror or exc}") from None


class Signer:
    """Signs each event with its source's key from a key folder; with `create`, a source without
    a key gets a new one (a simulation's road users are not known in advance)."""

    def __init__(self, folder: KeyFolder, *, create: bool = False) -> None:
        self.folder = folder
        self.create = create
        self._keys: dict[str, tuple[Any, str]] = {}  # src -> (SigningKey, key id)

    def sign(self, event: dict) -> dict:
        """The event with its `sig`; a KeysError if its source has no key and none may be made."""
        key = self._keys.get(event["src"]) or self._load(event["src"])
        return sign_event(event, *key)

    def _load(self, src: str) -> tuple[Any, str]:
        from nacl.signing import SigningKey

        seed = self.folder.seed(src)
        if seed is None:
            if not self.create:
                raise KeysError(f"no key for {src} in {self.folder.path} (gaps keys new {self.folder.path} {src})")
            self.folder.create(src)
            seed = self.folder.seed(src)
        signing = SigningKey(cast(bytes, seed))  # just made: the folder holds it now
        self._keys[src] = entry = (signing, key_id(bytes(signing.verify_key)))
        return entry


# --- public keys ------------------------------------------------------------------------------------


class TrustedKeys:
    """The public keys file, ready to judge events: `reason(event)` says why one is not proven to
    come from its source (None when its signature verifies with a key trusted for its source)."""

    def __init__(self, entries: Iterable[tuple[str, bytes]], origin: str) -> None:
        from nacl.signing import VerifyKey

        self.origin = origin
        self.entries = [(pattern, public) for pattern, public in entries]
        self._by_id: dict[str, list[tuple[str, Any]]] = {}
        for pattern, public in self.entries:
            self._by_id.setdefault(key_id(public), []).append((pattern, VerifyKey(public)))
        self._for: dict[tuple[str, str], list[Any]] = {}  # (key id, src) -> the keys to try

    @classmethod
    def load(cls, path: str | os.PathLike) -> TrustedKeys:
        """Read a public keys file; a KeysError names the file and the entry that is wrong."""
        try:
            data = json.loads(Path(path).read_text("utf-8"))
        except FileNotFoundError:
            raise KeysError(f"no public keys file at {path}") from None
        except (OSError, UnicodeDecodeError, ValueError) as exc:
            raise KeysError(f"cannot read the public keys file {path}: {exc}") from None
        return cls.from_json(data, str(path))

    @classmethod
    def from_json(cls, data: Any, origin: str) -> TrustedKeys:
        if not isinstance(data, dict) or not data:
            raise KeysError(f"{origin}: a public keys file is a JSON object {{\"<role>/<id or pattern>\": "
                            "\"<base64 public key>\" or [...]}, with at least one entry")
        entries = []
        for pattern, value in data.items():
            if not _PATTERN.fullmatch(pattern):
                raise KeysError(f"{origin}: {pattern!r} is not a source or a pattern of sources (<role>/<id>)")
            for public in value if isinstance(value, list) else [value]:
                entries.append((pattern, _public_key(public, f"{origin}: the key of {pattern}")))
        return cls(entries, origin)

    def __len__(self) -> int:
        return len(self.entries)

    def covers(self, src: str) -> bool:
        """Whether some key is trusted for ``src`` (a source or a pattern naming it): a source with
        none can sign nothing the ingest accepts, so its liveliness token is not recorded either."""
        return any(fnmatchcase(src, pattern) for pattern, _ in self.entries)

    def reason(self, event: dict) -> str | None:
        """None if the event's signature verifies with a key trusted for its src; else why not,
        prefixed with the event's identity. The event must be valid (its envelope checked)."""
        problem = self.problem(event)
        if problem is None:
            return None
        return f"event run={event['run']} src={event['src']} seq={event['seq']}: {problem}"

    def problem(self, event: dict) -> str | None:
        """reason(event) without the event's identity in front."""
        sig = event.get(SIG_FIELD)
        if sig is None:
            return "unsigned, and signatures are required"
        kid, src = sig["key"], event["src"]
        keys = self._for.get((kid, src))
        if keys is None:
            keys = self._keys_for(kid, src)
        if not keys:
            owners = [pattern for pattern, _ in self._by_id.get(kid, ())]
            if owners:
                return f"signed with key {kid}, which is trusted for {', '.join(owners)}, not for {src}"
            return f"signed with key {kid}, which is not in {self.origin}"
        for key in keys:
            if signature_reason(event, key) is None:
                return None
        return f"signed with key {kid}: " + cast(str, signature_reason(event, keys[0]))  # none verified

    def _keys_for(self, kid: str, src: str) -> list[Any]:
        keys = [key for pattern, key in self._by_id.get(kid, ()) if fnmatchcase(src, pattern)]
        if len(self._for) >= _CACHE_LIMIT:  # hostile input can make up a source per event
            self._for.clear()
        self._for[(kid, src)] = keys
        return keys


def _public_key(value: Any, where: str) -> bytes:
    if not isinstance(value, str):
        raise KeysError(f"{where} must be a base64 string (or a list of them), got {type(value).__name__}")
    try:
        public = base64.b64decode(value, validate=True)
    except binascii.Error:
        raise KeysError(f"{where} is not base64") from None
    if len(public) != 32:
        raise KeysError(f"{where} is {len(public)} bytes; an Ed25519 public key is 32")
    return public
