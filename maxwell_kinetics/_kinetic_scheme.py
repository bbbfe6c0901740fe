"""The JAX part of the semi-Lagrangian scheme of :mod:`maxwell_kinetics.solver`.

The method, its boundaries and its conventions are described in the solver's module docstring;
this module holds its compiled pieces as module-level jitted functions over pytrees, so that
one compilation serves every restitution coefficient at a given resolution and law:

* :class:`Static` (hashable, the static argument): the grid, the initial law (its φ feeds the
  inflow, its m₃ the reference), whether G is complex, and the solver options.  A change of any
  of these compiles anew: one compile per (resolution, law family, options).
* :class:`Dynamic` (a NamedTuple of arrays, traced): everything that depends on r, i.e. p, λ,
  the window (its length Δτ in τ and the ``cells`` the grid moves by), the gain stencils (first
  node and Lagrange weights of the shifts ln p / h and ln(1 − p) / h), and the number of active
  state nodes.  They are computed on the host exactly as before (:func:`dynamic`), so the
  numbers are those of the former per-r closure up to round-off in the step-size norm.
* the output times, window indices and counts are traced arguments as well.

Shapes must not depend on r: the state always holds ``n_state = n + cells_max`` nodes
(cells_max: the cells of λ = 1/4, the largest λ), of which the first ``n + cells`` are active;
the others are held at zero, their time derivative is zero, and the error norm of the step-size
controller is the RMS over the active nodes only (what diffrax's RMS norm gives over the
unpadded state, so G is the same as without padding, to 3e-14).  Gain stencils read one
array [continuation w(q₀) e^{3h·j} for j < 0 (solver docstring, Boundaries) | state | inflow]
moved by the traced stencil offset (:func:`_stencil`).

Cost: the padded arrays and the dynamic offsets make a window ~1.3–1.5x the CPU time of a
scheme compiled for one r, in exchange for one compilation for every r; a
``lax.dynamic_slice`` in place of :func:`_stencil`'s moved copy is 4–6x slower.

The isotropic d-dimensional model (d = 2, 3; :func:`maxwell_kinetics.solver.solve` with
``dimension``) uses the same windows with transport speed Λ/2 = p(1 − p)⟨η⟩ and one pair of
gain stencils per Gauss–Jacobi node η_i (:meth:`.AngularLaw.quadrature`, :func:`_rhs_isotropic`),
with more nodes at larger q (:func:`angular_tiers`); d = 1 is the single node η = 1 and runs
the one-dimensional code unchanged.

Every call must run with float64 enabled (``jax.enable_x64(True)``): the solver does that
itself, without changing JAX's global configuration.

``TRACES`` counts the traces of the jitted functions (a Python side effect that runs only
when JAX traces, i.e. once per compilation): tests and ``benchmarks/solver.py sweep`` read it.
"""

from __future__ import annotations

import collections
import math
from dataclasses import dataclass
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from particles.initial import InitialLaw

from .angular import angular_law
from .angular_tiers import ANGULAR_RULES, tier_counts  # noqa: F401  (the rules' old home)
from .deviation import source_parts
from .grid import INFLOW_CUT, Resolution, lagrange_weights
from .model import MaxwellModel

#: Traces (= compilations) of the jitted function since import: {"step": n}.
TRACES: collections.Counter = collections.Counter()

@dataclass(frozen=True)
class Static:
    """The static (hashable) part of the scheme: one compilation per value."""

    grid: Resolution
    law: InitialLaw
    opts: object  # the solver's SolverOptions (tolerances, window)
    complex: bool
    m3: float
    dimension: int = 1
    angular: str = "uniform"
    nodes: int = 1  # η quadrature nodes of all tiers together (1 for d = 1)
    # (first state node, nodes) per angular tier, increasing first (angular_tiers); () for d = 1
    tiers: tuple[tuple[int, int], ...] = ()

    @property
    def parts(self) -> int:
        """1 for real G, 2 for complex G carried as (Re, Im) real arrays."""
        return 2 if self.complex else 1

    @property
    def cells_max(self) -> int:
        """Cells per window for the largest λ = 1/4 (r = 0): the padding of the state."""
        return max(1, round(self.opts.window * 0.25 / self.grid.h))

    @property
    def n_state(self) -> int:
        return self.grid.n + self.cells_max

    @property
    def out_order(self) -> int:
        """Points of the output interpolation (twice the stencil; solver docstring)."""
        return 2 * self.grid.order

    @property
    def n_right(self) -> int:
        """Inflow ghosts after the last active node: gain stencils reach at most order/2 past a
        node (their shifts are toward small q), a window moves by ≤ cells_max, and the output
        stencil reaches out_order/2 further."""
        return self.grid.order // 2 + self.cells_max + self.out_order

    @property
    def n_left(self) -> int:
        """Continuation nodes before node 0 in the array the gain stencils read."""
        return self.n_state + self.grid.order

    @property
    def n_source(self) -> int:
        """Length of the slice one gain stencil reads: n_state + order − 1."""
        return self.n_state + self.grid.order - 1


class Dynamic(NamedTuple):
    """The traced, r-dependent data of the scheme (see the module docstring)."""

    p: jax.Array
    lam: jax.Array
    dtau: jax.Array  # window length in τ
    cells: jax.Array  # int32: cells the comoving grid moves per window
    n_active: jax.Array  # int32: n + cells active state nodes
    first_a: jax.Array  # int32 (nodes,): first node of the stencils of ln(p √η) / h
    weights_a: jax.Array  # (nodes, order)
    first_b: jax.Array  # int32 (nodes,): the same for ln √(1 − (1 − (1−p)²) η) / h
    weights_b: jax.Array
    eta: jax.Array  # (nodes,) quadrature nodes η_i of all tiers (η ≡ 1 for d = 1)
    eta_weights: jax.Array  # (nodes,) their weights, summing to 1 in each tier
    eta_series: jax.Array  # (tiers, SERIES_TERMS + 1): Σ_i ω_i η_i^k / k! of each tier's rule


def window_cells(speed: float, grid: Resolution, opts) -> tuple[int, float]:
    """(cells, Δτ): at transport speed ``speed`` (λ in d = 1, p(1 − p)⟨η⟩ in general) the grid
    moves by ``cells`` nodes in a window of Δτ = cells h / speed."""
    cells = max(1, round(opts.window * speed / grid.h))
    return cells, cells * grid.h / speed


@dataclass(frozen=True)
class AngularTier:
    """The η rule (:meth:`.AngularLaw.quadrature`) of the state nodes j ≥ ``first`` (up to the
    next tier's first node)."""

    first: int
    eta: np.ndarray
    weights: np.ndarray


def angular_tiers(dimension: int, angular: str, nodes: int, grid: Resolution,
                  rule: str = "accurate") -> tuple[AngularTier, ...]:
    """The η quadrature of the gain per range of q: Gauss–Jacobi (:meth:`.AngularLaw.quadrature`)
    with min(max(⌈N_k ``nodes`` / 16⌉, 2), ``nodes``) nodes at the state nodes whose q at the
    window start is ≥ q_k, for (q_k, N_k) in :data:`ANGULAR_RULES` [``rule``] (N_k = None:
    ``nodes``).  "accurate", at ``nodes`` = 16: 2 nodes below q = 1e-6 (37 % of the state
    nodes), 16 up to q = 10 and 12 above: 10.7 nodes per state node on average instead of 16.
    "fast": the ladder 2, 3, 4, 6, 8, 12, 16, 12 nodes from q = 0, 1e-3, 1e-2, 0.05, 0.15,
    0.35, 0.6, 10 (4.76 per state node; the measurements below).  ``nodes`` scales every
    tier, so it stays the accuracy knob (32 doubles them all), but never below 2 nodes (unless
    ``nodes`` = 1): 2 nodes are exact for η³, so the q⁴ and q⁶ Taylor coefficients of G (C₂,
    C₃ of :mod:`maxwell_kinetics.scaling_tails`) follow their exact hierarchy at small q.
    d = 1: one tier, η ≡ 1.  A node moves to smaller q within a window, never to larger q, so
    the tier picked at the window start has at least the nodes its q needs.

    Why not fewer nodes at small q: at wavenumber q the gain integrand G(√(1 − (1 − q₁²)η) q)
    G(p √η q) varies with η on the scale ~1/q², so for G alone few nodes suffice at small q:
    measured (coarse grid, Gaussian start, G at τ = 30 and 300 against 32 Gauss–Jacobi nodes at
    every q; d = 2, 3, uniform and hard, r = 0, 0.5, 0.9) the ladder 2, 3, 4, 6, 8, 12, 16, 12
    nodes from q = 0, 1e-3, 1e-2, 0.05, 0.15, 0.35, 0.6, 10 (4.76 nodes per state node, 3.7–4x
    the CPU time of d = 1) differs by at most 1.0e-8 (d = 2 uniform, r = 0; 16 nodes at every
    q: 6.7e-9) and 5.4e-9 elsewhere.  But the non-analytic |q|^{2s*} term that
    :mod:`maxwell_kinetics.scaling_tails` fits on q ∈ [1e-4, 0.1] is a slowly relaxing
    (neutral) mode whose rate needs ⟨η^{s*}⟩ to ~1e-6 (Gauss–Jacobi: 16 nodes 4e-7, 4 nodes
    1e-4 for s ∈ [1.5, 5]): with that ladder the fitted s* moved by 5e-4 (tolerance 3e-4) and
    the resonant q⁴ ln q amplitude by 4e-3 relative; with 2 nodes below q = 1e-4, s* still
    failed; below 1e-6 it passes.  Errors at small q also grow with τ through the neutral modes
    (1 node below q = 0.01 gave 9.8e-7 at τ = 300, r = 0.5, d = 2 uniform).  A rule with few
    nodes that is exact for η^k, k ≤ 3, and accurate for η^s, s ∈ [2, 5], at small q would
    give the 4x; Gauss in u = η^{1/m} (m = 2, 3) reached 1.5e-6 with 5 nodes only for m = 2.

    Every tier's rule has the exact ⟨η⟩ (to round-off), so the transport speed p q₁ ⟨η⟩ is the
    same for all of them; :func:`transport_speed` takes the lowest tier's ⟨η⟩, the rule of
    q → 0 where G''(0) = −1 is decided.
    """
    law = angular_law(dimension, angular)
    if dimension == 1:
        return (AngularTier(0, *law.quadrature(1)),)
    return tuple(AngularTier(first, *law.quadrature(count))
                 for first, count in tier_counts(nodes, grid, rule))


def transport_speed(model: MaxwellModel, eta: np.ndarray, weights: np.ndarray) -> float:
    """p (1 − p) Σ ω_i η_i (= Λ/2 with the quadrature's own ⟨η⟩, so that the discrete
    equation keeps G''(0) = −1 exactly; λ for d = 1): :meth:`.MaxwellModel.transport_speed`."""
    return model.transport_speed(eta, weights)


def dynamic(model: MaxwellModel, grid: Resolution, opts, tiers=None) -> Dynamic:
    """The traced data for restitution ``model.restitution`` (λ > 0), computed on the host.

    ``tiers``: :func:`angular_tiers` (None: d = 1); their nodes are stored one after the other.
    Gain shifts per node: ln(p √η) and ln √(1 − (1 − (1 − p)²) η) (ln p and ln(1 − p) when
    η = 1, the d = 1 equation; computed there exactly as before, by log and log1p).
    """
    if tiers is None:
        tiers = (AngularTier(0, np.ones(1), np.ones(1)),)
    eta = np.concatenate([t.eta for t in tiers])
    weights = np.concatenate([t.weights for t in tiers])
    speed = transport_speed(model, tiers[0].eta, tiers[0].weights)
    cells, dtau = window_cells(speed, grid, opts)
    fa, wa, fb, wb = [], [], [], []
    for e in eta:
        shift_a, shift_b = model.gain_shifts(float(e))
        first, w = lagrange_weights(shift_a / grid.h, grid.order)
        fa.append(first)
        wa.append(w)
        first, w = lagrange_weights(shift_b / grid.h, grid.order)
        fb.append(first)
        wb.append(w)
    i32 = np.int32
    return Dynamic(
        p=jnp.asarray(model.p, jnp.float64),
        lam=jnp.asarray(speed, jnp.float64),
        dtau=jnp.asarray(dtau, jnp.float64),
        cells=jnp.asarray(i32(cells)),
        n_active=jnp.asarray(i32(grid.n + cells)),
        first_a=jnp.asarray(np.array(fa, dtype=i32)),
        weights_a=jnp.asarray(np.array(wa), jnp.float64),
        first_b=jnp.asarray(np.array(fb, dtype=i32)),
        weights_b=jnp.asarray(np.array(wb), jnp.float64),
        eta=jnp.asarray(eta, jnp.float64),
        eta_weights=jnp.asarray(weights, jnp.float64),
        eta_series=jnp.asarray(np.array([
            [float(t.weights @ t.eta**k) / math.factorial(k) for k in range(SERIES_TERMS + 1)]
            for t in tiers]), jnp.float64),
    )


# -- complex values as (parts, …) real arrays ------------------------------------------------
# XLA's complex128 arithmetic on the CPU was measured 10x slower (127 µs against 13 µs per
# right-hand side at the default resolution).


def _pair(st: Static, z):
    return jnp.stack([jnp.real(z), jnp.imag(z)]) if st.complex else jnp.real(z)[None]


def _mul(st: Static, x, y):
    if not st.complex:
        return x * y
    return jnp.stack([x[0] * y[0] - x[1] * y[1], x[0] * y[1] + x[1] * y[0]])


def _reference_pair(st: Static, q, gauss=None):
    gauss = jnp.exp(-0.5 * q * q) if gauss is None else gauss
    if not st.complex:
        return gauss[None]
    return jnp.stack([gauss, -(st.m3 / 6.0) * q**3 * gauss])


# -- the pieces of one window -----------------------------------------------------------------
# Time inside a window is local, t = τ − τ_w ∈ [0, Δτ] (solver docstring).


def _q_at(st: Static, dy: Dynamic, j, t):
    """q of comoving node j at local time t of a window."""
    return jnp.exp(st.grid.s_min + j * st.grid.h - dy.lam * t)


def _inflow(st: Static, dy: Dynamic, t, tau_w):
    """w at the n_right nodes after the active ones at τ = τ_w + t: e^{−τ} φ(q e^{λτ}) − g(q)."""
    j = (dy.n_active + jnp.arange(st.n_right, dtype=jnp.int32)).astype(jnp.float64)
    q = _q_at(st, dy, j, t)
    tau = tau_w + t
    if st.law.traceable:
        # e^{−τ} |φ| < 4e-18 for τ > 40: drop it, and never evaluate φ at the huge
        # k = q e^{λτ} of late times (trigonometric range reduction is slow there).
        k = q * jnp.exp(dy.lam * jnp.minimum(tau, INFLOW_CUT))
        free = jnp.where(tau < INFLOW_CUT, jnp.exp(-tau) * st.law.characteristic(k, jnp), 0.0)
    else:
        free = jnp.zeros_like(q)
    return _pair(st, free) - _reference_pair(st, q)


def _padded(st: Static, dy: Dynamic, w, t, tau_w):
    """[continuation | state | inflow ghosts]: node j (j ≥ −n_left) sits at index n_left + j.

    Left of node 0: w(q₀) e^{3h·j} (solver docstring, Boundaries).  The inflow overwrites the
    inactive state nodes from n_active on.
    """
    h = st.grid.h
    left = w[:, :1] * jnp.exp(3.0 * h * jnp.arange(-st.n_left, 0, dtype=jnp.float64))[None, :]
    base = jnp.concatenate([left, w, jnp.zeros((st.parts, st.n_right))], axis=1)
    start = (jnp.int32(0), jnp.int32(st.n_left) + dy.n_active)
    return jax.lax.dynamic_update_slice(base, _inflow(st, dy, t, tau_w), start)


def _stencil(st: Static, padded, first, weights):
    """Σ_k weights[k] · w[j + first + k] for every state node j.

    ``first`` is traced.  Written as a static slice of ``padded`` moved right by −first
    (≥ order/2 > 0: both gain shifts point to smaller q): a dynamic_slice feeding the stencil
    sum was measured 2–3x slower on the CPU.  For −first > n_left (1 − p < e^{−(n + order) h},
    r within ~1e-12 of 1) the move is clamped and the stencil reads the continuation at −n_left
    instead of further left, an error below w(q₀) e^{−3h·n_left} (< 1e-35 w(q₀)).
    """
    moved = jnp.concatenate([jnp.zeros((st.parts, st.n_left)), padded], axis=1)
    moved = jax.lax.dynamic_update_slice(moved, padded, (jnp.int32(0), -first))
    source = moved[:, st.n_left : st.n_left + st.n_source]
    ns = st.n_state
    return sum(weights[k] * source[:, k : k + ns] for k in range(st.grid.order))


def _active(st: Static, dy: Dynamic):
    return (jnp.arange(st.n_state, dtype=jnp.int32) < dy.n_active)[None, :]


def _rhs(st: Static, t, y, args):
    if st.dimension != 1:
        return _rhs_isotropic(st, t, y, args)
    tau_w, dy = args
    p, lam = dy.p, dy.lam
    w = y
    padded = _padded(st, dy, w, t, tau_w)
    j_grid = jnp.arange(st.n_state, dtype=jnp.float64)
    q_state = jnp.exp(st.grid.s_min + st.grid.h * j_grid)  # comoving nodes at the window start
    q = q_state * jnp.exp(-lam * t)
    w_p = _stencil(st, padded, dy.first_a[0], dy.weights_a[0])  # w(p q)
    w_1mp = _stencil(st, padded, dy.first_b[0], dy.weights_b[0])  # w((1 − p) q)
    # three exponentials per node: e^{−q²/2}, e^{−p²q²/2}, e^{−(1−p)²q²/2}
    # the gain's arguments p q and (1 − p) q, each written as before (the same traced graph)
    gauss_p = jnp.exp(-0.5 * (p * q) ** 2)
    gauss_1mp = jnp.exp(-0.5 * (MaxwellModel.complement_of(p) * q) ** 2)
    g_p = _reference_pair(st, p * q, gauss_p)
    g_1mp = _reference_pair(st, MaxwellModel.complement_of(p) * q, gauss_1mp)
    re, im = source_parts(q, lam, st.m3, jnp, jnp.exp(-0.5 * q * q), gauss_p * gauss_1mp)
    if st.complex:  # an asymmetric law may still have m₃ = 0: then Im S = 0
        im = jnp.zeros_like(re) if im is None else im
        dw = jnp.stack([re, im]) - w
    else:
        dw = re[None] - w
    dw = dw + _mul(st, g_p, w_1mp) + _mul(st, w_p, g_1mp) + _mul(st, w_p, w_1mp)
    # Inactive nodes (≥ n_active) evolve too, harmlessly: the stencils of active nodes read
    # the inflow there, and the error norm skips them.
    return dw


def _stencil_range(st: Static, padded, first, weights, j0: int, j1: int):
    """Σ_k weights[k] · w[j + first + k] for the state nodes j0 ≤ j < j1 (a dynamic slice
    of the j1 − j0 + order − 1 values read; clamped into ``padded`` like :func:`_stencil`)."""
    length = j1 - j0
    source = jax.lax.dynamic_slice(
        padded, (jnp.int32(0), jnp.int32(st.n_left + j0) + first),
        (st.parts, length + st.grid.order - 1))
    return sum(weights[k] * source[:, k : k + length] for k in range(st.grid.order))


#: Highest power of the series of e^x − 1 − x (truncation < 1e-17 relative for x < 1/2, as
#: :func:`maxwell_kinetics.deviation._expm1_minus_x`).
SERIES_TERMS = 16


def _series_terms(x_max: float) -> int:
    """Highest power K ≥ 2 with x_max^{K+1}/(K+1)! ≤ 1e-17 x_max²/2 (capped at SERIES_TERMS)."""
    k = 2
    while k < SERIES_TERMS and x_max ** (k - 1) / math.factorial(k + 1) > 0.5e-17:
        k += 1
    return k


def _rhs_isotropic(st: Static, t, y, args):
    """d ≥ 2, real G: ∂w = S − w + Σ_i ω_i [g(b_i q) w(a_i q) + w(b_i q) g(a_i q)
    + w(b_i q) w(a_i q)] with b_i = p √η_i, a_i = √(1 − (1 − (1−p)²) η_i) and the source
    S = e^{−q²/2} Σ_i ω_i (e^{x_i} − 1 − x_i), x_i = X η_i, X = p(1 − p) q².  The sums over i
    run over the nodes of the tier (:func:`angular_tiers`) each state node belongs to.

    The source without cancellation and without a series per node: for X < 1/2 it is
    e^{−q²/2} Σ_{k≥2} X^k ⟨η^k⟩/k! with the tier rule's moments ⟨η^k⟩ = Σ_i ω_i η_i^k (the
    same sum, reordered; truncated where the terms fall below 1e-17 relative for the largest X
    of the tier), else Σ_i ω_i e^{−(a_i² + b_i²) q²/2} − e^{−q²/2}(1 + X⟨η⟩) (≥ e^{X⟨η⟩} −
    1 − X⟨η⟩ ≥ 0.03 e^{−q²/2} there, by Jensen: no cancellation).
    """
    tau_w, dy = args
    p, lam = dy.p, dy.lam
    w = y
    padded = _padded(st, dy, w, t, tau_w)
    j_grid = jnp.arange(st.n_state, dtype=jnp.float64)
    q_all = jnp.exp(st.grid.s_min + st.grid.h * j_grid) * jnp.exp(-lam * t)
    pq = MaxwellModel.lam_of(p)
    one_minus_q2 = MaxwellModel.cross_fraction_of(p)
    pieces = []
    node = 0
    for k, (j0, count) in enumerate(st.tiers):
        j1 = st.tiers[k + 1][0] if k + 1 < len(st.tiers) else st.n_state
        q_top = math.exp(st.grid.s_min + st.grid.h * (j1 - 1))  # largest q of the tier
        x_top = 0.25 * q_top * q_top  # p(1 − p) ≤ 1/4
        q = q_all[j0:j1]
        qq = q * q
        gauss = jnp.exp(-0.5 * qq)
        big_x = pq * qq
        moments = dy.eta_series[k]
        terms = _series_terms(min(x_top, 0.5))
        series = moments[terms] + jnp.zeros_like(q)
        for power in range(terms - 1, 1, -1):
            series = series * big_x + moments[power]
        series = gauss * series * big_x * big_x
        # The tier's η nodes as one vectorised batch: a Python loop over them unrolled into
        # one operation chain per node, which took 2-3 times as long to trace and compile.
        nodes = slice(node, node + count)
        eta, omega = dy.eta[nodes], dy.eta_weights[nodes]
        stencil = jax.vmap(lambda first, weights, j0=j0, j1=j1:
                           _stencil_range(st, padded, first, weights, j0, j1))
        w_b = stencil(dy.first_a[nodes], dy.weights_a[nodes])  # (count, parts, j1 − j0)
        w_a = stencil(dy.first_b[nodes], dy.weights_b[nodes])
        g_b = jnp.exp(-0.5 * (p * p * eta)[:, None] * qq[None])  # (count, j1 − j0)
        g_a = jnp.exp(-0.5 * (1.0 - one_minus_q2 * eta)[:, None] * qq[None])
        # Σ ω_i e^{−(a_i² + b_i²) q²/2}, needed where X ≥ 1/2
        both = jnp.einsum("i,ij->j", omega, g_a * g_b) if x_top >= 0.5 else None
        gain = jnp.einsum("i,ipj->pj", omega,
                          g_b[:, None] * w_a + w_b * g_a[:, None] + w_b * w_a)
        node += count
        if x_top >= 0.5:
            source = jnp.where(big_x < 0.5, series,
                               both - gauss * (1.0 + big_x * moments[1]))
        else:
            source = series
        pieces.append(gain + source[None])
    return jnp.concatenate(pieces, axis=1) - w


def _integrate(st: Static, dy: Dynamic, y, tau_w, t_end):
    """Integrate the window that started at τ_w from local time 0 to ``t_end``.

    A failed integration (step limit, non-finite values) gives NaN, which the solver reports
    after the window (a non-finite G); a state that is already NaN is passed on without a
    solve.  diffrax's own ``throw=True`` check would be a host callback, and JAX's persistent
    compilation cache does not store executables with host callbacks.
    """
    return jax.lax.cond(
        jnp.all(jnp.isfinite(y)),
        lambda: _solve_window(st, dy, y, tau_w, t_end),
        lambda: jnp.full_like(y, jnp.nan),
    )


def _solve_window(st: Static, dy: Dynamic, y, tau_w, t_end):
    # Imported when the scheme is traced: a process that loads the compiled scheme from the
    # persistent cache (maxwell_kinetics.compile_cache) never imports them.
    import diffrax
    import optimistix as optx

    active_values = (dy.n_active * st.parts).astype(jnp.float64)

    active = _active(st, dy)

    def active_rms(x):
        # diffrax's default RMS norm, over the active nodes only.
        return optx.two_norm(jnp.where(active, x, 0.0)) / jnp.sqrt(active_values)

    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(lambda t, y, args: _rhs(st, t, y, args)),
        diffrax.Dopri8(),
        t0=0.0,
        t1=t_end,
        dt0=None,
        y0=y,
        args=(tau_w, dy),
        stepsize_controller=diffrax.PIDController(
            rtol=st.opts.rtol, atol=st.opts.atol, norm=active_rms
        ),
        saveat=diffrax.SaveAt(t1=True),
        max_steps=st.opts.max_steps_per_window,
        throw=False,
    )
    return jnp.where(sol.result == diffrax.RESULTS.successful, sol.ys[0], jnp.nan)


def _interpolate(st: Static, dy: Dynamic, y_tau, i_window, t):
    """w on the fixed grid (shape (parts, n)) from the state ``y_tau`` at local time ``t`` of
    window ``i_window``."""
    n, out_order, nl = st.grid.n, st.out_order, st.out_order
    ext = _padded(st, dy, y_tau, t, i_window * dy.dtau)[:, st.n_left - nl :]
    shift = dy.lam * t / st.grid.h  # fixed node j sits at comoving j + shift
    base = jnp.floor(shift)
    frac = shift - base
    nodes = np.arange(out_order) - (out_order // 2 - 1)
    out = jnp.zeros((st.parts, n))
    for k in range(out_order):
        wk = 1.0
        for m in range(out_order):
            if m != k:
                wk = wk * (frac - nodes[m]) / (nodes[k] - nodes[m])
        start = (nl + nodes[k] + base).astype(jnp.int32)
        out = out + wk * jax.lax.dynamic_slice(ext, (jnp.int32(0), start), (st.parts, n))
    return out


def step_unjitted(st: Static, dy: Dynamic, y, i_start, count, t):
    """``count`` windows from window ``i_start``, then w on the fixed grid at local time ``t``
    ≥ 0 of the window they end at: ``(state at the start of window i_start + count, w)``.

    A window from τ_w = i Δτ integrates to Δτ, then shifts the values by ``cells`` nodes; the
    last pass of the loop integrates window i_start + count to ``t`` only (nothing at ``t`` =
    0) and keeps the state.  One integration in the loop serves both, so each configuration
    compiles the integrator once: as two functions (stepping; output), each compiled its own
    copy, in about equal time.
    """
    TRACES["step"] += 1

    def window(j, carry):
        y, _ = carry
        tau_w = (i_start + j) * dy.dtau
        last = j == count
        t_end = jnp.where(last, t, dy.dtau)
        w1 = jax.lax.cond(t_end > 0.0, lambda: _integrate(st, dy, y, tau_w, t_end),
                          lambda: y)
        padded = _padded(st, dy, w1, dy.dtau, tau_w)  # nodes n_active.. now at n_active − cells
        moved = jax.lax.dynamic_slice(
            padded, (jnp.int32(0), jnp.int32(st.n_left) + dy.cells), (st.parts, st.n_state)
        )
        return jnp.where(last, y, jnp.where(_active(st, dy), moved, 0.0)), w1

    y, y_tau = jax.lax.fori_loop(0, count + 1, window, (y, y))
    return y, _interpolate(st, dy, y_tau, i_start + count, t)


#: ``step(static, dynamic, y, i_start, count, t)``: :func:`step_unjitted`, compiled.
step = jax.jit(step_unjitted, static_argnums=0)


def initial_state(st: Static, w0: np.ndarray):
    """The state array (parts, n_state) from w(q, 0) on the n + cells active nodes."""
    y = np.zeros((st.parts, st.n_state))
    if st.complex:
        y[0, : w0.size], y[1, : w0.size] = w0.real, w0.imag
    else:
        y[0, : w0.size] = w0.real
    return jnp.asarray(y)
