"""The explanation tests build their runs with the verdict-path builder (tests/reasoner/runs.py)."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parents[1] / "reasoner"))
