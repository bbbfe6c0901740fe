"""The driven 1D inelastic Maxwell (Ulam) model: white-noise heating balanced by collisions.

Model.  Every particle collides at rate 1 with a random partner (the collision rule,
p = (1 + r)/2, q = 1 − p; τ counts collisions per particle) and between collisions feels white
noise of strength D: dv = √(2D) dW.  A time Δτ of heating is a Gaussian kick of variance 2DΔτ,
i.e. the Fokker–Planck term D ∂²_v P.  With P̂(k) = ∫ e^{ikv} P(v) dv (our sign), ∂²_v becomes
(−ik)² = −k², and the master equation is

    ∂τ P̂(k) + (1 + D k²) P̂(k) = P̂(pk) P̂(qk).

Moments (zero mean, conserved: dM₁/dτ = −M₁ + (p + q)M₁ = 0).  Expanding in k,

    dM₂/dτ = 2D − 2pq M₂,
    dM₄/dτ = −(1 − p⁴ − q⁴) M₄ + 12 D M₂ + 6 p²q² M₂²,

closed and solved exactly by :func:`moments` (sums of exponentials).  Steady state:
M₂ = D/(pq) and M₄/M₂² = 3(2 + pq)/(2 − pq).

Cumulants.  The steady P̂ solves (1 + Dk²) P̂(k) = P̂(pk) P̂(qk).  Writing ln P̂ = Σ_j c_j k^{2j}
and ln(1 + Dk²) = Σ_j (−1)^{j+1} D^j k^{2j}/j gives c_j (1 − p^{2j} − q^{2j}) = (−1)^j D^j/j,
so with a_j = 1 − p^{2j} − q^{2j}

    ln P̂(k) = Σ_j (−1)^j D^j k^{2j} / (j a_j),    κ_{2j} = (2j)! D^j / (j a_j)

(κ_{2j} is the coefficient of (ik)^{2j}/(2j)!).  κ₂ = D/(pq) (a₁ = 2pq) and the kurtosis is
3 + κ₄/κ₂² = 3 + 6pq/(2 − pq), the same as from the moment equations.  The series converges for
|k| < 1/√D.

Characteristic function at any k.  Iterating P̂(k) = P̂(pk) P̂(qk)/(1 + Dk²) over the binary tree
of arguments k p^a q^b (C(a+b, a) paths reach each node) gives
ln P̂(k) = −Σ_{nodes} C(a+b, a) ln(1 + D k² p^{2a} q^{2b}) + Σ_{leaves} (paths) · series(k p^a q^b),
where a node is expanded while k_max p^a q^b > 1/(2√D) and the series is used below that
(:func:`characteristic_function`; exact up to round-off and the truncated series, < 1e-17).

Density.  P(v) = (1/2π) ∫ e^{−ikv} P̂(k) dk, evaluated by an FFT of P̂ on k_m = mΔk, |k| ≤ k_max
(P̂(k_max) < e^{−40}), on the periodic v-grid of period 2π/Δk = 2H, H = √D max(60, 15/√(pq))
(aliasing: P(v + 2H), < e^{−100} on the returned grid; a grid fixed at ±60√D, narrower than the
law for r → 1 where the variance D/(pq) diverges, returned half the variance at r = 0.999).
The tail: P̂ has simple poles at k = ±i/√D (the nearest
singularities), so P(v) ≈ R e^{−|v|/√D}/√D for |v| ≫ √D with
R = ½ P̂(−ip) P̂(−iq) at D = 1 (residue at k = −i; P̂(−iy) = ⟨e^{yv}⟩ from the series).

Refused (:class:`particles.validation.InvalidArgumentError`): D < 0 or not finite; D = 0 (no
steady state: the gas cools to rest); r = 1 with D > 0 (the heating is never dissipated).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from particles.collision import transfer_fraction
from particles.validation import InvalidArgumentError, check_restitution

from .model import DrivenMaxwellModel, MaxwellModel, maxwell_restitution

__all__ = [
    "DrivenSteadyState",
    "cumulants",
    "steady_kurtosis",
    "steady_variance",
    "characteristic_function",
    "tail_amplitude",
    "moments",
    "steady_state",
]

#: Terms of the ln P̂ series at |k|√D ≤ 1/2 (terms ≤ 4^{−j}: 4^{−30} ≈ 1e-18).
_SERIES_TERMS = 30
_LEAF = 0.5  # the series is used for |k|√D ≤ _LEAF
_HALF_WIDTH = 60.0  # the v-grid covers at least [−60√D, 60√D) ...
_SIGMAS = 15.0  # ... and 15 standard deviations √(D/(pq)) on either side

#: Largest number of cumulants (κ_{2j} holds (2j)!, which overflows float64 beyond 2j = 170).
MAX_CUMULANTS = 85



#: Largest heating strength accepted: the cumulants grow as D^j (j ≤ 4 by default), so D^4 must
#: stay finite in float64 with room to spare.
MAX_DRIVING = 1e60


def _check_driving(driving, restitution, *, allow_zero=False) -> tuple[float, float]:
    r = check_restitution(maxwell_restitution(restitution))
    try:
        d = float(driving)
    except (TypeError, ValueError):
        raise InvalidArgumentError("driving", driving, "a finite number > 0") from None
    if not math.isfinite(d) or d < 0.0:
        raise InvalidArgumentError("driving", driving, "a finite number > 0")
    if d > MAX_DRIVING:
        raise InvalidArgumentError(
            "driving", driving, f"D <= {MAX_DRIVING:g} (the cumulants, ~ D^j, overflow beyond)"
        )
    if d == 0.0 and not allow_zero:
        raise InvalidArgumentError(
            "driving", driving, "D > 0 (with D = 0 there is no steady state: the gas cools to rest)"
        )
    if r == 1.0:
        raise InvalidArgumentError(
            "restitution", restitution, "r < 1 (elastic collisions never dissipate the heating)"
        )
    if transfer_fraction(r) == 1.0:
        raise InvalidArgumentError(
            "restitution", restitution, "r < 1 with 1 − r above round-off (p = (1 + r)/2 rounds "
            "to 1: no dissipation left in float64)"
        )
    return r, d


def _check_count(count) -> int:
    from particles.validation import check_count

    count = check_count(count, "count", 1)
    if count > MAX_CUMULANTS:
        raise InvalidArgumentError(
            "count", count, f"at most {MAX_CUMULANTS} cumulants ((2j)! overflows beyond)")
    return count


def _rates(p: float, orders: np.ndarray) -> np.ndarray:
    """a_j = 1 − p^{2j} − q^{2j} (:meth:`.DrivenMaxwellModel.moment_rates`)."""
    return MaxwellModel.rate_of(p, 2.0 * orders)


def cumulants(restitution, driving, count: int = 4) -> np.ndarray:
    """Steady cumulants [κ₂, κ₄, …, κ_{2·count}] of the driven model (exact).

    κ_{2j} = (2j)! D^j/(j (1 − p^{2j} − q^{2j})), the coefficient of (ik)^{2j}/(2j)! in
    ln P̂(k) with P̂(k) = ∫ e^{ikv} P(v) dv; odd cumulants vanish (Santos & Ernst, Phys. Rev. E
    2003, derived here from the steady Fourier equation).

    Parameters
    ----------
    restitution : float
        r ∈ [0, 1); p = (1 + r)/2, q = 1 − p.
    driving : float
        Noise strength D > 0 (Fokker–Planck term D ∂²_v P, per unit τ).
    count : int, default 4
        Number of even cumulants.

    Returns
    -------
    numpy.ndarray
        Shape (count,): κ₂, κ₄, …, κ_{2·count}.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If r is outside [0, 1) or D is not a finite number in (0, MAX_DRIVING].
    """
    r, d = _check_driving(driving, restitution)
    count = _check_count(count)
    j = np.arange(1, count + 1, dtype=float)
    factorial = np.array([math.factorial(2 * int(i)) for i in j], dtype=float)
    return factorial * d**j / (j * _rates(transfer_fraction(r), j))


def steady_variance(restitution, driving) -> float:
    """Steady variance ⟨v²⟩ = D/(pq) of the driven model.

    Parameters
    ----------
    restitution : float
        r ∈ [0, 1).
    driving : float
        Noise strength D > 0.

    Returns
    -------
    float
        ⟨v²⟩ in the steady state (zero mean).

    Raises
    ------
    particles.validation.InvalidArgumentError
        If r is outside [0, 1) or D is not a finite number in (0, MAX_DRIVING].
    """
    r, d = _check_driving(driving, restitution)
    return DrivenMaxwellModel(r, driving=d).steady_energy


def steady_kurtosis(restitution, driving=1.0) -> float:
    """Steady kurtosis ⟨v⁴⟩/⟨v²⟩² = 3 + κ₄/κ₂² = 3 + 6pq/(2 − pq) (independent of D > 0).

    Parameters
    ----------
    restitution : float
        r ∈ [0, 1).
    driving : float, default 1.0
        Noise strength D > 0 (only checked: the kurtosis does not depend on it).

    Returns
    -------
    float
        The kurtosis, > 3 for r < 1.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If r is outside [0, 1) or D is not a finite number in (0, MAX_DRIVING].
    """
    r, _ = _check_driving(driving, restitution)
    pq = MaxwellModel(r).pair_lam
    return 3.0 + 6.0 * pq / (2.0 - pq)


def _series(p: float, y2: np.ndarray, terms: int = _SERIES_TERMS) -> np.ndarray:
    """Σ_j (−1)^j y2^j/(j a_j), j ≤ ``terms``, for y2 = D k² (ln P̂ near 0; |y2| < 1); y2 < 0
    gives ln P̂ at imaginary k."""
    out = np.zeros_like(y2)
    j = np.arange(terms, 0, -1, dtype=float)  # smallest terms first
    coef = (-1.0) ** j / (j * _rates(p, j))
    for c, jj in zip(coef, j, strict=True):
        out += c * y2**jj
    return out


def _log_cf_unit(p: float, k: np.ndarray) -> np.ndarray:
    """ln P̂(k) at D = 1 for real k (tree expansion of the module docstring)."""
    q = MaxwellModel.complement_of(p)
    k = np.abs(np.asarray(k, dtype=float))
    out = np.zeros_like(k)
    kmax = float(k.max(initial=0.0))
    level = {(0, 0): 1.0}  # nodes (a, b) of one depth a + b, with their number of paths
    while level:
        following: dict[tuple[int, int], float] = {}
        for (a, b), paths in level.items():
            w = p**a * q**b
            kw = k * w
            if kmax * w <= _LEAF or w == 0.0:
                out += paths * _series(p, kw * kw)
                continue
            out -= paths * np.log1p(kw * kw)
            for child in ((a + 1, b), (a, b + 1)):
                following[child] = following.get(child, 0.0) + paths
        level = following
    return out


def characteristic_function(k, restitution, driving) -> np.ndarray:
    """Steady P̂(k) = ⟨e^{ikv}⟩ = ∫ e^{ikv} P(v) dv (real and even) at real ``k``.

    Evaluated by the tree expansion of the module docstring (ln(1 + Dk²) at the nodes, the
    cumulant series at the leaves), exact up to round-off.

    Parameters
    ----------
    k : array_like
        Real wave numbers (unscaled: conjugate to v).
    restitution : float
        r ∈ [0, 1).
    driving : float
        Noise strength D > 0.

    Returns
    -------
    numpy.ndarray
        P̂(k), float, of the shape of ``k``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If r is outside [0, 1) or D is not a finite number in (0, MAX_DRIVING].
    """
    r, d = _check_driving(driving, restitution)
    k = np.asarray(k, dtype=float)
    return np.exp(_log_cf_unit(transfer_fraction(r), np.sqrt(d) * k))


def tail_amplitude(restitution) -> float:
    """R with P(v) ≈ (R/√D) e^{−|v|/√D} for |v| ≫ √D: R = ½ ⟨e^{pv}⟩⟨e^{qv}⟩ at D = 1.

    From the residue of P̂ at its nearest poles k = ±i/√D (Santos & Ernst, Phys. Rev. E 2003);
    ⟨e^{yv}⟩ = P̂(−iy) is summed from the cumulant series.

    Parameters
    ----------
    restitution : float
        r ∈ [0, 1).

    Returns
    -------
    float
        The amplitude R (independent of D).

    Raises
    ------
    particles.validation.InvalidArgumentError
        If r is outside [0, 1).
    """
    r, _ = _check_driving(1.0, restitution)
    p = transfer_fraction(r)
    y2 = -np.array([p * p, MaxwellModel.complement_of(p) ** 2])  # D k² at k = −ip, −iq
    terms = int(np.ceil(40.0 / -np.log(p * p))) + 1  # p^{2j} < e^{−40}
    return 0.5 * float(np.exp(_series(p, y2, max(terms, _SERIES_TERMS))).prod())


def moments(tau, restitution, driving, m2_initial=1.0, m4_initial=3.0):
    """Exact M₂(τ), M₄(τ) of the driven model from zero-mean data with M₂(0), M₄(0).

    The closed moment equations of the module docstring, solved as sums of exponentials in τ
    (collisions per particle).  D = 0 is accepted here (free cooling).

    Parameters
    ----------
    tau : float or array_like
        Collisions per particle τ.
    restitution : float
        r ∈ [0, 1).
    driving : float
        Noise strength D ≥ 0.
    m2_initial, m4_initial : float, default 1.0 and 3.0
        M₂(0) and M₄(0) (the defaults are a unit Gaussian).

    Returns
    -------
    m2, m4 : numpy.ndarray
        M₂(τ) and M₄(τ), of the shape of ``tau``.

    Raises
    ------
    particles.validation.InvalidArgumentError
        If r is outside [0, 1) or D is negative, not finite or above MAX_DRIVING.
    """
    r, d = _check_driving(driving, restitution, allow_zero=True)
    p = transfer_fraction(r)
    pq = MaxwellModel.lam_of(p)
    tau = np.asarray(tau, dtype=float)
    a2 = 2.0 * pq
    a4 = MaxwellModel.rate_of(p, 4)  # = 2pq(2 − pq), never a2 or 2 a2 for r < 1
    m2_steady = d / pq
    amp = m2_initial - m2_steady
    m2 = m2_steady + amp * np.exp(-a2 * tau)
    # forcing 12 D M₂ + 6p²q² M₂² = f0 + f1 e^{−a2 τ} + f2 e^{−2 a2 τ}
    c = 6.0 * pq * pq
    f0 = 12.0 * d * m2_steady + c * m2_steady**2
    f1 = 12.0 * d * amp + 2.0 * c * m2_steady * amp
    f2 = c * amp * amp
    g0, g1, g2 = f0 / a4, f1 / (a4 - a2), f2 / (a4 - 2.0 * a2)
    m4 = (
        g0
        + g1 * np.exp(-a2 * tau)
        + g2 * np.exp(-2.0 * a2 * tau)
        + (m4_initial - g0 - g1 - g2) * np.exp(-a4 * tau)
    )
    return m2, m4


@dataclass(frozen=True)
class DrivenSteadyState:
    """The steady state of the driven 1D model, as returned by :func:`steady_state`.

    Attributes
    ----------
    restitution : float
        r ∈ [0, 1).
    driving : float
        Noise strength D > 0.
    variance : float
        ⟨v²⟩ = D/(pq).
    kurtosis : float
        ⟨v⁴⟩/⟨v²⟩² = 3 + 6pq/(2 − pq).
    cumulants : numpy.ndarray
        [κ₂, κ₄, …] (see :func:`cumulants`).
    velocity : numpy.ndarray
        Uniform velocity grid on [−H, H), H = √D · max(60, 15/√(pq)) (15 standard
        deviations of the steady law on either side: wider than 60√D for r > 0.87).
    density : numpy.ndarray
        P(v) on ``velocity``, from an FFT of P̂ (P(v) = (1/2π) ∫ e^{−ikv} P̂(k) dk, numpy's
        forward sign; round-off ~ 1e-16).
    """

    restitution: float
    driving: float
    variance: float
    kurtosis: float
    cumulants: np.ndarray = field(repr=False)
    velocity: np.ndarray = field(repr=False)
    density: np.ndarray = field(repr=False)


def _half_width(p: float) -> float:
    """Half-width H of the x grid at D = 1: max(60, 15/√(pq)) (15 standard deviations)."""
    return max(_HALF_WIDTH, _SIGMAS / math.sqrt(MaxwellModel.lam_of(p)))


def _first_kmax(p: float) -> float:
    """Starting k_max: 8, or 16√(pq) on the wider grids of pq < 1/16 (r > 0.87), where
    P̂ ≈ e^{−k²/(2pq)} is then below e^{−128}.  The tree expansion of ln P̂ has
    ~ ln(2 k_max)/(1 − p) levels and the FFT grid ~ k_max H points, so a k_max fixed at 8 made
    the cost grow like 1/(1 − r) (16 s at r = 0.9999, a day near r = 1 − 1e-8); with k_max
    ∝ √(pq) ∝ 1/H both stay bounded for every r < 1."""
    pq = MaxwellModel.lam_of(p)
    return 8.0 if _half_width(p) == _HALF_WIDTH else 16.0 * math.sqrt(pq)


def _density_unit(p: float) -> tuple[np.ndarray, np.ndarray]:
    """P(x) at D = 1 on [−H, H) by FFT, H = :func:`_half_width`."""
    period = 2.0 * _half_width(p)
    dk = 2.0 * math.pi / period
    # k_max: double until ln P̂(k_max) < −40
    kmax = _first_kmax(p)
    while _log_cf_unit(p, np.array([kmax]))[0] > -40.0:
        kmax *= 2.0
    m = max(512, 1 << int(np.ceil(np.log2(2.0 * kmax / dk))))
    k = np.fft.fftfreq(m, d=1.0 / (m * dk))  # k_j = j Δk in FFT order, |k| ≤ m Δk/2 ≥ k_max
    phi = np.exp(_log_cf_unit(p, k))
    # P(x_n) = (Δk/2π) Σ_j P̂(k_j) e^{−i k_j x_n}, x_n = n · period/m: numpy's forward FFT sign
    dens = np.fft.fftshift(np.fft.fft(phi).real) * dk / (2.0 * math.pi)
    x = (np.arange(m) - m // 2) * (period / m)
    return x, dens


def steady_state(restitution, driving, count: int = 4) -> DrivenSteadyState:
    """The steady state of the driven model for r ∈ [0, 1), D > 0 (``count`` cumulants).

    Parameters
    ----------
    restitution : float or particles.kernels.Kernel
        r ∈ [0, 1), or the Maxwell kernel of r (:func:`maxwell_kinetics.model.maxwell_restitution`).
    driving : float
        D > 0, the strength of the white noise (Fokker–Planck term D ∂²_v P).
    count : int
        Number of cumulants to return.

    Returns
    -------
    DrivenSteadyState
        Variance D/(pq), kurtosis 3 + 6pq/(2 − pq), the first cumulants (all exact) and the
        density on a grid, whose tail is exp(−|v|/√D) (Santos and Ernst).

    Raises
    ------
    particles.InvalidArgumentError
        For r or D out of range; naming ``kernel`` for a kernel whose Fourier-space equation does
        not close.
    """
    r, d = _check_driving(driving, restitution)
    x, dens = _density_unit(transfer_fraction(r))
    scale = math.sqrt(d)
    return DrivenSteadyState(
        r,
        d,
        steady_variance(r, d),
        steady_kurtosis(r, d),
        cumulants(r, d, count),
        x * scale,
        dens / scale,
    )
