"""Continuous Morlet wavelet transform, for the time-frequency plots of Fig. 11.

Hand-written (a dozen lines of FFT) rather than a dependency: the figure needs one transform
of one real signal. The analytic Morlet filter of centre frequency ``omega0`` at scale
``s = omega0 / omega`` is ``2 exp(-(s w - omega0)**2 / 2)`` for w > 0 and 0 otherwise, so a
cosine of amplitude a and angular frequency omega gives |W| = a on the ridge at omega: the plot
reads in amplitude, not in energy density.
"""

from __future__ import annotations

import numpy as np

__all__ = ["morlet_transform"]


def morlet_transform(signal, dt: float, omegas, *, omega0: float = 6.0) -> np.ndarray:
    """|W|(omega, t): the modulus of the Morlet transform, shape (len(omegas), len(signal)).

    ``signal`` is sampled uniformly with step ``dt``; ``omegas`` are angular frequencies (> 0,
    below the Nyquist frequency pi/dt). ``omega0`` trades time for frequency resolution
    (6 is the usual choice; larger resolves close frequencies better).
    """
    x = np.asarray(signal, dtype=float)
    omegas = np.asarray(omegas, dtype=float)
    if x.ndim != 1 or x.size < 4 or not np.all(np.isfinite(x)):
        raise ValueError("signal must be a 1-d array of at least 4 finite samples")
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be positive; got {dt!r}")
    if omegas.ndim != 1 or np.any(omegas <= 0) or np.any(omegas >= np.pi / dt):
        raise ValueError(
            f"omegas must lie in (0, pi/dt = {np.pi / dt:.4g}); got [{omegas.min():.4g}, {omegas.max():.4g}]"
        )
    if not (np.isfinite(omega0) and omega0 >= 5):
        raise ValueError(f"omega0 must be >= 5 (below, the Morlet wavelet is not admissible); got {omega0!r}")
    n = x.size
    padded = 1 << int(np.ceil(np.log2(2 * n)))  # zero padding against wrap-around
    spectrum = np.fft.fft(x - x.mean(), padded)
    w = 2 * np.pi * np.fft.fftfreq(padded, d=dt)
    scales = omega0 / omegas
    filters = np.where(w > 0, 2.0 * np.exp(-0.5 * (scales[:, None] * w[None, :] - omega0) ** 2), 0.0)
    return np.abs(np.fft.ifft(spectrum[None, :] * filters, axis=1)[:, :n])
