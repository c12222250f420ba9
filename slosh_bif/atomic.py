"""Files written whole or not at all, below every layer of the pipeline (the continuation
engine's branches and every wing's outputs use it): a reader, or a later run, sees the previous
complete file or the new complete one, never a partial file left by a kill, a full disk or an
exception."""

from __future__ import annotations

import contextlib
import os
from pathlib import Path

__all__ = ["replaced_atomically", "write_text_atomically"]


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
