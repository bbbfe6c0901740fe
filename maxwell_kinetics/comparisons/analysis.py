"""Estimators on arrays shared by the comparisons (NumPy; no runs, no drawing): bin edges and
rescaled samples, velocity profiles and their coarse-grained increments, log-binned S(k) and its
Porod fit, and the jackknife.
"""

from __future__ import annotations

import numpy as np

from particles.observables import log_bin
from particles.validation import InvalidArgumentError

__all__ = [
    "bin_edges",
    "rescaled",
    "block_means",
    "velocity_on_grid",
    "coarse_increment_skewness",
    "profile_scales",
    "log_binned",
    "porod_fit",
    "binned_porod_fit",
    "porod_slope",
    "jackknife",
]


def bin_edges(spec) -> np.ndarray:
    """Edges ``lo, lo + step, …, hi`` of a preset's ``(lo, hi, step)`` (rounded to 12 digits)."""
    lo, hi, step = spec
    return np.round(np.arange(lo, hi + 0.5 * step, step), 12)


def rescaled(v: np.ndarray) -> np.ndarray:
    """x = (v − ⟨v⟩) / √⟨(v − ⟨v⟩)²⟩ per run (rows).

    Every run starts with zero total momentum, and collisions conserve it up to round-off; but
    that round-off (~1e-16 of the initial velocities) does not decay while the velocities decay
    like e^{−λτ}, so the mean is subtracted.  Even so the fluctuations keep only ~16 − λτ/ln 10
    digits: the Ulam runs here stay at λτ ≤ 30 (measured: at r = 0.9, τ = 1200, λτ = 57, the
    raw velocities of N = 2·10⁴ particles were all equal to their round-off mean).
    """
    v = v - v.mean(axis=-1, keepdims=True)
    return v / np.sqrt(np.mean(v * v, axis=-1, keepdims=True))


# ----------------------------------------------------------------------- profiles (Fig. 4)


def _increment_skewness(dv: np.ndarray) -> float:
    d = dv - dv.mean()
    return float(np.mean(d**3) / np.mean(d**2) ** 1.5)


def coarse_increment_skewness(profile, scale: int) -> float:
    """Skewness of the increments of a periodic profile coarse-grained over ``scale`` points.

    ``profile`` holds equally spaced samples of a field on a ring (v(i) against the label, or
    v(x) on a uniform grid).  It is cut into consecutive blocks of ``scale`` samples (a tail of
    ``len(profile) mod scale`` samples is dropped), each block is replaced by its mean, and the
    skewness γ₁ = ⟨(Δ − ⟨Δ⟩)³⟩ / ⟨(Δ − ⟨Δ⟩)²⟩^{3/2} of the increments between neighbouring
    blocks, the last to the first included, is returned.  ``scale = 1`` is the raw increment
    skewness.  Rare large negative increments (sharp drops after slow rises) give γ₁ < 0.
    """
    v = np.asarray(profile, dtype=float)
    if v.ndim != 1:
        raise InvalidArgumentError("profile", f"shape {v.shape}", "a 1-d array")
    if isinstance(scale, bool) or not isinstance(scale, (int, np.integer)) or scale < 1:
        raise InvalidArgumentError("scale", scale, "an integer >= 1")
    if v.size // scale < 3:
        raise InvalidArgumentError("scale", scale,
                                   f"at most {v.size // 3} for a profile of {v.size} points")
    means = block_means(v, scale)
    return _increment_skewness(np.diff(np.append(means, means[0])))


def block_means(values, m: int) -> np.ndarray:
    """Means of consecutive blocks of ``m`` values (a tail of ``len(values) mod m`` dropped)."""
    values = np.asarray(values, dtype=float)
    blocks = values.size // m
    return values[: blocks * m].reshape(blocks, m).mean(axis=1)


def velocity_on_grid(positions, velocities, length: float) -> np.ndarray:
    """MD v(x): the rods' velocities interpolated linearly in x (periodic, rods sorted by
    position) at the N grid points x_m = m L / N, m = 0 … N − 1."""
    n = len(velocities)
    order = np.argsort(positions, kind="stable")
    grid = np.arange(n) * (length / n)
    return np.interp(grid, positions[order], velocities[order], period=length)


def profile_scales(n: int) -> tuple[int, ...]:
    """Coarse-graining scales of comparison 7: 1, 4, 16, … up to N/64 (at least 64 blocks)."""
    scales = [1]
    while scales[-1] * 4 * 64 <= n:
        scales.append(scales[-1] * 4)
    return tuple(scales)


# ----------------------------------------------------------------------- S(k) (Fig. 3)


def log_binned(k, s):
    """Log-binned S(k), 10 bins per decade: (bin centres, mean S)
    (:func:`particles.observables.log_bin`)."""
    kb, sb, _ = log_bin(k, s, 10)
    return kb, sb


def porod_fit(k, s, t, z, x_window, k_max):
    """Least-squares line ln S = a + b ln k over the log bins with k·t^z in ``x_window`` and
    k ≤ ``k_max``: (b, a, k of the bins used), or None with fewer than 3 bins."""
    return binned_porod_fit(*log_binned(k, s), t, z, x_window, k_max)


def binned_porod_fit(kb, sb, t, z, x_window, k_max):
    """:func:`porod_fit` on a spectrum already log-binned (``kb``, ``sb``)."""
    x = kb * t**z
    sel = (x >= x_window[0]) & (x <= x_window[1]) & (kb <= k_max)
    if sel.sum() < 3:
        return None
    b, a = np.polyfit(np.log(kb[sel]), np.log(sb[sel]), 1)
    return float(b), float(a), kb[sel]


def porod_slope(k, s, t, z, x_window, k_max):
    """Slope of ln S against ln k over k·t^z in ``x_window`` and k ≤ ``k_max`` (None with
    fewer than 3 log bins there)."""
    fit = porod_fit(k, s, t, z, x_window, k_max)
    return None if fit is None else fit[0]


def jackknife(values) -> float | None:
    """Jackknife standard error from the leave-one-out estimates ``values`` (None below 3 of
    them: two replicas give one difference, not a spread)."""
    v = np.asarray([x for x in values if x is not None], dtype=float)
    if v.size < 3 or v.size < len(values):
        return None
    return float(np.sqrt((v.size - 1) / v.size * np.sum((v - v.mean()) ** 2)))
