"""What a new user meets first: --version, -h on every command, shell completion, short help that
is one whole sentence, and `-` for standard input and output wherever a file is taken."""
import json

import pytest
from typer.main import get_command

from cli.main import app
from sim_replay.paper import RUN
from tests.helpers.cli import gaps

ROOT = get_command(app)


def commands(group=ROOT, path=()):
    """Every command and group below the app, as its path of names."""
    for name, command in group.commands.items():
        yield (*path, name), command
        if hasattr(command, "commands"):
            yield from commands(command, (*path, name))


ALL = list(commands())


@pytest.mark.parametrize("flag", ["--version", "-V"])
def test_version(flag, tmp_path):
    result = gaps(flag, db=None)
    assert result.exit_code == 0 and result.stdout.startswith("gaps (mind-the-gaps) ")


@pytest.mark.parametrize("path", [p for p, _ in ALL] + [()], ids=lambda p: " ".join(p) or "gaps")
def test_h_is_help_on_every_command(path, tmp_path):
    short = gaps(*path, "-h", db=None)
    assert short.exit_code == 0 and "Usage: " in short.stdout
    assert short.stdout == gaps(*path, "--help", db=None).stdout


def test_shell_completion_is_offered(tmp_path):
    shown = gaps("--help", db=None, columns=100).stdout
    assert "--install-completion" in shown and "--show-completion" in shown


@pytest.mark.parametrize("path, command", ALL, ids=lambda p: " ".join(p) if isinstance(p, tuple) else "")
def test_short_help_is_one_whole_sentence(path, command):
    """The first paragraph of a docstring is what `gaps --help` lists: one sentence on one line,
    so no terminal width cuts it mid-thought, and Typer never joins it with the next."""
    text = command.help or ""
    first = text.strip().split("\n\n")[0]
    assert "\n" not in first, f"{' '.join(path)}: the summary runs over lines: {first!r}"
    assert first[:1].isupper() and first.endswith("."), f"{' '.join(path)}: {first!r}"
    assert first.count(". ") == 0, f"{' '.join(path)}: more than one sentence: {first!r}"


def test_export_to_stdout_imports_from_stdin(paper_db, tmp_path):
    exported = gaps("export", "--run", RUN, "-o", "-", db=paper_db)
    assert exported.exit_code == 0, exported.output
    lines = exported.stdout.splitlines()
    assert len(lines) == 20 and all(json.loads(line)["run"] == RUN for line in lines)
    assert "exported run paper-junctions: 20 events" in exported.stderr
    copy = tmp_path / "copy.db"
    imported = gaps("import", "-", "--format", "jsonl", "--json", db=copy, input=exported.stdout)
    assert imported.exit_code == 0, imported.output
    assert (json.loads(imported.stdout)["stored"], json.loads(imported.stdout)["file"]) == (20, "-")


def test_import_from_stdin_needs_a_format(tmp_path):
    result = gaps("import", "-", db=tmp_path / "gaps.db", input="")
    assert result.exit_code == 2 and "needs --format" in result.stderr
    assert not (tmp_path / "gaps.db").exists()


def test_report_to_stdout(paper_db):
    result = gaps("report", "--run", RUN, "-o", "-", "--format", "md", db=paper_db)
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("# Incident report: run paper-junctions") and result.stderr == ""
    assert gaps("report", "--run", RUN, "-o", "-", db=paper_db).stdout.startswith("<!DOCTYPE html>")
    refused = gaps("report", "--run", RUN, "-o", "-", "--pdf", db=paper_db)
    assert refused.exit_code == 2 and "give -o FILE" in refused.stderr


def test_rules_check_reads_stdin(tmp_path):
    from reasoner.bundled import RULES_DIR
    text = (RULES_DIR / "paper.le").read_text(encoding="utf-8")
    result = gaps("rules", "check", "-", db=None, input=text)
    assert result.exit_code == 0 and result.stdout.startswith("stdin.le: ok (")


def test_help_paragraphs_are_reflowed_not_broken_where_the_source_breaks():
    wide = gaps("verify", "-h", db=None, columns=240).stdout
    assert "2 for a usage error such as a missing store or run. Snapshots, and the index of where each road user was, live in the cache beside the store" in wide
