"""The random part of the excitation (47): ``F = eps*Abar*cos(tau) + eps*F_w(tau)``.

The paper draws one Gaussian number of standard deviation sigma_bar per integration step. That
makes the forcing, and so the response, depend on the step: a sequence of independent samples
of standard deviation s at spacing h has a flat spectrum up to the Nyquist frequency pi/h with
one-sided density s**2 h/pi, so halving the step halves the noise power near the resonance. Such
a simulation does not converge as the step shrinks.

Here the noise is a signal defined before and independently of any solver: a band-limited
Gaussian process with a flat spectrum on (0, cutoff] and standard deviation ``std`` (the paper's
sigma_bar), built as a sum of equal-amplitude cosines with random phases (the spectral
representation of Shinozuka and Deodatis),

    F_w(tau) = std * sqrt(2/N) * sum_k cos(k dw tau + phi_k),   k dw <= cutoff,  phi_k ~ U(0, 2 pi),

with dw = 2 pi / L and L at least the simulated duration (so the signal does not repeat within a
run). Its exact values on a grid of 16 points per shortest period come from one inverse FFT, and
the forcing *is* the degree-7 interpolating spline through them: C6, within about 1e-8 of the sum
of cosines, evaluated in O(1) inside the compiled integrator. (A cubic spline was 1e-3 off and,
being only C2, cost DOP853 its order at every knot: end states stalled at 1e-5 under tolerance
refinement.) Any convergent solver converges to the same trajectory as its tolerance shrinks.

The paper's noise with step h is, in spectrum, this one with ``cutoff = pi/h``: same standard
deviation, same flat band. The default cutoff 10 (h = 0.31) covers the 1:1 resonance and the
particle's linear frequency with room to spare; the response to noise near the resonance scales
as std**2 / cutoff, so state the cutoff with the standard deviation when comparing runs.

Reproducible: the phases come from ``numpy.random.default_rng(seed)``; the same seed, std,
cutoff and duration give the same signal bit for bit.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

__all__ = ["BandLimitedNoise", "band_limited_noise", "MAX_NOISE_SAMPLES", "MAX_NOISE_STD"]

_POINTS_PER_SHORTEST_PERIOD = 16
_DEGREE = 7
# At most this many samples of the noise (its table holds 8 spline coefficients a sample; 2e7 is
# about 1.3 GB): a cutoff of 1e6 over tau = 600 would ask for 1.5e9.
MAX_NOISE_SAMPLES = 20_000_000
# The largest standard deviation accepted (the paper uses up to 4): beyond ~1e300 the spectrum
# overflows, and far below that the wall force, not the noise, is meaningless.
MAX_NOISE_STD = 1e6


@dataclasses.dataclass(frozen=True)
class BandLimitedNoise:
    """A realisation of F_w on ``[t0, t0 + duration]``; call it like a function of tau.

    ``table`` packs the spline as ``[t0, dt, m, d, c_0 ... ]`` (m pieces of degree d, d + 1
    coefficients each, highest power first) for the compiled integrator; ``modes`` is the number
    of cosines.
    """

    std: float
    cutoff: float
    seed: int
    t0: float
    duration: float
    modes: int
    table: np.ndarray

    def __call__(self, tau):
        """F_w at time(s) tau (outside the realised interval the end pieces are extended)."""
        t0, dt, m, degree = self.table[0], self.table[1], int(self.table[2]), int(self.table[3])
        coef = self.table[4:].reshape(m, degree + 1)
        tau = np.asarray(tau, dtype=float)
        i = np.clip(((tau - t0) / dt).astype(int), 0, m - 1)
        s = tau - (t0 + i * dt)
        c = coef[i]
        value = c[..., 0]
        for j in range(1, degree + 1):
            value = value * s + c[..., j]
        return value


def band_limited_noise(
    std: float, *, seed: int, duration: float, t0: float = 0.0, cutoff: float = 10.0
) -> BandLimitedNoise:
    """Draw the noise signal of (47) for a run over ``[t0, t0 + duration]``.

    Parameters
    ----------
    std : float
        Standard deviation sigma_bar of F_w, >= 0 (0 gives a zero signal).
    seed : int
        Seed of ``numpy.random.default_rng``; required, so every run is reproducible.
    duration, t0 : float
        The time interval the signal must cover (duration > 0).
    cutoff : float
        Highest angular frequency of the flat band, > 0 (see the module docstring).
    """
    for name, value, ok, allowed in (
        ("std", std, lambda v: 0 <= v <= MAX_NOISE_STD, f"[0, {MAX_NOISE_STD:g}]"),
        ("duration", duration, lambda v: v > 0, "(0, inf)"),
        ("cutoff", cutoff, lambda v: v > 0, "(0, inf)"),
        ("t0", t0, lambda v: True, "(-inf, inf)"),
    ):
        if (
            isinstance(value, bool)
            or not isinstance(value, (int, float, np.floating, np.integer))
            or not math.isfinite(value)
            or not ok(value)
        ):
            raise ValueError(f"noise {name} must be a finite number in {allowed}; got {value!r}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"noise seed must be a non-negative integer; got {seed!r}")
    length = 1.05 * duration + 2 * np.pi  # the realisation is periodic with this length: longer than the run
    d_omega = 2 * np.pi / length
    # In floats first: a huge cutoff overflows int().
    grid = 2.0 * max(
        cutoff / d_omega + 1, 32.0, _POINTS_PER_SHORTEST_PERIOD * cutoff * length / (4 * np.pi) + 1
    )
    if not grid <= MAX_NOISE_SAMPLES:  # refuse before allocating (inf and NaN included)
        raise ValueError(
            f"noise cutoff {cutoff:g} over a run of {duration:g} needs {grid:.3g} noise samples, "
            f"more than the {MAX_NOISE_SAMPLES:.0e} allowed "
            f"(about {8 * 8 * grid / 1e9:.0f} GB): lower the cutoff (at most "
            f"{cutoff * MAX_NOISE_SAMPLES / grid:.3g} here) or shorten the run"
        )
    modes = max(1, int(cutoff / d_omega))
    rng = np.random.default_rng(seed)
    phases = rng.uniform(0.0, 2 * np.pi, modes)
    # At least 16 points per period of the cutoff frequency, as an FFT length.
    m = 2 * max(modes + 1, 32, math.ceil(_POINTS_PER_SHORTEST_PERIOD * cutoff * length / (4 * np.pi)))
    spectrum = np.zeros(m // 2 + 1, dtype=complex)
    amplitude = std * math.sqrt(2.0 / modes)
    spectrum[1 : modes + 1] = 0.5 * amplitude * m * np.exp(1j * phases)
    samples = np.fft.irfft(spectrum, n=m)  # sum_k amplitude cos(k d_omega t_j + phi_k) at t_j = j L/m
    dt = length / m
    count = math.ceil(duration / dt) + 2
    # Pad with samples beyond both ends (the realisation is L-periodic, so they exist) so that the
    # spline's irregular end pieces fall outside the run and the kept pieces sit between samples.
    knots = np.arange(-2 * _DEGREE, count + 2 * _DEGREE)
    from scipy.interpolate import PPoly, make_interp_spline  # only where noise is drawn

    spline = PPoly.from_spline(make_interp_spline(t0 + dt * knots, samples[knots % m], k=_DEGREE))
    start = np.searchsorted(spline.x, t0 - 0.5 * dt)
    coef = spline.c[:, start : start + count - 1]
    if not np.allclose(
        spline.x[start : start + count],
        t0 + dt * np.arange(count),
        rtol=0,
        atol=1e-9 * max(1.0, abs(t0) + duration),
    ):
        raise RuntimeError("noise spline: breakpoints are not the sample times (internal error)")
    table = np.concatenate([[t0, dt, count - 1, _DEGREE], coef.T.ravel()])
    return BandLimitedNoise(float(std), float(cutoff), int(seed), float(t0), float(duration), modes, table)
