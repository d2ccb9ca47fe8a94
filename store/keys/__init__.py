"""Keys and what they sign: a source's private key and the public keys a verifier trusts, the
signatures on events, signed tree heads, the witness files that keep them outside a store, and
the checks of a store against them (`gaps keys`, `gaps verify --against`). This is its face:
other rooms import from here (`from store.keys import X`), never from a module inside.

    files       keys on disk: a source's private key, the public keys file, the signer
    signatures  Ed25519 signatures on events
    tally       what `gaps verify` finds about signatures
    tree_heads  signed tree heads: a checkpoint as a statement the ingest's key signs
    witness     signed tree heads kept outside the store, as JSON lines
    trust_root  what decides, from outside the store file, whether a run is as signed
    anchors     a store checked against what is kept outside it
"""
from .anchors import AnchorReport, HeadOutcome, KeyCheck, KeyedRun, KeyProblem, RunProof
from .files import PUBLIC_KEYS_FILE, KeyFolder, KeysError, Signer, TrustedKeys
from .signatures import SIG_FIELD, key_id, sign_event, signed_bytes
from .tree_heads import CheckpointKey, TreeHead, load_public, public_path_of
from .trust_root import recorded_heads
from .witness import WitnessError, WitnessFile, read_heads

__all__ = [
    "AnchorReport", "CheckpointKey", "HeadOutcome", "KeyCheck", "KeyFolder", "KeyProblem", "KeyedRun", "KeysError",
    "PUBLIC_KEYS_FILE", "RunProof", "SIG_FIELD", "Signer",
    "TreeHead", "TrustedKeys", "WitnessError", "WitnessFile", "key_id", "load_public", "public_path_of",
    "read_heads", "recorded_heads", "sign_event", "signed_bytes",
]
