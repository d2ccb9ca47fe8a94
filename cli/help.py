"""`gaps help [COMMAND]...`: the help of gaps, or of one of its commands, as `--help` prints it."""
from __future__ import annotations

from typing import Optional

import typer

from cli.app import fail


def help_(ctx: typer.Context,
          command: Optional[list[str]] = typer.Argument(None, metavar="COMMAND", help="A command, or a group and "
                                                        "its command (rules check); none: gaps itself.")) -> None:
    """Show the help of gaps, or of a command: `gaps help incidents` is `gaps incidents --help`."""
    root = ctx.find_root()
    asked = list(command or [])
    here = root.command
    for i, name in enumerate(asked):
        known = getattr(here, "commands", None) or {}
        if name not in known:
            said = " ".join(asked[:i + 1])
            fail(f"no command {said!r}; commands{' of ' + ' '.join(asked[:i]) if i else ''}: "
                 f"{', '.join(sorted(known)) or 'none'}")
        here = known[name]
    root.command.main([*asked, "--help"], prog_name=root.info_name, standalone_mode=False)
