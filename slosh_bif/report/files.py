"""Files written whole or not at all: a reader (or a later run) sees the previous complete file or
the new complete one, never a partial file left by a kill, a full disk or an exception."""

from __future__ import annotations

import contextlib
import json
import os
from pathlib import Path

__all__ = ["replaced_atomically", "write_text_atomically", "read_store"]


@contextlib.contextmanager
def replaced_atomically(path):
    """Yield a temporary path beside ``path`` (same folder, same suffix, so that writers that
    choose a format by the suffix still do); when the block ends normally it is renamed onto
    ``path`` (``os.replace``: atomic on POSIX and Windows), otherwise it is removed and ``path``
    is left as it was."""
    path = Path(path)
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.partial{path.suffix}")
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp.unlink()


def write_text_atomically(path, text: str) -> Path:
    with replaced_atomically(path) as tmp:
        tmp.write_text(text)
    return Path(path)


def read_store(path, settings: dict, *, key: str | None = "settings") -> dict:
    """The JSON that an earlier run stored in ``path``, when its settings (``stored[key]``, or
    the whole file when ``key`` is None) equal ``settings``; else a one-line ValueError naming
    the settings that differ (what ``--resume`` needs before reusing anything)."""
    try:
        stored = json.loads(Path(path).read_text())
    except (OSError, ValueError) as err:
        raise ValueError(f"--resume: cannot read {path}: {err}") from None
    found = stored if key is None else stored.get(key, {})
    if found != settings:
        differ = sorted(k for k in settings if found.get(k) != settings[k])
        raise ValueError(f"--resume: {path} was written for other settings ({', '.join(differ)} differ); run without --resume or into another --out")
    return stored
