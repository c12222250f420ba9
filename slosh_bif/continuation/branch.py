"""Results of a continuation: a :class:`Branch` of solutions and its :class:`SpecialPoint` s.

A branch is arrays in branch order (parameter, states, stability, Newton iterations, arclength)
plus special points (folds ``LP``, branch points ``BP``, ends ``END``, and the kinds of a
problem's own test functions) with where they sit, their tangent and the bracket they were
located in, and a status and message saying how the run ended. Its columns are named: ``b["A"]``
is the state component ``A``, ``b["sigma"]`` the continued parameter. Branches save to and load
from ``.npz`` without loss, so re-plotting never recomputes.

Every special-point kind and every status is one member of :class:`Kind` and :class:`Status`
(strings, so that ``s.kind == "LP"`` keeps working).
"""

from __future__ import annotations

import dataclasses
import enum
import json
from pathlib import Path

import numpy as np

from slosh_bif.atomic import replaced_atomically

__all__ = [
    "Branch",
    "SpecialPoint",
    "Kind",
    "Status",
    "polyline_distance",
    "FOLD",
    "BRANCH_POINT",
    "PERIOD_DOUBLING",
    "NEIMARK_SACKER",
    "END",
]


class Kind(str, enum.Enum):
    """Kinds of special points, labelled as AUTO and MatCont label them."""

    FOLD = "LP"  # a fold (limit point): the curve turns back in its parameter
    BRANCH_POINT = "BP"  # a simple branch point (for symmetric orbits: the symmetry-breaking pitchfork)
    PERIOD_DOUBLING = "PD"  # a Floquet multiplier through -1
    NEIMARK_SACKER = "NS"  # a complex pair of multipliers through the unit circle
    END = "END"  # an end of the branch (its reason in SpecialPoint.reason)
    CUSP = "CP"  # on a fold curve: the fold's quadratic coefficient vanishes
    RESONANCE_1_1 = "R1"  # on an NS curve: multipliers exp(+-i theta) with theta = 0
    RESONANCE_1_2 = "R2"  # theta = pi
    RESONANCE_1_3 = "R3"  # theta = 2 pi / 3
    RESONANCE_1_4 = "R4"  # theta = pi / 2
    FOLD_FLIP = "LPPD"  # multipliers +1 and -1 together
    FOLD_NS = "LPNS"  # +1 and a complex pair on the unit circle
    FLIP_NS = "PDNS"  # -1 and a complex pair on the unit circle
    PITCHFORK_FOLD = "BPLP"  # a symmetry-breaking (pitchfork) curve meets a fold curve
    TURN = "TP"  # a curve of codimension-1 points turns back in its first parameter (no bifurcation)
    GRAZING = "GR"  # of a hybrid orbit: a flight touches a switching surface with zero normal speed

    def __str__(self):
        return self.value


class Status(str, enum.Enum):
    """How one direction of a continuation ended; OK when the branch is complete."""

    OK = "ok"
    BOUND = "parameter bound"
    EDGE = "domain edge"
    LOOP = "closed loop"
    STEPS = "step limit"
    STALL = "step below minimum"
    TIME = "time limit"
    # a located special point where the curve ends by nature (an NS curve at R1 or R2)
    TERMINAL = "terminal point"

    def __str__(self):
        return self.value


FOLD, BRANCH_POINT, END = Kind.FOLD.value, Kind.BRANCH_POINT.value, Kind.END.value
PERIOD_DOUBLING, NEIMARK_SACKER = (
    Kind.PERIOD_DOUBLING.value,
    Kind.NEIMARK_SACKER.value,
)  # from a problem's own test functions


@dataclasses.dataclass(frozen=True)
class SpecialPoint:
    """A located special point.

    ``kind`` is a :class:`Kind` value: ``"LP"`` (fold), ``"BP"`` (branch point), ``"END"``, or a
    kind of the problem's own test functions (``"PD"`` period doubling, ``"NS"`` Neimark-Sacker
    for periodic orbits, the codimension-2 kinds on curves of them); ``index`` the branch point
    after which it lies; ``p`` and ``x`` where it is; ``bracket`` the parameter values of the two
    branch points (or located end points) it was found between; ``message`` says what it is;
    ``tangent`` is the unit tangent of the branch in (x, p) there (None where not known);
    ``located`` is False when a sign change was detected but not located (then ``x`` is the
    nearest computed point); ``reason`` is an END point's :class:`Status`, and ``edge`` the
    problem's name for the domain edge it reached (``reason`` "domain edge").
    """

    kind: str
    index: int
    p: float
    x: np.ndarray
    bracket: tuple
    message: str = ""
    tangent: np.ndarray | None = None
    located: bool = True
    reason: str = ""
    edge: str = ""


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
    kind : what the points are (e.g. ``"equilibria"``, ``"periodic orbits"``, ``"PD curve"``)
    ends : ``(direction, reason)`` of each direction run, the reason a :class:`Status` value:
        what the message says in words, as fields to test
    diagnostics : {name: (N,) array}, the problem's per-point checks (for periodic orbits
        ``liouville_error``), computed with the stability when each point was accepted

    ``b[name]`` is a column by name: the continued parameter, or a state component of ``names``.
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
    kind: str = ""
    ends: tuple = ()
    diagnostics: dict = dataclasses.field(default_factory=dict)

    def __len__(self):
        return len(self.p)

    @property
    def columns(self) -> tuple:
        """The names ``b[name]`` accepts: the continued parameter, then the state components."""
        return (self.param, *self.names)

    def __getitem__(self, name: str) -> np.ndarray:
        if name == self.param:
            return self.p
        if name in self.names:
            return self.x[:, self.names.index(name)]
        raise KeyError(f"{name!r} is not a column of this branch; its columns are {', '.join(self.columns)}")

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
            diagnostics={k: v[keep].copy() for k, v in self.diagnostics.items()},
            special=tuple(sp for sp in self.special if sp.index <= stop),
            status="ok",
            message=f"{self.message}; cut at point {stop}: {reason}",
        )

    # -- persistence ----------------------------------------------------------------------------

    def save(self, path, **extra) -> Path:
        """Write the branch to ``path`` (.npz), everything included; ``extra`` arrays are stored
        beside it (a result built on a branch adds its own) and ignored by :meth:`load`."""
        path = Path(path)
        meta = {
            "param": self.param,
            "names": list(self.names),
            "status": self.status,
            "message": self.message,
            "options": self.options,
            "kind": self.kind,
            "ends": [list(e) for e in self.ends],
            "diagnostics": sorted(self.diagnostics),
            "special": [
                {
                    "kind": str(s.kind),
                    "index": s.index,
                    "p": s.p,
                    "bracket": list(s.bracket),
                    "message": s.message,
                    "located": s.located,
                    "reason": str(s.reason),
                    "edge": s.edge,
                }
                for s in self.special
            ],
        }
        special_x = np.array([s.x for s in self.special]) if self.special else np.zeros((0, self.x.shape[1]))
        width = self.x.shape[1] + 1
        special_t = (
            np.array([s.tangent if s.tangent is not None else np.full(width, np.nan) for s in self.special])
            if self.special
            else np.zeros((0, width))
        )
        path = Path(path) if str(path).endswith(".npz") else Path(f"{path}.npz")  # numpy's naming
        with replaced_atomically(path) as tmp:  # whole or not at all
            self._savez(tmp, meta, special_x, special_t, extra)
        return path

    def _savez(self, tmp, meta, special_x, special_t, extra):
        np.savez(
            tmp,
            meta=np.array(json.dumps(meta)),
            p=self.p,
            x=self.x,
            stable=self.stable,
            eigenvalues=self.eigenvalues,
            newton_iterations=self.newton_iterations,
            arclength=self.arclength,
            special_x=special_x,
            special_tangent=special_t,
            **{f"diagnostic_{k}": v for k, v in self.diagnostics.items()},
            **extra,
        )

    @classmethod
    def load(cls, path) -> "Branch":
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
            tangents = data["special_tangent"] if "special_tangent" in data.files else None

            def tangent(i):
                t = None if tangents is None else tangents[i].copy()
                return None if t is None or not np.all(np.isfinite(t)) else t

            special = tuple(
                SpecialPoint(
                    s["kind"],
                    int(s["index"]),
                    float(s["p"]),
                    data["special_x"][i].copy(),
                    tuple(s["bracket"]),
                    s["message"],
                    tangent(i),
                    bool(s.get("located", True)),
                    s.get("reason", ""),
                    s.get("edge", ""),
                )
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
                kind=meta.get("kind", ""),
                ends=tuple(tuple(e) for e in meta["ends"]) if "ends" in meta else _ends_of(meta["message"]),
                diagnostics={k: data[f"diagnostic_{k}"].copy() for k in meta.get("diagnostics", [])},
            )


def _ends_of(message: str) -> tuple:
    """The ``ends`` of a branch saved before they were stored: from its message's
    "backward: REASON; forward: REASON" (each reason a :class:`Status` value, maybe with detail)."""
    ends = []
    for part in message.split("; "):
        direction, _, rest = part.partition(": ")
        reason = next((s.value for s in Status if rest.startswith(s.value)), "")
        if direction in ("backward", "forward") and reason:
            ends.append((direction, reason))
    return tuple(ends)


def polyline_distance(points, u) -> float:
    """Distance from the point u to the polyline through ``points`` (rows, in order): whether a
    new start lies on a curve already traced."""
    points = np.asarray(points, dtype=float)
    if len(points) == 1:
        return float(np.linalg.norm(points[0] - u))
    seg = np.diff(points, axis=0)
    w = np.clip(
        np.einsum("ij,ij->i", u - points[:-1], seg) / np.maximum(np.einsum("ij,ij->i", seg, seg), 1e-300),
        0,
        1,
    )
    return float(np.min(np.linalg.norm(points[:-1] + w[:, None] * seg - u, axis=1)))
