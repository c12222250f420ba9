"""Physical parameters of the sloshing model, validated once, in the paper's symbols.

Every symbol is documented here and nowhere else; other modules refer to this table.

========  ==========================================================  ==========  ======================
symbol    meaning                                                     equation    allowed range
========  ==========================================================  ==========  ======================
eps       mass ratio m/M of the sloshing mass to the vessel           (5), (6)    (0, inf)
beta      ratio of the sloshing to the vessel natural frequency       (6)         [0, inf)
gamma     nondimensional linear damping of the vessel                 (6)         [0, inf)
sigma     detuning of the forcing frequency from 1:1 resonance        (7)         (-inf, inf)
Abar      forcing amplitude (the force is eps Abar cos(tau))          (7)         [0, inf)
lam       wall dissipation coefficient lambda = beta_bar*R/m          (9), (21)   [0, inf)
chi       wall stiffness coefficient chi = alpha_bar*R/m              (9), (21)   (0, inf)
n         exponent of the wall potential, force chi w^(2n+1)          (9), (10)   integer >= 1
pbar      dissipation exponent pbar = 2p - n, force lam w' w^(2p)     (19)        integer > -(n+1),
                                                                                  (pbar + n)/2 integer
========  ==========================================================  ==========  ======================

The restitution coefficient implied by ``lam, chi, n, pbar`` (eq. 21 at unit impact velocity;
eq. 40 when ``pbar == 0``) must be real and in (0, 1]; it equals 1 only for the elastic wall
``lam == 0``.

The state of both models is ``[X, X', w, w']`` in the nondimensional time tau of eq. (6), with
``X = u + eps*v`` (proportional to the centre of mass) and ``w = u - v`` (the particle's
displacement relative to the vessel, walls at ``|w| = 1``).
"""

from __future__ import annotations

import dataclasses
import math
import numbers

__all__ = ["Params", "FIELDS", "REAL_FIELDS", "real_pair"]

FIELDS = ("eps", "beta", "gamma", "sigma", "Abar", "lam", "chi", "n", "pbar")
REAL_FIELDS = FIELDS[:7]  # the real-valued ones, which a continuation can vary (n and pbar are integers)

# name -> (allowed range as text, predicate on a finite value)
_REAL_RANGES = {
    "eps": ("(0, inf)", lambda v: v > 0),
    "beta": ("[0, inf)", lambda v: v >= 0),
    "gamma": ("[0, inf)", lambda v: v >= 0),
    "sigma": ("(-inf, inf)", lambda v: True),
    "Abar": ("[0, inf)", lambda v: v >= 0),
    "lam": ("[0, inf)", lambda v: v >= 0),
    "chi": ("(0, inf)", lambda v: v > 0),
}

# the real fields no rule across fields involves (lam and chi enter the restitution check)
_UNCOUPLED = frozenset(_REAL_RANGES) - {"lam", "chi"}


def real_pair(pair, what: str = "two-parameter curves") -> tuple:
    """``pair`` as a tuple if it names two different real fields; else a one-line ValueError."""
    pair = tuple(pair)
    if len(pair) != 2:
        raise ValueError(f"{what} take two parameters; got {pair!r}")
    for name in pair:
        if name not in FIELDS:
            raise ValueError(f"parameter {name!r} is not a field of Params ({', '.join(FIELDS)})")
        if name not in REAL_FIELDS:
            raise ValueError(f"parameter {name!r} is an integer; {what} take two of {', '.join(REAL_FIELDS)}")
    if pair[0] == pair[1]:
        raise ValueError(f"the two parameters must differ; got {pair[0]!r} twice")
    return pair


def _bad(name: str, allowed: str, value) -> ValueError:
    return ValueError(f"parameter {name} must be in {allowed}; got {value!r}")


def _real(name: str, value) -> float:
    """A real field's value as a float, or the one-line error naming its range."""
    allowed, ok = _REAL_RANGES[name]
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise _bad(name, allowed, value)
    if not math.isfinite(value) or not ok(value):
        raise _bad(name, allowed, value)
    return float(value)


def _as_integer(name: str, value, allowed: str) -> int:
    """Accept ints and integral floats (CLI and JSON give floats); reject everything else."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise _bad(name, allowed, value)
    if not math.isfinite(value) or float(value) != int(value):
        raise _bad(name, allowed, value)
    return int(value)


@dataclasses.dataclass(frozen=True)
class Params:
    """One parameter set of models (8) and (9); see the module docstring for each symbol.

    Immutable and validated on construction: a bad value raises ``ValueError`` naming the
    parameter, its allowed range and the value received. Derive variants with
    :meth:`replace` (or ``dataclasses.replace``), which validates again.
    """

    eps: float
    beta: float
    gamma: float
    sigma: float
    Abar: float
    lam: float
    chi: float
    n: int
    pbar: int

    def __post_init__(self):
        for name in _REAL_RANGES:
            object.__setattr__(self, name, _real(name, getattr(self, name)))
        n = _as_integer("n", self.n, "integers >= 1")
        if n < 1:
            raise _bad("n", "integers >= 1", self.n)
        object.__setattr__(self, "n", n)
        pbar = _as_integer("pbar", self.pbar, f"integers > -(n+1) = {-(n + 1)}")
        if pbar <= -(n + 1):
            raise _bad("pbar", f"integers > -(n+1) = {-(n + 1)} (eq. 19 diverges otherwise)", self.pbar)
        if (pbar + n) % 2 != 0 or pbar + n < 0:
            raise _bad(
                "pbar",
                f"integers with p = (pbar + n)/2 a non-negative integer, i.e. pbar of the parity of n = {n}",
                self.pbar,
            )
        object.__setattr__(self, "pbar", pbar)
        self._check_restitution()

    def _check_restitution(self):
        from slosh_bif.model.restitution.eq21 import dissipation_at_unit_speed

        try:
            delta = dissipation_at_unit_speed(self.lam, self.chi, self.n, self.pbar)
        except OverflowError:  # (n + 1)/chi to a huge power (pbar = 1e9, say): no real kappa
            delta = math.inf
        if not delta < 1.0:
            kappa_sq = 1.0 - delta
            raise ValueError(
                "restitution coefficient kappa (eq. 21 at unit impact speed) must be real in (0, 1]; "
                f"with lam={self.lam!r}, chi={self.chi!r}, n={self.n}, pbar={self.pbar} "
                f"kappa**2 = 1 - {delta:.6g} = {kappa_sq:.6g}. Lower lam or raise chi or n."
            )

    def require_positive_stiffness(self) -> "Params":
        """Self, or a one-line ValueError when the vessel's linear stiffness ``1 - eps sigma`` of (8)
        and (9) is not positive: then X has no restoring force and every trajectory diverges. The
        check belongs to what simulates (a continuation may pass such sets as a domain edge)."""
        if self.eps * self.sigma >= 1.0:
            raise ValueError(
                f"eps * sigma = {self.eps * self.sigma:g} >= 1: the vessel's stiffness 1 - eps "
                "sigma of (8) and (9) is not positive "
                f"and every trajectory diverges; sigma must be below 1/eps = {1 / self.eps:g}"
            )
        return self

    @property
    def p(self) -> int:
        """Exponent p of the dissipation force ``lam*w'*w**(2p)``, p = (pbar + n)/2."""
        return (self.pbar + self.n) // 2

    def replace(self, **changes) -> "Params":
        """A validated copy with some fields changed (unknown names raise ``ValueError``)."""
        unknown = sorted(set(changes) - set(FIELDS))
        if unknown:
            raise ValueError(f"unknown parameter(s) {unknown}; known: {', '.join(FIELDS)}")
        if changes.keys() <= _UNCOUPLED:  # only their own ranges to check (a continuation asks often)
            copy = object.__new__(Params)
            copy.__dict__.update(self.__dict__)
            for name, value in changes.items():
                object.__setattr__(copy, name, _real(name, value))
            return copy
        return dataclasses.replace(self, **changes)

    def as_dict(self) -> dict:
        return {name: getattr(self, name) for name in FIELDS}

    def with_overrides(self, assignments) -> "Params":
        """Apply ``["name=value", ...]`` strings (the CLI's ``--set``), validating names and values."""
        changes = {}
        for text in assignments:
            name, sep, raw = text.partition("=")
            name = name.strip()
            if not sep or name not in FIELDS:
                raise ValueError(f"--set takes name=value with name one of {', '.join(FIELDS)}; got {text!r}")
            try:
                changes[name] = float(raw)
            except ValueError:
                raise ValueError(f"parameter {name} needs a number; got {raw.strip()!r}") from None
        return self.replace(**changes)
