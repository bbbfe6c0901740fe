"""The overpopulated tail of the hard-disk cooling state in comparison ``hard_spheres``: how far
the Maxwell model's power-law tail is from the hard spheres' exponential one.

Conventions (those of :mod:`maxwell_kinetics.sphere_tail`).  c is the scaled velocity of unit
variance per component, c = (v − u)/√T with T = ⟨|v − u|²⟩/d, and F(c) its density
(∫F dc = 1; the solver's F normalised on its grid).  Both models' cooling states are taken at
the same restitution α (the tails' r is α: v′ = v − (1 + α)/2 (g·n) n) and in the same d.

* Hard spheres (rate |g·n|): F ∝ c^μ exp(−A c) at large c, A = 2K/ζ*
  (:func:`maxwell_kinetics.sphere_tail.tail_rate`, ζ* the solver's own cooling rate per unit
  τ = ∫n√T dt).
* The Maxwell model of the comparison, :class:`particles.sphere_kernels.VariableHardSpheres`
  at γ = 0 (Ulam's ``angular="uniform"`` in d = 2, ``"hard"`` in d = 3): F ∝ c^(−p) with
  p = d + 2s* (:func:`maxwell_kinetics.tails.tail_exponent`, the density's exponent; the
  speed's would be 1 + 2s*).  An exponent is the same in every scale of c.  Its scaled state
  itself is the Fourier fixed point (:func:`maxwell_kinetics.stationary.fixed_point`, G''(0) =
  −1: the same unit variance per component) inverted by the Hankel transform
  (:func:`maxwell_kinetics.velocity.radial_density_at`): no box, no cutoff.  The spectral
  solver's γ = 0 cooling state is not used: the power-law tail reaches its box (benchmarks:
  no stationary state within τ = 40 on ``coarse``).

Measurement (:func:`measure`).  The profile of ln F over shells of |c| of width h (the
reported grid's spacing, on both grids) leaving out the nodes within :data:`AXIS_GAP` = 20° of
the axes, where the Fourier cutoff rings (:func:`maxwell_kinetics.sphere_tail.radial_profile`).
The window rule, stated once and never tuned by hand: the window holds
:data:`WINDOW_SHELLS` = 5.5 shells (W = 5.5 h: the fit's five shells, or six), moves by ± W/4
for the window systematic, and is the OUTERMOST one whose moved copies
stay inside the profile resolved on BOTH grids: c_hi = min(resolved) − W/4, c_lo = c_hi − W.
It is accepted only when c_lo ≥ :data:`TAIL_START` = 3 (three thermal speeds: below, the fit
is the Gaussian core's); otherwise the tail is not measured (d = 3 on the default size's
grids: shells of h = 0.75 inside R = 7 and 6 leave no such window even for an exact
exponential).  The fit ln F = a + μ ln c − A c (:func:`maxwell_kinetics.sphere_tail.fit_tail`) gives
A with its standard error (n − 3 degrees of freedom for n shells) and the window systematic;
the grid difference is |A − A₂|, A₂ the same fit on the second grid.  On the default size's
d = 2 grids the off-axis profile is resolved up to the kernel's cutoff (R = 7.5 and 7), which
bends F from c ≈ R − 3 (benchmarks/README.md): the grid difference, between two cutoffs,
carries that error, and it is large (0.53 in A, measured).

The discriminating statistic (:func:`verdicts`).  The fitted A itself: with the fitted form
the local log-log slope is −d ln F/d ln c = A c − μ, so A is exactly the rate at which that
slope rises across the window; a power law c^(−p) keeps it at p and gives A = 0 (to
round-off, whatever p and its amplitude: so the statistic needs neither s* nor the Maxwell
model's amplitude).  It is set against the Maxwell model's OWN A, its exact scaled state
fitted the same way on the same nodes and window, not against 0: at |c| ≈ 4–6 that state is
not yet its power law (measured, d = 2, α = 0.5, window [3.72, 6.24]: A = 0.49 ± 0.04, its
log-log slope 7.4 → 8.7 against p = 9.04 beyond), and 0 would credit the Maxwell model with
an asymptote it has not reached there.  The level of the log-log slope against p was not
chosen: it depends on s* and on how far the Maxwell state is from its asymptote.  The
claim's failure is refuted (its cause shown) by an independent number of the solver: the
collision frequency ν(c) = loss/F of the hard-sphere cooling state rises across the window
(as K c), where the Maxwell model's is the same at every c.  F_Maxwell/F_HS at the last shell
resolved on both grids says how far the Maxwell tail is.
"""

from __future__ import annotations

import functools
import math
import time

import numpy as np

from particles.validation import InvalidArgumentError

from ...sphere_grid import sphere_grid
from ...sphere_spectral import SphereOperator
from ...sphere_tail import MIN_SHELLS, fit_tail, node_speeds, radial_profile, tail_rate
from ...stationary import fixed_point
from ...tails import tail_exponent
from ...velocity import radial_density_at
from .verdicts import Check, judge

__all__ = ["AXIS_GAP", "WINDOW_SHELLS", "TAIL_START", "MAXWELL_DEGREES", "tail_window",
           "maxwell_density", "measure", "not_computed", "verdicts", "tells_apart",
           "beyond_crossover", "rate_claim_resolution", "maxwell_claim_resolution", "draw"]

#: Leave out the nodes within this angle (degrees) of a coordinate axis.
AXIS_GAP = 20.0
#: The window's width in shells: 5.5 holds :data:`MIN_SHELLS` = 5 shell means or 6 (a
#: window that holds fewer, in it or moved, leaves the tail not measured, with the reason).
WINDOW_SHELLS = MIN_SHELLS + 0.5
#: The earliest start of an accepted window (in |c|): three thermal speeds.
TAIL_START = 3.0
#: (Chebyshev degree, η nodes) of the two Maxwell fixed points; their difference is the error.
MAXWELL_DEGREES = ((128, 16), (192, 32))

_WHY_THREE = ("the cooling state's profile off the axes is not resolved far enough: a window "
              "of {shells:g} shells (W = {width:.3g}) moved by ±W/4 inside |c| < {resolved:.3g} "
              "starts at {start}, below |c| = {first:g}")


def tail_window(resolved: float, width: float) -> tuple[float, float, float]:
    """The outermost window of the rule (module docstring): ``(c_lo, c_hi, shift)`` with
    c_hi = ``resolved`` − W/4, c_lo = c_hi − W, shift = W/4, W = :data:`WINDOW_SHELLS` ×
    ``width``.

    Parameters
    ----------
    resolved : float
        The |c| up to which the profile is resolved on every grid used.
    width : float
        The shells' width.

    Returns
    -------
    tuple of float
        c_lo, c_hi and the shift; c_lo may be below :data:`TAIL_START` (the window is then not
        accepted).
    """
    w = WINDOW_SHELLS * float(width)
    shift = 0.25 * w
    hi = float(resolved) - shift
    return hi - w, hi, shift


def maxwell_density(restitution: float, dimension: int, speeds, degree: int = 128,
                    nodes: int = 16) -> np.ndarray:
    """The Maxwell model's scaled density F(c) (unit variance per component, ∫F dc = 1) at the
    speeds |c| = ``speeds``: the Fourier fixed point inverted in d dimensions.

    Parameters
    ----------
    restitution : float
        α ∈ [0, 1).
    dimension : int
        d, 2 or 3 (the angular law of :class:`particles.sphere_kernels.VariableHardSpheres` at
        γ = 0: "uniform" in d = 2, "hard" in d = 3).
    speeds : array_like
        |c| ≥ 0.
    degree, nodes : int
        The fixed point's Chebyshev degree and η quadrature nodes.

    Returns
    -------
    numpy.ndarray
        F at ``speeds``.

    Raises
    ------
    RuntimeError
        When the fixed point's Gauss–Newton iteration does not converge.
    """
    fp = _fixed_point(float(restitution), int(dimension), int(degree), int(nodes))
    return radial_density_at(fp, speeds, dimension, q_max=fp.q_max)


@functools.lru_cache(maxsize=8)
def _fixed_point(restitution, dimension, degree, nodes):
    """The Maxwell model's fixed point (kept: a comparison asks for it several times)."""
    fp = fixed_point(restitution, degree, dimension=dimension, angular_nodes=nodes,
                     angular="uniform" if dimension == 2 else "hard")
    if not fp.converged:
        raise RuntimeError(f"the Maxwell fixed point (d = {dimension}, n = {degree}) did not "
                           f"converge (residual {fp.residual:.3g})")
    return fp


def _profile(F, grid, width):
    """The off-axis profile of F normalised to ∫F dc = 1 on its grid."""
    F = np.asarray(F, dtype=float)
    F = F / (float(np.sum(F)) * grid.spacing**F.ndim)
    return radial_profile(F, grid, width=width, axis_gap=AXIS_GAP)


def _maxwell_profile(alpha, d, grid, width, degree, nodes):
    """The profile of the Maxwell model's F on the nodes of ``grid`` (the same shells)."""
    r, _ = node_speeds(grid, d)
    unique, inverse = np.unique(np.round(r, 12), return_inverse=True)
    inside = unique <= grid.cutoff + width
    values = np.full(unique.shape, 1e-300)  # outside the kept shells: never read
    values[inside] = maxwell_density(alpha, d, unique[inside], degree, nodes)
    F = values[inverse].reshape(r.shape)
    return radial_profile(F, grid, width=width, axis_gap=AXIS_GAP)


def _solver_loss(kernel, dimension):
    """loss(state): the spectral operator's collision loss ν F at the state's nodes."""
    def loss(state):
        return SphereOperator(kernel, dimension, state.grid).collision(state.F)[1]
    return loss


def _collision_rates(states, grids, kernel, d, width, profile, window, loss) -> dict:
    """ν = loss/F averaged over the off-axis nodes of the window's first and last shells, on
    both grids: the collision frequency of a particle at |c| in the cooling state."""
    loss = _solver_loss(kernel, d) if loss is None else loss
    inside = profile.speed[(profile.speed >= window[0]) & (profile.speed <= window[1])]
    shells = np.floor(inside[[0, -1]] / width).astype(int)
    k = float(np.asarray(kernel.rate(np.eye(1, d), np.zeros((1, d)), np))[0])  # K
    rates = []
    for state, grid in zip(states, grids, strict=True):
        r, off = node_speeds(grid, d, AXIS_GAP)
        gone, F = np.asarray(loss(state), dtype=float), np.asarray(state.F, dtype=float)
        shell = np.floor(r / width).astype(int)
        picks = [off & (shell == j) for j in shells]  # F > 0 there: resolved shells
        rates.append([float(np.mean(gone[pick] / F[pick])) for pick in picks])
    speeds = inside[[0, -1]]
    ratios = [b / a for a, b in rates]
    return {"speeds": speeds.tolist(), "rates": rates[0],
            "over_asymptotic": [nu / (k * (c + (d - 1) / (2 * c)))
                                for nu, c in zip(rates[0], speeds, strict=True)],
            "ratio": ratios[0], "second_ratio": ratios[1],
            "grid_difference": abs(ratios[0] - ratios[1]), "sphere_factor": k}


def _not_measured(record: dict, reason: str) -> tuple[dict, None]:
    record.update(measured=False, reason=reason)
    return record, None


def measure(states, kernel, dimension: int, loss=None) -> tuple[dict, dict | None]:
    """The tail of the hard-sphere cooling state on two grids, and the Maxwell model's in the
    same window (module docstring).

    Parameters
    ----------
    states : sequence of maxwell_kinetics.sphere_spectral.CoolingState
        The cooling state on the reported grid, then on the second grid.
    kernel : particles.sphere_kernels.HardSpheres
        Their kernel (for the predicted A and the collision operator).
    dimension : int
        d.
    loss : callable, optional
        ``loss(state)``: the collision loss ν(c) F at the state's nodes (default the spectral
        operator's, :meth:`maxwell_kinetics.sphere_spectral.SphereOperator.collision`).

    Returns
    -------
    record : dict
        JSON-able: ``measured`` (and ``reason`` when not), ``axis_gap``, ``shell_width``,
        ``resolved`` (both grids), ``last_resolved``, ``predicted_rate``, ``crossover``
        (2A, where exp(−A c) overtakes the Gaussian core), ``window``, ``shift``, ``fit``
        (:meth:`maxwell_kinetics.sphere_tail.TailFit.to_dict`), ``rate``, ``rate_error``,
        ``rate_dof``, ``window_systematic``, ``second_rate``, ``grid_difference``,
        ``loglog_slope`` (A c − μ at c_lo and c_hi), ``collision_rate`` (ν = loss/F averaged
        over the window's first and last shells off the axes: ``speeds``, ``rates``,
        ``over_asymptotic`` ν/(K(c + (d − 1)/(2c))), ``ratio`` of the last to the first and its
        ``grid_difference``), and ``maxwell``: its exponents, its own fit on the window
        (``rate``, ``rate_error``, ``rate_dof``, ``window_systematic``, ``numerical_error``,
        ``loglog_slope``), ``difference`` A − A_Maxwell with its ``difference_systematic``
        (the largest change of the difference on the moved windows), and ``density_ratio``
        F_Maxwell/F_HS at ``speed`` (the last shell resolved on both grids) with
        ``log_ratio_error``.
    figure : dict or None
        The arrays of the figure's panel (None when not measured).

    Raises
    ------
    RuntimeError
        When a Maxwell fixed point does not converge.
    """
    start = time.perf_counter()
    d = int(dimension)
    grids = [sphere_grid(s.grid, d) for s in states]
    width = grids[0].spacing
    alpha = float(kernel.restitution)
    predicted = tail_rate(kernel, d, states[0].cooling_rate)
    law = tail_exponent(d, alpha, "uniform" if d == 2 else "hard")
    record = {"axis_gap": AXIS_GAP, "shell_width": width, "window_shells": WINDOW_SHELLS,
              "tail_start": TAIL_START, "predicted_rate": predicted,
              "cooling_rate": states[0].cooling_rate, "crossover": 2.0 * predicted,
              "maxwell_exponent": law.exponents["density"], "maxwell_s_star": law.s}
    profiles = [_profile(s.F, g, width) for s, g in zip(states, grids, strict=True)]
    record["resolved"] = [p.resolved for p in profiles]
    record["last_resolved"] = profiles[0].resolved
    reach = min(p.resolved for p in profiles)
    lo, hi, shift = tail_window(reach, width)
    record.update(window=[lo, hi], shift=shift)
    if lo < TAIL_START:
        return _not_measured(record, _WHY_THREE.format(
            shells=WINDOW_SHELLS, width=WINDOW_SHELLS * width, resolved=reach,
            start=f"{lo:.3g}", first=TAIL_START))
    try:
        fits = [fit_tail(p, (lo, hi), shift=shift, predicted=predicted) for p in profiles]
    except InvalidArgumentError as exc:  # too few shells in a (moved) window
        return _not_measured(record, f"no fit on the window: {exc}")
    fit = fits[0]
    record.update(measured=True, reason="", fit=fit.to_dict(), rate=fit.rate,
                  rate_error=fit.rate_error, rate_dof=fit.shells - 3,
                  window_systematic=fit.window_systematic, second_rate=fits[1].rate,
                  grid_difference=abs(fit.rate - fits[1].rate),
                  loglog_slope=[fit.rate * c - fit.power for c in (lo, hi)])
    # the Maxwell model on the same nodes, shells and window; two resolutions: the error
    maxwell = [_maxwell_profile(alpha, d, grids[0], width, n, m) for n, m in MAXWELL_DEGREES]
    m_fits = [fit_tail(p, (lo, hi), shift=shift) for p in maxwell]
    difference = fit.rate - m_fits[0].rate
    moved = [a - b for a, b in zip(fit.moved_rates, m_fits[0].moved_rates, strict=True)]
    record["collision_rate"] = _collision_rates(states, grids, kernel, d, width, profiles[0],
                                                (lo, hi), loss)
    # the last shell resolved on both grids: ln F_HS there on each (the second's profile
    # interpolated to the same |c|; their difference is the grid error)
    last = float(min(p.speed[-1] for p in profiles))
    hs_last, hs_second = (float(np.interp(last, p.speed, p.log_density)) for p in profiles)
    m_last = [float(maxwell_density(alpha, d, [last], n, m)[0]) for n, m in MAXWELL_DEGREES]
    log_ratio = math.log(m_last[0]) - hs_last
    record["maxwell"] = {
        "angular": "uniform" if d == 2 else "hard", "s_star": law.s,
        "exponent": law.exponents["density"], "rate": m_fits[0].rate,
        "rate_error": m_fits[0].rate_error, "rate_dof": m_fits[0].shells - 3,
        "window_systematic": m_fits[0].window_systematic,
        "numerical_error": abs(m_fits[0].rate - m_fits[1].rate),
        "power": m_fits[0].power, "degrees": [list(x) for x in MAXWELL_DEGREES],
        "loglog_slope": [m_fits[0].rate * c - m_fits[0].power for c in (lo, hi)],
        "difference": difference,
        "difference_systematic": max(abs(m - difference) for m in moved),
        "speed": float(last), "density": m_last[0], "hs_density": math.exp(hs_last),
        "density_ratio": math.exp(log_ratio), "log_ratio": log_ratio,
        "log_ratio_error": abs(math.log(m_last[0]) - math.log(m_last[1]))
        + abs(hs_last - hs_second)}
    record["seconds"] = time.perf_counter() - start
    c = np.linspace(0.0, float(profiles[0].resolved), 121)[1:]
    figure = {"speed": profiles[0].speed, "log_density": profiles[0].log_density,
              "maxwell_speed": c,
              "maxwell_log_density": np.log(maxwell_density(alpha, d, c, *MAXWELL_DEGREES[0]))}
    return record, figure


def not_computed(dimension: int) -> dict:
    """The record of a size without the solver's cooling state.

    Parameters
    ----------
    dimension : int
        d.

    Returns
    -------
    dict
        ``measured`` False and the ``reason``.
    """
    return {"measured": False, "dimension": int(dimension),
            "reason": "the solver's cooling state is computed at the default and full sizes "
                      "only"}


def verdicts(row: dict) -> list:
    """The two tail claims of one dimension's row (``row["tail"]`` from :func:`measure`).

    * "the Maxwell model's power-law tail is the hard-sphere tail": the hard-sphere fitted A
      against the Maxwell model's own fitted A on the same nodes and window (its exact scaled
      state; a pure power law would give 0), σ the two fits' standard errors (Student's t,
      n − 3 dof each, Welch), tolerance the window systematic of the difference, the grid
      difference of A and the Maxwell state's numerical error; refuted when it fails and the
      cause shows in the solver's cooling state: the collision frequency ν(c) = loss/F of
      the window's last shell differs from its first one's (the Maxwell model's rate is the
      same at every c), beyond the grid difference of that ratio;
    * "A = 2K/ζ*": the fitted A against the prediction, σ the fit's standard error,
      tolerance the window systematic and the grid difference; ``not measured`` while the
      window starts before the crossover 2A (:func:`beyond_crossover`) or the fitted A
      drifts with the window by more than its error (window systematic > fit error: the fit
      is not yet in the exponential regime).

    Both are ``not measured`` where no window is accepted; the first also where the deviation
    its check allows is not below the gap between 2K/ζ* and the Maxwell model's A
    (:func:`tells_apart`: the check could not tell the two tails apart).

    Parameters
    ----------
    row : dict
        A row of the comparison's summary, with ``dimension``, ``grid``, ``second_grid`` and
        ``tail``.

    Returns
    -------
    list of maxwell_kinetics.app.comparisons.verdicts.Verdict
        Empty when the row has no tail record (a size without the cooling state).
    """
    tail = row.get("tail")
    if not tail or "window" not in tail:
        return []
    d = row["dimension"]
    body, name = ("hard spheres", "hard-sphere") if d == 3 else ("hard disks", "hard-disk")
    grids = f"grids {row['grid']} and {row['second_grid']}"
    measured = bool(tail.get("measured"))
    lo, hi = tail["window"]
    window = (f"|c| ∈ [{lo:.2f}, {hi:.2f}]" if lo >= TAIL_START
              else f"the rule's outermost window (none from |c| ≥ {TAIL_START:g})")
    placed = Check(f"start of the outermost window of {WINDOW_SHELLS:g} shells off the axes "
                   f"(resolved on both grids to |c| = {min(tail['resolved']):.2f})", lo, None,
                   TAIL_START, "exact: the window rule (three thermal speeds)",
                   relation="at_least")
    quantity = f"fitted A of ln F = a + μ ln c − A c, {window}, nodes ≥ {AXIS_GAP:g}° off axes"
    maxwell = tail.get("maxwell") or {}
    rate = tail.get("rate") if measured else None
    fit_sigma = tail.get("rate_error") if measured else None
    dof = tail.get("rate_dof") if measured else None
    shells = f"{dof + 3} shells" if dof else "the shells"
    not_yet = "a wider grid than any size's (none yet)"
    if measured:
        m_dof = maxwell["rate_dof"]
        claim_check = Check(
            quantity, rate, fit_sigma, maxwell["rate"],
            f"model: the Maxwell model's exact scaled state (Fourier fixed point), fitted the "
            f"same way on the same nodes (power law c^(−{tail['maxwell_exponent']:.3f}) "
            f"beyond; a pure power law gives A = 0)", expected_sigma=maxwell["rate_error"],
            dof=dof, expected_dof=m_dof, t_law=True,
            tolerance=(maxwell["difference_systematic"] + tail["grid_difference"]
                       + maxwell["numerical_error"]),
            sigma_source=f"fits over {shells} (n − 3 dof each); tolerance: the window "
                         f"systematic of the difference (windows moved by "
                         f"±{tail['shift']:.2f}), the grid difference of A between {grids}, "
                         f"the difference of two fixed-point resolutions")
        rates = tail["collision_rate"]
        a, b = rates["speeds"]
        refutation = Check(
            f"collision frequency ν = loss/F of the {name} cooling state, shell at |c| = "
            f"{b:.2f} over the shell at {a:.2f} (off the axes)", rates["ratio"], None, 1.0,
            "exact: the Maxwell model's rate, the same at every c", relation="differs",
            tolerance=rates["grid_difference"],
            sigma_source=f"deterministic; tolerance: the ratio's difference between {grids}")
        near = ", ".join(f"{x:.3f}" for x in rates["over_asymptotic"])
        why = (f"the hard-sphere rate |g| makes a fast particle's collision frequency grow like "
               f"c (measured: ν/(K(c + (d − 1)/(2c))) = {near} at |c| = {a:.2f}, {b:.2f}), so "
               f"the log-log slope of the tail keeps rising (an exponential); the Maxwell "
               f"model's constant rate leaves a power law")
        resolves, why = maxwell_claim_resolution(claim_check, tail["predicted_rate"],
                                                 maxwell["rate"], why, "this size")
    else:
        claim_check = Check(quantity, None, None, 0.0, "model: the Maxwell model's power law "
                            "(A = 0 in this fit)")
        refutation, why, resolves = None, tail.get("reason") or "", placed
    out = [judge(
        f"{body}, d = {d}: the Maxwell model's power-law tail c^(−d−2s*) is the {name} "
        f"cooling state's tail", claim_check, why=why, refutation=refutation,
        resolution=resolves, measured_at="default" if measured else not_yet,
        short=f"d={d}: Maxwell tail = HS tail")]
    drift = Check(f"window systematic of the fitted A (window moved by ±{tail['shift']:.2f})",
                  tail.get("window_systematic") if measured else None, None,
                  fit_sigma if fit_sigma is not None else 0.0,
                  "exact: at most the fit's own standard error (the fit is stable under the "
                  "window's move)", relation="at_most")
    why_rate = tail.get("reason") or ""
    if measured:
        why_rate = (f"the fitted A still drifts with the window: moving it by "
                    f"±{tail['shift']:.2f} changes A by {tail['window_systematic']:.3f}, more "
                    f"than its fit error {tail['rate_error']:.3f} (A = {tail['rate']:.3f} on "
                    f"{window} against {tail['predicted_rate']:.3f}; exp(−A c) overtakes the "
                    f"Gaussian core only beyond c ≈ 2A = {tail['crossover']:.2f}, the profile "
                    f"is resolved to |c| = {min(tail['resolved']):.2f})")
        drift, why_rate = rate_claim_resolution(lo, tail["predicted_rate"], tail["rate"],
                                                window, drift, why_rate)
    out.append(judge(
        f"{body}, d = {d}: the cooling state's tail is exp(−A c) with A = 2K/ζ* "
        f"(Esipov–Pöschel, van Noije–Ernst)",
        Check(quantity, rate, fit_sigma, tail["predicted_rate"],
              "model: A = 2K/ζ* with the solver's own ζ*", dof=dof, t_law=measured,
              tolerance=(tail["window_systematic"] + tail["grid_difference"]
                         if measured else 0.0),
              sigma_source=f"fit over {shells} (n − 3 dof); tolerance: the window systematic "
                           f"(window moved by ±{tail['shift']:.2f}) + the grid difference of "
                           f"A between {grids}"),
        why=why_rate, resolution=drift if measured else placed, measured_at=not_yet,
        short=f"d={d}: HS tail A = 2K/ζ*"))
    return out


def beyond_crossover(start: float, predicted: float) -> Check:
    """The first resolution of a claim "A = 2K/ζ*": the window starts beyond the crossover
    c = 2A at which exp(−A c) overtakes the Gaussian core exp(−c²/2).  Before it, the fitted A
    measures the crossover, not the asymptote (it is larger), and a stable fit there would
    judge the theory outside its domain.

    Parameters
    ----------
    start : float
        The window's first |c|.
    predicted : float
        A = 2K/ζ*.

    Returns
    -------
    maxwell_kinetics.app.comparisons.verdicts.Check
    """
    return Check("start of the fit's window", float(start), None, 2.0 * float(predicted),
                 "exact: at least the crossover c = 2A where exp(−A c) overtakes the Gaussian "
                 "core exp(−c²/2) (the asymptotic law's domain)", relation="at_least")


def rate_claim_resolution(start: float, predicted: float, rate: float, window: str,
                          drift: Check, why: str) -> tuple[Check, str]:
    """The resolution of a measured claim "A = 2K/ζ*" and its reason: :func:`beyond_crossover`
    first (the one shown when it fails), then ``drift`` (the fit stable under the window's
    move) with ``why``.

    Parameters
    ----------
    start, predicted, rate : float
        The window's first |c|, 2K/ζ* and the fitted A.
    window : str
        The window in words.
    drift : maxwell_kinetics.app.comparisons.verdicts.Check
        The stability check of the fit.
    why : str
        The reason shown when ``drift`` fails.

    Returns
    -------
    tuple of (maxwell_kinetics.app.comparisons.verdicts.Check, str)
    """
    asymptotic = beyond_crossover(start, predicted)
    if asymptotic.holds():
        return drift, why
    return asymptotic, (f"the window starts at |c| = {start:.2f}, before the crossover 2A = "
                        f"{2.0 * predicted:.2f} where exp(−A c) overtakes the Gaussian core: "
                        f"the fit (A = {rate:.3f} on {window}, against 2K/ζ* = "
                        f"{predicted:.3f}) measures the crossover, not the asymptote")


def maxwell_claim_resolution(check: Check, predicted: float, maxwell: float, why: str,
                             who: str) -> tuple[Check, str]:
    """The resolution of a measured claim "the Maxwell model's tail is the hard-sphere tail"
    (:func:`tells_apart`) and the reason shown: ``why`` when it holds, else that ``who``
    ("this size", "this sample") cannot tell the two tails apart.

    Parameters
    ----------
    check : maxwell_kinetics.app.comparisons.verdicts.Check
        The claim's check.
    predicted, maxwell : float
        2K/ζ* and the Maxwell model's fitted A on the window.
    why : str
        The claim's reason (its refutation's cause).
    who : str
        What measured it, in words.

    Returns
    -------
    tuple of (maxwell_kinetics.app.comparisons.verdicts.Check, str)
    """
    resolves = tells_apart(check, predicted, maxwell)
    if resolves.holds():
        return resolves, why
    return resolves, (f"{who} cannot tell the two tails apart: it allows a deviation of "
                      f"{check.allowed:.3f}, more than the gap {resolves.expected:.3f} "
                      f"between 2K/ζ* and the Maxwell model's A on the window")


def tells_apart(check: Check, predicted: float, maxwell: float) -> Check:
    """The resolution of a claim "the Maxwell model's tail is the hard-sphere tail": the
    deviation that ``check`` allows (its standard errors of the t law and its tolerance) must
    lie below the gap |2K/ζ* − A_Maxwell| between the predicted hard-sphere rate and the
    Maxwell model's fitted A on the same window; a larger allowance would let the two tails
    agree whatever they are, and the claim is then not measured.

    Parameters
    ----------
    check : maxwell_kinetics.app.comparisons.verdicts.Check
        The claim's check (the hard-sphere fitted A against the Maxwell model's).
    predicted : float
        2K/ζ*.
    maxwell : float
        The Maxwell model's fitted A on the window.

    Returns
    -------
    maxwell_kinetics.app.comparisons.verdicts.Check
    """
    return Check("the deviation this check allows (its t-law standard errors + tolerance)",
                 check.allowed, None, abs(predicted - maxwell),
                 "exact: below the gap between 2K/ζ* and the Maxwell model's A on the window "
                 "(else the check cannot tell the two tails apart)", relation="below")


def draw(ax, rows, curves) -> bool:
    """The tail panel: ln F of the hard-sphere cooling state off the axes against |c|, the
    fitted a + μ ln c − A c over its window, the predicted rate (the same curve with A = 2K/ζ*
    through the fit at the window's middle), the Maxwell model's scaled state and its power law
    c^(−d−2s*) (through it at the last resolved |c|).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The panel.
    rows, curves : list
        The comparison's rows and figure data (``curves[i]["tail"]``).

    Returns
    -------
    bool
        Whether a measured tail was drawn.
    """
    drawn = False
    for i, (row, cur) in enumerate(zip(rows, curves, strict=True)):
        tail, data = row.get("tail") or {}, cur.get("tail")
        if not tail.get("measured") or data is None:
            continue
        drawn, col, d = True, f"C{i}", row["dimension"]
        fit = tail["fit"]
        ax.plot(data["speed"], data["log_density"], "o", ms=3, color=col,
                label=f"d = {d}: HS, ≥ {tail['axis_gap']:g}° off axes")
        lo, hi = tail["window"]
        c = np.linspace(0.6 * lo, data["speed"][-1], 80)
        line = fit["amplitude"] + fit["power"] * np.log(c) - fit["rate"] * c
        ax.plot(c, line, "-", color=col,
                label=f"fit A = {fit['rate']:.2f} ± {fit['rate_error']:.2f} ± "
                      f"{fit['window_systematic']:.2f}")
        mid = 0.5 * (lo + hi)
        pred = line + (fit["rate"] - tail["predicted_rate"]) * (c - mid)
        ax.plot(c, pred, "--", color=col, label=f"2K/ζ* = {tail['predicted_rate']:.2f}")
        ax.axvspan(lo, hi, color=col, alpha=0.08)
        maxwell = tail["maxwell"]
        ax.plot(data["maxwell_speed"], data["maxwell_log_density"], "-", color="0.3",
                label="Maxwell model (γ = 0)")
        at = maxwell["speed"]
        ax.plot(c, math.log(maxwell["density"]) - maxwell["exponent"] * np.log(c / at), ":",
                color="0.3", label=f"c^(−{maxwell['exponent']:.2f}); F_M/F_HS = "
                                   f"{maxwell['density_ratio']:.0f} at {at:.2f}")
    if drawn:
        ax.set(xlabel="|c| (unit variance per component)", ylabel="ln F",
               title="tail of the cooling state (shaded: the fit's window)")
        low, high = ax.get_ylim()
        ax.set_ylim(low, high + 0.5 * (high - low))  # room for the legend above the curves
        ax.legend(loc="upper right")
    return drawn
