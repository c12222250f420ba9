"""The continuation engine's problem interface, written as types.

A problem of F(x, p) = 0 must have (:class:`Problem`)

* ``names``: the names of the n state components;
* ``residual(x, p)`` -> (n,), ``jacobian(x, p)`` -> (n, n), ``dparam(x, p)`` -> (n,).

It may offer any of these capabilities, each a protocol of its own:

* :class:`Domain`: ``in_domain(x, p)`` -> bool; points outside are never evaluated further.
* :class:`Edges`: ``edge_point(x, p)`` -> ``(x, p)`` or None, the exact point where the branch
  through (x, p) leaves the domain (appended as the branch's end); ``edge_distance(x, p)``, the
  relative distance to that edge (a stall within 1e-5 of it counts as reaching it); ``edge_name``,
  what the edge is (read after ``edge_point``, which may set it), or ``edge_name_at(x, p)``, the
  name of the edge that failed steps from (x, p) ran into.
* :class:`Stability`: ``eigenvalues(x, p)`` -> (n,) complex, with ``is_stable(eigenvalues)`` ->
  bool when the rule is not "all real parts negative" (Floquet multipliers: inside the unit
  circle); or ``stability_from_jacobian = True`` for a problem whose stability is that of its own
  Jacobian (the engine reuses the one it has). The engine asks once per point of the branch, when
  the point is accepted (the problem need keep no cache of its own for it); ``diagnostics(x, p)``
  -> {name: float}, per-point checks recorded beside it (``Branch.diagnostics``).
* :class:`OwnTests`: ``test_kinds`` (names, e.g. PD, NS) with ``test_functions(x, p)`` -> one
  real value per kind, special points at their sign changes, located like folds; ``confirm(kind,
  x, p)`` -> a message, or None to drop a located point that is not what the kind means.
* :class:`Refinable`: ``refined()`` -> the same problem computed more precisely (tighter
  integration tolerances), or None when there is none: a direction that stalls is resumed with
  it from where the stall began, at most twice, before the stall is reported.
* ``accept(x, p)``, called after each accepted point (a minimally augmented problem refreshes its
  bordering vectors there); ``branch_kind``, what the points are, for the :class:`Branch`.

:func:`capabilities` reads a problem's optional members once; the engine asks it, never the
problem, what the problem can do.
"""

from __future__ import annotations

import weakref
from typing import Protocol, runtime_checkable

import numpy as np

__all__ = [
    "Problem",
    "Domain",
    "Edges",
    "Stability",
    "OwnTests",
    "Refinable",
    "Capabilities",
    "capabilities",
    "require_problem",
]

REQUIRED = ("names", "residual", "jacobian", "dparam")


@runtime_checkable
class Problem(Protocol):
    names: tuple

    def residual(self, x, p) -> np.ndarray: ...

    def jacobian(self, x, p) -> np.ndarray: ...

    def dparam(self, x, p) -> np.ndarray: ...


@runtime_checkable
class Domain(Protocol):
    def in_domain(self, x, p) -> bool: ...


@runtime_checkable
class Edges(Protocol):
    def edge_point(self, x, p): ...

    def edge_distance(self, x, p) -> float: ...


@runtime_checkable
class Stability(Protocol):
    def eigenvalues(self, x, p) -> np.ndarray: ...


@runtime_checkable
class OwnTests(Protocol):
    test_kinds: tuple

    def test_functions(self, x, p) -> tuple: ...

    def confirm(self, kind, x, p) -> str | None: ...


@runtime_checkable
class Refinable(Protocol):
    def refined(self): ...


def _all_negative(eigenvalues) -> bool:
    return bool(np.all(eigenvalues.real < 0))


class Capabilities:
    """What one problem offers beyond :class:`Problem`, read once (see the module docstring)."""

    def __init__(self, problem):
        self.problem = problem
        self._in_domain = getattr(problem, "in_domain", None)
        self.edge_point = getattr(problem, "edge_point", None)
        self.edge_distance = getattr(problem, "edge_distance", None)
        self._edge_name_at = getattr(problem, "edge_name_at", None)
        self.from_jacobian = bool(getattr(problem, "stability_from_jacobian", False))
        self._eigenvalues = getattr(problem, "eigenvalues", None)
        self._diagnostics = getattr(problem, "diagnostics", None)
        self.has_stability = self.from_jacobian or self._eigenvalues is not None
        self.is_stable = getattr(problem, "is_stable", _all_negative)
        self.test_kinds = tuple(getattr(problem, "test_kinds", ()))
        self._test_functions = getattr(problem, "test_functions", None)
        self.confirm = getattr(problem, "confirm", None)
        self.terminal_kinds = frozenset(getattr(problem, "terminal_kinds", ()))
        self.test_floor = dict(getattr(problem, "test_floor", {}))
        self.accept = getattr(problem, "accept", None)
        self.refined = getattr(problem, "refined", None)
        self.branch_kind = getattr(problem, "branch_kind", "")

    @property
    def edge_name(self) -> str:
        """Read when asked: a problem's ``edge_point`` may name the edge it found."""
        return getattr(self.problem, "edge_name", "boundary")

    def edge_name_near(self, u) -> str:
        """The name of the edge that failed steps from u = (x, p) ran into: the problem's
        ``edge_name_at(x, p)`` where it has one, else :attr:`edge_name`."""
        return self._edge_name_at(u[:-1], u[-1]) if self._edge_name_at is not None else self.edge_name

    def in_domain(self, u) -> bool:
        """u = (x, p) is finite and inside the problem's domain."""
        return bool(np.isfinite(u).all()) and (
            self._in_domain is None or bool(self._in_domain(u[:-1], u[-1]))
        )

    def tests(self, x, p) -> tuple:
        """The problem's own test values, in the order of ``test_kinds`` (empty without them)."""
        return () if self._test_functions is None else tuple(float(v) for v in self._test_functions(x, p))

    def diagnostics(self, x, p) -> dict:
        """The problem's per-point checks at (x, p) ({} without them)."""
        return {} if self._diagnostics is None else {k: float(v) for k, v in self._diagnostics(x, p).items()}

    def eigenvalues(self, x, p, jac=None) -> np.ndarray:
        """The eigenvalues behind stability at (x, p) (NaN when the problem gives none);
        ``jac``: F_x there when the engine already has it."""
        n = len(x)
        if self.from_jacobian:
            J = jac if jac is not None else self.problem.jacobian(x, p)
            return np.linalg.eigvals(J) if np.isfinite(J).all() else np.full(n, np.nan + 0j)
        if self._eigenvalues is not None:
            return self._eigenvalues(x, p)
        return np.full(n, np.nan + 0j)


_KNOWN: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def require_problem(problem) -> None:
    """A TypeError naming what ``problem`` lacks of :class:`Problem` (Newton alone needs less:
    ``residual`` and ``jacobian``)."""
    missing = [name for name in REQUIRED if not hasattr(problem, name)]
    if missing:
        raise TypeError(
            f"{type(problem).__name__} is not a continuation problem: it lacks "
            f"{', '.join(missing)} (see slosh_bif.continuation.problem)"
        )


def capabilities(problem) -> Capabilities:
    """The :class:`Capabilities` of ``problem``, made once per problem object."""
    try:
        found = _KNOWN.get(problem)
    except TypeError:  # not weakly referenceable: read it each time
        return Capabilities(problem)
    if found is None:
        found = _KNOWN[problem] = Capabilities(problem)
    return found
