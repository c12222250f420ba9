"""The wall's integer parameters in a frequency-response fit: the power n of the smooth wall (9)
and the exponent pbar of the restitution law (21) (p = (pbar + n) / 2 a non-negative integer, so
pbar has n's parity), profiled: the continuous parameters are fitted at each admissible (n, pbar)
and the best misfit wins; those within the chi-square(1) 95 % threshold of it are reported as
consistent with the data."""

from __future__ import annotations

from slosh_bif.identify.response_stats import CHI2_95
from slosh_bif.model.params import Params
from slosh_bif.model.restitution import dissipation_at_unit_speed

__all__ = ["INTEGERS", "N_CANDIDATES", "PBAR_MAX", "integer_sets", "integer_estimates", "start_at"]

INTEGERS = ("n", "pbar")
N_CANDIDATES = (2, 3, 4, 5, 6, 8, 10, 15, 20, 30, 50, 75, 100)  # wall powers tried when n is free
PBAR_MAX = 8


def integer_sets(base: Params, free) -> list:
    """The (n, pbar) pairs to fit at: n over :data:`N_CANDIDATES` (and the base's) when free, of
    the base pbar's parity unless pbar is free too; pbar over 0..PBAR_MAX of n's parity when free."""
    if "n" in free:
        ns = sorted(set(N_CANDIDATES) | {base.n})
        ns = ns if "pbar" in free else [n for n in ns if (n - base.pbar) % 2 == 0]
    else:
        ns = [base.n]
    return [
        (n, pbar)
        for n in ns
        for pbar in (range(n % 2, PBAR_MAX + 1, 2) if "pbar" in free else [base.pbar])
        if (n + pbar) % 2 == 0
    ]


def start_at(base: Params, n: int, pbar: int, lam_free: bool) -> Params | None:
    """The start of the fit at (n, pbar): the base set there, with lam scaled (when free) so that
    C of (21), the energy fraction lost at unit speed, is the base's (C is linear in lam); None
    where the set is not admissible (kappa not real)."""
    try:
        if lam_free:
            C = dissipation_at_unit_speed(base.lam, base.chi, base.n, base.pbar)
            lam = base.lam * C / dissipation_at_unit_speed(base.lam, base.chi, n, pbar)
            return base.replace(n=n, pbar=pbar, lam=float(lam))
        return base.replace(n=n, pbar=pbar)
    except ValueError:
        return None


def integer_estimates(free, misfits: dict, best: tuple) -> tuple:
    """(estimates, values, sentences) of the free integers: the best (n, pbar) and the values of
    each consistent at 95 % (misfit within 3.84 of the best's), with a sentence for each that the
    data do not determine."""
    estimates, values, sentences = {}, {}, []
    lowest = misfits[best]
    consistent = [key for key, m in misfits.items() if m - lowest <= CHI2_95]
    for k, name in enumerate(INTEGERS):
        if name not in free:
            continue
        seen = sorted({key[k] for key in consistent})
        estimates[name] = {"value": int(best[k]), "consistent_95": seen}
        values[name] = int(best[k])
        if len(seen) > 1:
            sentences.append(
                f"{name} is not determined: {', '.join(map(str, seen))} fit equally at 95 %; the other "
                f"estimates hold given {name} = {best[k]}."
            )
    return estimates, values, sentences
