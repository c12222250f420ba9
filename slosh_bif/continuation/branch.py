"""Results of a continuation: a :class:`Branch` of solutions and its :class:`SpecialPoint` s.

A branch is arrays in branch order (parameter, states, stability, Newton iterations, arclength)
plus special points (folds ``LP``, branch points ``BP``, ends ``END``) with where they sit and the
bracket they were located in, and a status and message saying how the run ended. Branches save to
and load from ``.npz`` without loss, so re-plotting never recomputes.
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np

__all__ = ["Branch", "SpecialPoint", "FOLD", "BRANCH_POINT", "PERIOD_DOUBLING", "NEIMARK_SACKER", "END"]

FOLD, BRANCH_POINT, END = "LP", "BP", "END"
PERIOD_DOUBLING, NEIMARK_SACKER = "PD", "NS"  # located through a problem's own test functions


@dataclasses.dataclass(frozen=True)
class SpecialPoint:
    """A located special point.

    ``kind`` is ``"LP"`` (fold), ``"BP"`` (branch point), ``"END"``, or a kind of the problem's
    own test functions (``"PD"`` period doubling, ``"NS"`` Neimark-Sacker for periodic orbits); ``index`` the branch point
    after which it lies; ``p`` and ``x`` where it is; ``bracket`` the parameter values of the two
    branch points (or located end points) it was found between; ``message`` says what it is.
    """

    kind: str
    index: int
    p: float
    x: np.ndarray
    bracket: tuple
    message: str = ""


@dataclasses.dataclass(frozen=True)
class Branch:
    """A continuation result: solution curve ``(p[i], x[i])`` in branch order.

    Attributes
    ----------
    param : name of the continued parameter
    names : names of the state components
    p : (N,) parameter values;  x : (N, n) states
    stable : (N,) booleans (all True when the problem gives no stability)
    eigenvalues : (N, n) complex, the eigenvalues behind ``stable`` (NaN when not given)
    newton_iterations : (N,) corrector iterations per point (0 for located points)
    arclength : (N,) cumulative arclength in (x, p)
    special : special points, in branch order
    status : ``"ok"`` when both directions ended at a bound, an edge or a closed loop;
             otherwise the reason one direction stopped early
    message : the ends of both directions, in words
    options : the options used, as a dict
    """

    param: str
    names: tuple
    p: np.ndarray
    x: np.ndarray
    stable: np.ndarray
    eigenvalues: np.ndarray
    newton_iterations: np.ndarray
    arclength: np.ndarray
    special: tuple
    status: str
    message: str
    options: dict

    def __len__(self):
        return len(self.p)

    def special_of(self, kind: str) -> list:
        """The special points of one kind (``"LP"``, ``"BP"``, ``"END"``)."""
        return [s for s in self.special if s.kind == kind]

    def special_labels(self) -> list:
        """Per point: the kind of the special point located at it, or ''."""
        labels = [""] * len(self.p)
        for s in self.special:
            labels[s.index] = s.kind
        return labels

    def head(self, stop: int, reason: str) -> "Branch":
        """The branch up to and including point ``stop``, ending there for ``reason``."""
        keep = slice(0, stop + 1)
        return dataclasses.replace(
            self,
            p=self.p[keep].copy(),
            x=self.x[keep].copy(),
            stable=self.stable[keep].copy(),
            eigenvalues=self.eigenvalues[keep].copy(),
            newton_iterations=self.newton_iterations[keep].copy(),
            arclength=self.arclength[keep].copy(),
            special=tuple(sp for sp in self.special if sp.index <= stop),
            status="ok",
            message=f"{self.message}; cut at point {stop}: {reason}",
        )

    # -- persistence ----------------------------------------------------------------------------

    def save(self, path) -> Path:
        """Write the branch to ``path`` (.npz), everything included."""
        path = Path(path)
        meta = {
            "param": self.param,
            "names": list(self.names),
            "status": self.status,
            "message": self.message,
            "options": self.options,
            "special": [
                {"kind": s.kind, "index": s.index, "p": s.p, "bracket": list(s.bracket), "message": s.message} for s in self.special
            ],
        }
        special_x = np.array([s.x for s in self.special]) if self.special else np.zeros((0, self.x.shape[1]))
        np.savez(
            path,
            meta=np.array(json.dumps(meta)),
            p=self.p,
            x=self.x,
            stable=self.stable,
            eigenvalues=self.eigenvalues,
            newton_iterations=self.newton_iterations,
            arclength=self.arclength,
            special_x=special_x,
        )
        return path

    @classmethod
    def load(cls, path) -> "Branch":
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
            special = tuple(
                SpecialPoint(s["kind"], int(s["index"]), float(s["p"]), data["special_x"][i].copy(), tuple(s["bracket"]), s["message"])
                for i, s in enumerate(meta["special"])
            )
            return cls(
                param=meta["param"],
                names=tuple(meta["names"]),
                p=data["p"].copy(),
                x=data["x"].copy(),
                stable=data["stable"].copy(),
                eigenvalues=data["eigenvalues"].copy(),
                newton_iterations=data["newton_iterations"].copy(),
                arclength=data["arclength"].copy(),
                special=special,
                status=meta["status"],
                message=meta["message"],
                options=meta["options"],
            )
