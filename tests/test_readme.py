"""Every `slosh-bif` command printed in the README works as printed (exit status 0, or the one its
comment announces), read from the
README itself so that the two cannot drift apart: the quick ones (at most 5 s as printed) in the
default run, the rest (marked ``slow`` or longer) by ``pytest -m slow``. Each runs in a fresh folder, in the
order printed (a
command may use a file an earlier one wrote: ``--params tank.toml``)."""

import re
import shlex
from pathlib import Path

import pytest

from slosh_bif.cli import main

README = Path(__file__).resolve().parents[1] / "README.md"


def readme_commands():
    """(command, comment) of each ``$ slosh-bif ...`` line of the README, in order."""
    found = []
    for line in README.read_text().splitlines():
        match = re.match(r"^\$ (slosh-bif .*?)\s+#\s*(.*)$", line)
        if match:
            found.append((match.group(1), match.group(2)))
    return found


QUICK_SECONDS = 5  # a command printed with at most this time runs in the default suite


def _is_slow(comment: str) -> bool:
    """Marked slow, or printed with a time above QUICK_SECONDS (``(8 s)``)."""
    timed = re.search(r"\((\d+(?:\.\d+)?) s\)", comment)
    return "(slow" in comment or (timed is not None and float(timed.group(1)) > QUICK_SECONDS)


def test_the_readme_prints_commands_and_marks_the_slow_ones():
    commands = readme_commands()
    assert (
        len(commands) >= 10
        and any(_is_slow(c) for _, c in commands)
        and any(not _is_slow(c) for _, c in commands)
    )
    assert README.stat().st_size < 12_000


def _expected_status(comment: str) -> int:
    """0, or the exit status the README's comment announces ("exits 3: ...")."""
    match = re.search(r"exits (\d+)", comment)
    return int(match.group(1)) if match else 0


def _run(commands, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "docs").symlink_to(README.parent / "docs")  # the data files the commands read
    for command, comment in commands:
        argv = shlex.split(command)[1:]
        assert main(argv) == _expected_status(comment), (
            f"README command did not do what the README says: {command}"
        )


def test_the_readmes_quick_commands_work_as_printed(tmp_path, monkeypatch):
    _run([c for c in readme_commands() if not _is_slow(c[1])], tmp_path, monkeypatch)


@pytest.mark.slow
def test_the_readmes_slow_commands_work_as_printed(tmp_path, monkeypatch):
    _run([c for c in readme_commands() if _is_slow(c[1])], tmp_path, monkeypatch)


def test_the_tour_writes_only_under_results():
    """Every file a README command writes lands under ``results/`` (ignored by git), never in the
    tracked ``docs/`` or the repository's root."""
    for command, _ in readme_commands():
        argv = shlex.split(command)
        for option in ("--out", "--write-params"):
            if option in argv:
                target = argv[argv.index(option) + 1]
                assert target.startswith("results/"), f"{command} writes {target}"
