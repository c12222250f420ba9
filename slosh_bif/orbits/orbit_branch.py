"""The results of tracing orbits: an OrbitBranch (a branch of 2pi-orbits of (9) or (8) with its
problem, stability and orbit measures) and an OrbitFamily (the branches one start reaches, and how
the tracing ended); the symmetry images of an orbit (w -> -w after half a period)."""

from __future__ import annotations

import dataclasses

import numpy as np

from slosh_bif.continuation.branch import (
    Branch,
    Status,
)
from slosh_bif.model.params import Params
from slosh_bif.orbits.shooting import (
    ShootingProblem,
)

__all__ = [
    "LIOUVILLE_TOL",
    "OrbitBranch",
    "OrbitFamily",
    "images",
    "mirror",
    "renamed",
    "unique_name",
]


# Liouville's check |det M - exp(int tr J)| / exp(int tr J) is ~1e-12..1e-9 at the default
# tolerances; beyond this the monodromy, and the stability read from it, cannot be trusted.
LIOUVILLE_TOL = 1e-6


@dataclasses.dataclass(frozen=True)
class OrbitBranch:
    """One branch of periodic orbits with per-point measures of the orbits; ``ob[name]`` is a
    measure or a column of the branch.

    Attributes
    ----------
    name : str
        Unique within its family: the kind, then "-2", "-3", ... for further branches of that kind.
    problem : ShootingProblem
        The problem the branch solves.
    branch : Branch
        The continuation result.
    measures : dict
        Arrays over the points: A1, max_abs_X, max_abs_w, symmetry_defect, max_abs_multiplier,
        liouville_error.
    origin : str
        Where it was switched on from (empty for the primary branch).
    kind : str
        "symmetric", "asymmetric" (one member of a mirror pair), "period-2", ... (default: ``name``).
    found_from : str
        How its first orbit was found: the start's description, or ``origin`` for a switched branch.
    """

    name: str
    problem: ShootingProblem
    branch: Branch
    measures: dict
    origin: str = ""
    kind: str = ""
    found_from: str = ""

    def __post_init__(self):
        if not self.kind:
            object.__setattr__(self, "kind", self.name)
        if not self.found_from:
            object.__setattr__(self, "found_from", self.origin)

    @property
    def closed(self) -> bool:
        """Whether the branch closed on itself (an isola, or a loop through its start), or ended
        where it meets its parent again (beyond, the curve is the image of what it traced under
        the symmetry, back to its start)."""
        return any(reason in (Status.LOOP.value, Status.TERMINAL.value) for _, reason in self.branch.ends)

    def __getitem__(self, name: str) -> np.ndarray:
        """A column by name, as for a :class:`Branch`: a measure (``"A1"``, ``"max_abs_w"``, ...),
        the continued parameter or a state component of the branch."""
        if name in self.measures:
            return self.measures[name]
        try:
            return self.branch[name]
        except KeyError:
            raise KeyError(
                f"{name!r} is neither a measure ({', '.join(self.measures)}) nor a column of the "
                f"branch ({', '.join(self.branch.columns)})"
            ) from None

    def __len__(self):
        return len(self.branch)


@dataclasses.dataclass(frozen=True)
class OrbitFamily:
    """Branches of orbits continued in ``param`` at ``params``; ``tasks``: what a family scan ran
    to find them (:class:`~slosh_bif.report.tasks.Task`, each start job and family traced, with
    its duration), empty for a family traced from one start."""

    params: Params
    param: str
    branches: list
    tasks: tuple = dataclasses.field(default=(), compare=False)  # timings: no part of the result's identity

    @property
    def complete(self) -> bool:
        """Whether every branch ended at a bound, an edge or by closing (none was cut short)."""
        return all(ob.branch.status == "ok" for ob in self.branches)

    def summary(self, detail: bool = False) -> str:
        """One line per branch: its status, points, range and special points (counted by kind;
        each with its parameter value when ``detail``)."""
        lines = []
        for ob in self.branches:
            b = ob.branch
            if detail:
                kinds = ", ".join(f"{s.kind} {s.p:.6g}" for s in b.special) or "none"
            else:
                counts = {}
                for s in b.special:
                    counts[s.kind] = counts.get(s.kind, 0) + 1
                kinds = (
                    f"{len(b.special)} ({', '.join(f'{n} {k}' for k, n in counts.items())})"
                    if counts
                    else "none"
                )
            lines.append(
                f"{ob.name}{' (' + ob.origin + ')' if ob.origin else ''}: {b.status}, {len(b)} "
                f"points, {self.param} in [{b.p.min():.4g}, {b.p.max():.4g}], special: {kinds}"
            )
        return "\n".join(lines)


def unique_name(kind: str, taken) -> str:
    """``kind`` if no branch in ``taken`` (OrbitBranches) has that name, else ``kind-2``, ``kind-3``, ..."""
    names = {ob.name for ob in taken}
    k = 1
    while (name := kind if k == 1 else f"{kind}-{k}") in names:
        k += 1
    return name


def renamed(branches, names: dict) -> list:
    """The OrbitBranches ``branches`` (their names unique) renamed by ``names`` ({old: new}), with
    the names inside their origins and ``found_from`` ("the NAME branch") rewritten to match."""
    slot = {old: f"\0{k}\0" for k, old in enumerate(names)}  # two passes: a new name may be another's old one

    def rewrite(text):
        for old in sorted(names, key=len, reverse=True):
            text = text.replace(f"the {old} branch", f"the {slot[old]} branch")
        for old, new in names.items():
            text = text.replace(slot[old], new)
        return text

    return [
        dataclasses.replace(
            ob,
            name=names.get(ob.name, ob.name),
            origin=rewrite(ob.origin),
            found_from=rewrite(ob.found_from),
        )
        for ob in branches
    ]


def images(problem: ShootingProblem, x) -> list:
    """The arc states of every copy of the orbit x under the symmetries of (9): its shifts by
    2pi k (an orbit of period 2pi m, read from tau = 2pi k) and their mirror images
    y'(tau) = -y(tau + pi), where the arcs split at those times; x itself first."""
    if problem.symmetric:  # its own mirror image, in the half period's arcs
        return [np.asarray(x, dtype=float)]
    m, pm = problem.segments, problem.period_multiple
    states = np.asarray(x, dtype=float).reshape(m, 4)
    per_2pi = m // pm if m % pm == 0 else 0
    shifts = [np.roll(states, -k * per_2pi, axis=0) for k in range(pm)] if per_2pi else [states]
    if per_2pi and per_2pi % 2 == 0:
        shifts += [-np.roll(s, -per_2pi // 2, axis=0) for s in shifts]
    return [s.ravel() for s in shifts]


def mirror(problem: ShootingProblem, x):
    """x of the mirror-image orbit: y'(0) = -y(pi), read off the arcs when they split at pi."""
    if problem.symmetric:
        return np.asarray(x, dtype=float)
    if problem.period_multiple == 1 and problem.segments % 2 == 0:
        return images(problem, x)[1]
    raise ValueError("mirror needs a 2pi problem with an even number of segments")
