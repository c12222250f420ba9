"""What a command says while it works: progress on stderr as one updating line on a terminal
(rich's status line), plain lines when stderr is a file or a pipe, nothing with ``-q``, and every
message with ``-v``. Results go to stdout and to files; this is only the running commentary."""

from __future__ import annotations

import sys

__all__ = ["REPORTER", "Reporter"]


class Reporter:
    """The process's progress channel (one per command run; :data:`REPORTER`)."""

    def __init__(self):
        self.level = "normal"  # "quiet", "normal" or "verbose"
        self._status = None  # rich's live status line, on a terminal

    def configure(self, *, quiet: bool = False, verbose: bool = False) -> None:
        self.close()
        self.level = "quiet" if quiet else "verbose" if verbose else "normal"

    @property
    def verbose(self) -> bool:
        return self.level == "verbose"

    def _live(self) -> bool:
        return self.level == "normal" and sys.stderr.isatty()

    def update(self, message: str) -> None:
        """A passing state ("point 219, sigma = -0.74"): the status line on a terminal, a plain line
        elsewhere."""
        if self.level == "quiet":
            return
        if not self._live():
            print(f"  {message}", file=sys.stderr, flush=True)
            return
        if self._status is None:
            from rich.console import Console

            self._status = Console(stderr=True).status(message)
            self._status.start()
        else:
            self._status.update(message)

    def note(self, message: str) -> None:
        """A message worth keeping on screen (a branch finished, a curve that could not start)."""
        if self.level == "quiet":
            return
        if self._status is not None:
            self._status.console.print(f"  {message}", markup=False, highlight=False)
        else:
            print(f"  {message}", file=sys.stderr, flush=True)

    def close(self) -> None:
        if self._status is not None:
            self._status.stop()
            self._status = None


REPORTER = Reporter()
