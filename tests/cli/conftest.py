"""The CLI tests build stores with the store tests' kit (tests/store/store_testkit.py)."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parents[1] / "store"))
