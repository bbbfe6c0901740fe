"""Time-dependent solver of the rescaled pseudo-Maxwell equation in Fourier space.

Equation (SPEC §2).  With P̂(k, τ) = ∫ e^{ikv} P(v, τ) dv (τ = collisions per particle) and the
rescaled characteristic function G(q, τ) = P̂(q / v0(τ), τ), v0² = ⟨v²⟩ = e^{−2λτ} for unit
initial variance,

    ∂τ G = λ q ∂q G − G + G(p q) G((1 − p) q),        p = (1 + r)/2,  λ = p(1 − p),

for q ≥ 0; G(−q) = conj G(q).  G(0) = 1 and G''(0) = −1 are conserved, and every solution with
finite variance tends to the scaling solution f̂(q) = (1 + |q|) e^{−|q|}.

Method: semi-Lagrangian in s = ln q.  In s the transport term λ ∂s G is a shift at constant
speed λ toward small q, so along the characteristics (the comoving points s + λ(τ − τ_w))
the equation is the unscaled one, ∂τ u = −u + u(s + ln p) u(s + ln(1 − p)), whose shifts are
fixed stencils on the uniform s grid (:mod:`maxwell_kinetics.grid`).  The solver integrates
that ODE with diffrax (Dopri8, adaptive PID steps, tolerances ``rtol``/``atol`` in diffrax's RMS
norm) over windows of length Δτ = m h / λ, after which the comoving grid has moved by exactly
m cells: the values are shifted by m (no interpolation), m points leave through the outflow end
q_min and m enter at the inflow end q_max.  Transport is therefore exact, the ODE is not stiff
(its rates are O(1), independent of h), and the only spatial error is the Lagrange
interpolation of order ``resolution.order`` in the gain term.  Outputs between window ends are
interpolated from the comoving grid back to the fixed grid with the same stencils.

Boundaries: below q_min the small-q expansion 1 − q²/2 − i m₃ q³/6 is imposed (exact to
O(q_min³) at all times; m₃ = ⟨x³⟩ is conserved); above q_max the free-streaming value
e^{−τ} φ(q e^{λτ}) of the initial law φ enters (zero for user laws that JAX cannot trace).

For r = 1 (elastic, λ = 0) collisions only exchange velocities: G(q, τ) = φ(q) for all τ.
"""

from __future__ import annotations

import dataclasses
import json
import math
import time
from dataclasses import dataclass, field

import numpy as np

from .exact import f_hat
from .grid import Resolution, get_resolution, lagrange_weights
from .initial import InitialLaw, get_law
from .model import MaxwellModel
from .validation import InvalidArgumentError, check_positive, check_times

__all__ = ["solve", "Solution", "SolverOptions"]


@dataclass(frozen=True)
class SolverOptions:
    """Time-integration settings.

    ``rtol``/``atol``: diffrax PID controller tolerances (RMS norm over the grid).
    ``window``: target length in τ of one semi-Lagrangian window (rounded so that the grid moves
    by a whole number of cells).
    """

    rtol: float = 1e-11
    atol: float = 1e-13
    window: float = 2.0
    max_steps_per_window: int = 100_000

    def __post_init__(self):
        check_positive(self.rtol, "rtol")
        check_positive(self.atol, "atol")
        check_positive(self.window, "window")


def _check_skewness_finite(law: InitialLaw) -> float:
    m3 = float(law.skewness)
    if not math.isfinite(m3):
        raise InvalidArgumentError("initial", law.name, "a law with a finite third moment")
    return m3


class _Stepper:
    """The jitted pieces of the semi-Lagrangian scheme for one (model, law, grid, options)."""

    def __init__(self, model: MaxwellModel, law: InitialLaw, grid: Resolution, opts: SolverOptions):
        import diffrax
        import jax
        import jax.numpy as jnp

        jax.config.update("jax_enable_x64", True)

        self.model, self.law, self.grid, self.opts = model, law, grid, opts
        p, lam, h, order, n = model.p, model.lam, grid.h, grid.order, grid.n
        self.complex = not law.symmetric
        self.m3 = _check_skewness_finite(law)
        # Cells moved per window and window length in τ.
        self.cells = max(1, round(opts.window * lam / h))
        self.dtau = self.cells * h / lam
        first_a, w_a = lagrange_weights(math.log(p) / h, order)
        first_b, w_b = lagrange_weights(math.log1p(-p) / h, order)
        # Ghost cells: left for the gain stencils, right for them and for mid-window output.
        self.n_left = max(0, -first_a, -first_b)
        self.n_right = max(first_a + order - 1, first_b + order - 1, 0) + self.cells + order
        nl, nr = self.n_left, self.n_right
        j_all = jnp.arange(-nl, n + nr, dtype=jnp.float64)
        s_min, m3, traceable = grid.s_min, self.m3, law.traceable
        characteristic = law.characteristic
        is_complex = self.complex

        def ghosts(tau, tau_w):
            """Extension values at comoving positions s_min + j h − λ (τ − τ_w)."""
            s = s_min + j_all * h - lam * (tau - tau_w)
            q = jnp.exp(s)
            small = 1.0 - 0.5 * q * q
            if is_complex:
                small = small - 1j * (m3 / 6.0) * q**3
            if traceable:
                k = jnp.minimum(q * jnp.exp(jnp.minimum(lam * tau, 690.0)), 1e30)
                free = jnp.exp(-tau) * characteristic(k, jnp)
                free = jnp.where(tau < 700.0, free, 0.0)
                if not is_complex:
                    free = jnp.real(free)
            else:
                free = jnp.zeros_like(small)
            return small[:nl], free[nl + n :]

        def to_c(y):
            return y[0] + 1j * y[1] if is_complex else y

        def from_c(g):
            return jnp.stack([g.real, g.imag]) if is_complex else g

        def extended(g, tau, tau_w):
            left, right = ghosts(tau, tau_w)
            return jnp.concatenate([left, g, right])

        def stencil(ext, first, w):
            start = nl + first
            return sum(w[k] * ext[start + k : start + k + n] for k in range(order))

        def rhs(tau, y, tau_w):
            g = to_c(y)
            ext = extended(g, tau, tau_w)
            return from_c(-g + stencil(ext, first_a, w_a) * stencil(ext, first_b, w_b))

        term = diffrax.ODETerm(rhs)
        solver = diffrax.Dopri8()
        controller = diffrax.PIDController(rtol=opts.rtol, atol=opts.atol)

        def integrate(y, tau_w, tau_end):
            sol = diffrax.diffeqsolve(
                term,
                solver,
                t0=tau_w,
                t1=tau_end,
                dt0=None,
                y0=y,
                args=tau_w,
                stepsize_controller=controller,
                saveat=diffrax.SaveAt(t1=True),
                max_steps=opts.max_steps_per_window,
            )
            return sol.ys[0]

        cells, dtau = self.cells, self.dtau

        def window(i, y):
            tau_w = i * dtau
            y1 = integrate(y, tau_w, tau_w + dtau)
            g1 = to_c(y1)
            _, right = ghosts(tau_w + dtau, tau_w)
            return from_c(jnp.concatenate([g1[cells:], right[:cells]]))

        def advance(y, i_start, count):
            return jax.lax.fori_loop(i_start, i_start + count, window, y)

        def output(y, i_window, tau):
            """G on the fixed grid at τ ≥ τ_w = i_window Δτ, from the state at τ_w."""
            tau_w = i_window * dtau
            y_tau = jax.lax.cond(
                tau > tau_w, lambda: integrate(y, tau_w, tau), lambda: y
            )
            ext = extended(to_c(y_tau), tau, tau_w)
            shift = lam * (tau - tau_w) / h  # fixed node j sits at comoving j + shift
            base = jnp.floor(shift)
            frac = shift - base
            nodes = jnp.arange(order) - (order // 2 - 1)
            out = 0.0
            for k in range(order):
                wk = 1.0
                for m in range(order):
                    if m != k:
                        wk = wk * (frac - nodes[m]) / (nodes[k] - nodes[m])
                start = (nl + base.astype(jnp.int32) + nodes[k]).astype(jnp.int32)
                out = out + wk * jax.lax.dynamic_slice(ext, (start,), (n,))
            return out

        self.advance = jax.jit(advance)
        self.output = jax.jit(output)
        q = grid.q
        g0 = law.phi(q)
        self.y0 = (
            jnp.asarray(np.stack([g0.real, g0.imag])) if self.complex else jnp.asarray(g0.real)
        )


def solve(
    restitution: float,
    initial="gaussian",
    tau=(1.0, 10.0, 100.0),
    resolution="default",
    *,
    options: SolverOptions | None = None,
    progress: bool = False,
) -> Solution:
    """Integrate the rescaled equation from G(q, 0) = φ(q) and save G at the requested τ.

    Parameters
    ----------
    restitution : r ∈ [0, 1].
    initial : a law name of :mod:`maxwell_kinetics.initial` or an ``InitialLaw``.
    tau : increasing, non-negative times (collisions per particle) at which G is saved.
    resolution : a name in :data:`maxwell_kinetics.grid.RESOLUTIONS` or a ``Resolution``.
    options : :class:`SolverOptions` (tolerances, window length).
    progress : show a tqdm progress bar over τ.
    """
    model = MaxwellModel(restitution)
    law = get_law(initial)
    taus = check_times(tau, "tau")
    grid = get_resolution(resolution)
    opts = options or SolverOptions()
    start = time.perf_counter()
    q = grid.q
    saved = np.empty((taus.size, grid.n), dtype=complex)
    if model.lam == 0.0:
        # Elastic collisions exchange velocities: P and hence G never change.
        saved[:] = law.phi(q)[None, :]
        return Solution(model.restitution, law.name, grid, taus, saved, law.skewness, opts,
                        time.perf_counter() - start)

    stepper = _Stepper(model, law, grid, opts)
    y = stepper.y0
    i_window = 0
    bar = None
    if progress:
        from tqdm.auto import tqdm

        bar = tqdm(total=float(taus[-1]), unit="τ", desc=f"solve r={model.restitution:g}",
                   bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} τ [{elapsed}<{remaining}]")
    chunk = max(1, int(math.ceil(taus[-1] / stepper.dtau / 200)))
    try:
        for k, target in enumerate(taus):
            n_full = int(math.floor(target / stepper.dtau + 1e-12)) - i_window
            while n_full > 0:
                step = min(chunk, n_full)
                y = stepper.advance(y, i_window, step)
                i_window += step
                n_full -= step
                if bar is not None:
                    bar.update(i_window * stepper.dtau - bar.n)
            g = np.asarray(stepper.output(y, i_window, float(target)))
            saved[k] = g[0] + 1j * g[1] if stepper.complex else g
            if not np.all(np.isfinite(saved[k])):
                raise FloatingPointError(f"solver produced non-finite G at tau={target}")
    finally:
        if bar is not None:
            bar.update(float(taus[-1]) - bar.n)
            bar.close()
    return Solution(model.restitution, law.name, grid, taus, saved, stepper.m3, opts,
                    time.perf_counter() - start)


@dataclass(frozen=True)
class Solution:
    """G(q, τ) on the grid at the saved τ, with evaluation and diagnostics.

    ``G[k, j]`` is G(q_j, tau[k]) for the grid q_j = e^{s_min + j h} (q ≥ 0; G(−q) = conj G(q)).
    """

    restitution: float
    initial: str
    resolution: Resolution
    tau: np.ndarray
    G: np.ndarray = field(repr=False)
    skewness: float = 0.0
    options: SolverOptions = field(default_factory=SolverOptions)
    seconds: float = 0.0

    @property
    def q(self) -> np.ndarray:
        return self.resolution.q

    @property
    def model(self) -> MaxwellModel:
        return MaxwellModel(self.restitution)

    def _index(self, tau_index: int) -> int:
        n = len(self.tau)
        if not -n <= tau_index < n:
            raise InvalidArgumentError("tau_index", tau_index, f"an index into {n} saved times")
        return tau_index % n

    def evaluate(self, q, tau_index: int = -1) -> np.ndarray:
        """G(q) at arbitrary real q, |q| ≤ q_max, by Lagrange interpolation in s = ln|q|.

        Accuracy O(h^order) inside the grid; below q_min the small-q expansion is used.
        """
        grid = self.resolution
        q = np.asarray(q, dtype=float)
        a = np.abs(q)
        if np.any(~np.isfinite(a)) or np.any(a > grid.q_max * (1 + 1e-12)):
            bad = q[~(np.isfinite(a) & (a <= grid.q_max * (1 + 1e-12)))].ravel()[:3]
            raise InvalidArgumentError(
                "q", bad.tolist(), f"|q| <= q_max={grid.q_max:.6g} (the grid's end)"
            )
        g = self.G[self._index(tau_index)]
        order = grid.order
        small = 1.0 - 0.5 * a**2 - 1j * (self.skewness / 6.0) * a**3
        out = np.array(small, dtype=complex)
        inside = a >= grid.q_min
        if np.any(inside):
            pos = (np.log(a[inside]) - grid.s_min) / grid.h
            base = np.floor(pos)
            first = np.clip(base - order // 2 + 1, 0, grid.n - order).astype(int)
            x = pos - first  # position within the stencil, in cells
            vals = np.zeros(x.shape, dtype=complex)
            for k in range(order):
                wk = np.ones_like(x)
                for m in range(order):
                    if m != k:
                        wk *= (x - m) / (k - m)
                vals += wk * g[first + k]
            out[inside] = vals
        return np.where(q < 0, np.conj(out), out)

    def sup_error(self, tau_index: int | None = None) -> np.ndarray | float:
        """sup over q ≥ 0 of |G(q, τ) − f̂(q)|: on the grid, refined 16× around the maximum."""
        if tau_index is None:
            return np.array([self.sup_error(k) for k in range(len(self.tau))])
        return self._weighted_sup(self._index(tau_index), 0.0, self.resolution.q_min)

    def fourier_distance(self, s: float, tau_index: int | None = None, q_low: float | None = None):
        """d_s(G, f̂) = sup_q |G − f̂| / q^s over q ∈ [q_low, q_max] (default q_low = q_min).

        Restricting the sup to q ≥ q_low gives a lower bound of the full metric, so it obeys the
        contraction bound too; small q_low makes the value sensitive to round-off (|ΔG| ~ 1e-16
        divided by q_low^s) and to the grid's cut at q_min (SPEC §2).
        """
        if tau_index is None:
            return np.array([self.fourier_distance(s, k, q_low) for k in range(len(self.tau))])
        q_low = self.resolution.q_min if q_low is None else q_low
        return self._weighted_sup(self._index(tau_index), s, q_low)

    def _weighted_sup(self, k: int, s: float, q_low: float) -> float:
        q = self.q
        keep = q >= q_low
        diff = np.abs(self.G[k][keep] - f_hat(q[keep])) / q[keep] ** s
        j = int(np.argmax(diff))
        qk = q[keep]
        lo, hi = qk[max(j - 1, 0)], qk[min(j + 1, qk.size - 1)]
        fine = np.exp(np.linspace(np.log(lo), np.log(hi), 33))
        fine_diff = np.abs(self.evaluate(fine, k) - f_hat(fine)) / fine**s
        return float(max(diff[j], fine_diff.max()))

    def density(self, x=None, tau_index: int = -1):
        """Velocity-space density P(x, τ) of x = v / v0 (inverse Fourier transform via pyfftw).

        See :mod:`maxwell_kinetics.velocity` for the transform conventions.
        """
        from .velocity import invert

        return invert(lambda q: self.evaluate(q, tau_index), q_max=self.resolution.q_max, x=x)

    # -- persistence --------------------------------------------------------------------
    def save(self, path) -> None:
        """Save to ``.npz`` (arrays plus a JSON header); reload with :meth:`Solution.load`."""
        meta = {
            "format": "maxwell_kinetics.Solution/1",
            "restitution": self.restitution,
            "initial": self.initial,
            "resolution": dataclasses.asdict(self.resolution),
            "skewness": self.skewness,
            "options": dataclasses.asdict(self.options),
            "seconds": self.seconds,
        }
        with open(path, "wb") as fh:
            np.savez(fh, meta=np.array(json.dumps(meta)), tau=self.tau, G=self.G)

    @classmethod
    def load(cls, path) -> Solution:
        try:
            with np.load(path, allow_pickle=False) as data:
                meta = json.loads(str(data["meta"]))
                tau, G = data["tau"], data["G"]
            if meta.get("format") != "maxwell_kinetics.Solution/1":
                raise ValueError(f"unknown format {meta.get('format')!r}")
            return cls(
                meta["restitution"],
                meta["initial"],
                Resolution(**meta["resolution"]),
                tau,
                G,
                meta["skewness"],
                SolverOptions(**meta["options"]),
                meta["seconds"],
            )
        except (OSError, KeyError, ValueError, TypeError) as exc:
            raise InvalidArgumentError("path", str(path), f"a saved Solution ({exc})") from exc
