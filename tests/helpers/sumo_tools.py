"""SUMO's own network tools (netgenerate, netconvert) for tests that build networks as a SUMO user would.

They come with the `eclipse-sumo` wheel the set-up installs (its SUMO_HOME/bin); one on PATH is
used otherwise. A test that needs one skips, saying so, where neither is there.
"""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

__all__ = ["sumo_tool", "netgenerate", "netconvert"]


def sumo_tool(name: str) -> str | None:
    """The path of a SUMO binary (netgenerate, netconvert), or None."""
    try:
        import sumo
        candidate = Path(sumo.SUMO_HOME) / "bin" / name
        if candidate.is_file():
            return str(candidate)
    except ImportError:
        pass
    return shutil.which(name)


def _run(name: str, args: list[str], cwd: Path) -> None:
    tool = sumo_tool(name)
    if tool is None:
        pytest.skip(f"{name} is not installed (the eclipse-sumo wheel)")
    done = subprocess.run([tool, "--no-warnings", *args], cwd=cwd, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, f"{name} {' '.join(args)}: {done.stderr}"


def netgenerate(out: Path, *args: str) -> Path:
    """`netgenerate ARGS -o OUT` (a grid, spider or random network)."""
    _run("netgenerate", [*args, "--seed", "1", "-o", str(out)], out.parent)
    return out


def netconvert(out: Path, *args: str) -> Path:
    """`netconvert ARGS -o OUT` (from plain files, or from another network)."""
    _run("netconvert", [*args, "-o", str(out)], out.parent)
    return out
