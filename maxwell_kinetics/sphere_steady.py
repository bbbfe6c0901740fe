"""The homogeneous cooling state as a steady solution of the scaled equation of
:mod:`maxwell_kinetics.sphere_spectral`, by Newton–Krylov.

The scaled equation ∂F/∂τ = Q̃(F) + σ′(F) D̃(F) (the projected collision operator and dilation
of :func:`maxwell_kinetics._sphere_spectral_scheme.scaled_rhs`) conserves mass, momentum and
Σ|c|²F exactly, so its Jacobian J is singular: every steady F belongs to a family of d + 2
(λF, its translates and dilates), and J's range misses the d + 2 conserved moments.  The
solve fixes the family by the moments m(F) = (mass, momentum, Σ|c|²F h^d) and zeroes

    G(F) = rhs(F) + Σ_i (m_i(F) − m_i*) φ_i,   m* = (1, 0, d),

φ_i the combinations of basis_i(c)·M(c) (basis_i = 1, c_a, |c|², M the unit Maxwellian) whose
moments are the unit vectors: since the moments of rhs vanish, m(G) = m(F) − m*, so G = 0 holds
exactly when rhs(F) = 0 and m(F) = m*, and the added term makes the Jacobian regular.  Each
Newton step solves J_G δ = −G by restarted GMRES (:func:`scipy.sparse.linalg.gmres`, relative
tolerance ``krylov_rtol``), each product J_G v one forward-mode JVP of the jitted G
(:func:`jax.jvp`, about two right-hand sides); a step that does not lower max|G| is halved
(at most four times).  Newton converges quadratically from a state near the cooling state,
such as a short march from the Maxwellian (:func:`maxwell_kinetics.sphere_spectral.cooling_state`
marches τ = 0.5 by default first).

The residual is the march's, max |dF/dτ| / max F, or the largest error of the d + 2 moments
if that is larger.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from particles.validation import InvalidArgumentError, check_count, check_positive

from . import _sphere_spectral_scheme as _scheme

__all__ = ["SteadyState", "SteadyStateError", "steady_state", "default_march_tau"]


class SteadyStateError(RuntimeError):
    """Newton–Krylov did not reach the requested residual (:func:`steady_state`); the message
    names the residual reached, the tolerance and the steps taken."""


@dataclass(frozen=True)
class SteadyState:
    """A steady F of the scaled equation (:func:`steady_state`).

    Attributes
    ----------
    F : numpy.ndarray
        F at the nodes, shape (N,)*d: mass 1, mean 0, Σ|c|²F h^d = d.
    sigma : float
        σ′ = d ln s/dτ at F (the cooling rate ζ* = −2σ′).
    residual : float
        max |dF/dτ| / max F at F (or the largest moment error, if larger).
    newton_steps, krylov_steps : int
        Newton steps and Jacobian-vector products (GMRES iterations) taken.
    history : numpy.ndarray
        The residual before each Newton step and at the end.
    """

    F: np.ndarray
    sigma: float
    residual: float
    newton_steps: int
    krylov_steps: int
    history: np.ndarray


_FUNCTIONS: dict = {}


def default_march_tau(restitution: float) -> float:
    """τ that :func:`maxwell_kinetics.sphere_spectral.cooling_state` marches before Newton by
    default: 1 for α ≤ 0.3, 0.5 above.

    From the Maxwellian both reach the same state (α = 0.1, 0.2, 0.5, 0.9, d = 2, 3, default
    grids: a₂ within 6e-10, a₃ within 1.1e-8).  Measured in d = 3 on the default grid: after
    τ = 0.5 Newton took 168–183 Jacobian products at α = 0.1 and 0.2 against 65–84 after τ = 1,
    while at α = 0.5 and 0.9 the shorter march made the whole solve 1.6–2 times faster.

    Parameters
    ----------
    restitution : float
        α.

    Returns
    -------
    float
        The τ to march.
    """
    return 1.0 if restitution <= 0.3 else 0.5


def _functions(dimension: int, separable: bool):
    """The jitted G and its JVP of one (d, separable) (compiled once per grid shape)."""
    key = (dimension, separable)
    if key not in _FUNCTIONS:
        import jax

        def residual(x, tables, basis, grids, modes, shifts, target, weight):
            F = x.reshape(basis.shape[1:])
            rhs, sigma = _scheme.scaled_rhs(F, tables, dimension, separable, basis, grids)
            moments = modes @ x * weight
            return rhs.reshape(-1) + (moments - target) @ shifts, rhs, sigma

        def product(x, v, *args):
            return jax.jvp(lambda y: residual(y, *args)[0], (x,), (v,))[1]

        _FUNCTIONS[key] = (jax.jit(residual), jax.jit(product))
    return _FUNCTIONS[key]


def steady_state(operator, start, *, tolerance: float = 1e-10, max_newton: int = 12,
                 krylov_rtol: float = 1e-4, restart: int = 60,
                 max_krylov: int = 2000) -> SteadyState:
    """The steady F of the scaled equation nearest ``start`` by Newton–Krylov (module
    docstring), on the operator's grid.

    Parameters
    ----------
    operator : maxwell_kinetics.sphere_spectral.SphereOperator
        The operator (grid, kernel, α).
    start : array_like
        The first iterate, shape (N,)*d (a short march from the Maxwellian: Newton converges
        from near the cooling state only).
    tolerance : float, default 1e-10
        The residual max |dF/dτ| / max F to reach (the moments are then exact to round-off).
    max_newton : int, default 12
        Most Newton steps.
    krylov_rtol : float, default 1e-4
        GMRES's relative tolerance in each step.
    restart : int, default 60
        GMRES's restart length.
    max_krylov : int, default 2000
        Most Jacobian-vector products in all.

    Returns
    -------
    SteadyState

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``start`` (wrong shape, not finite), ``tolerance``, ``max_newton``,
        ``krylov_rtol``, ``restart`` or ``max_krylov``.
    SteadyStateError
        When the residual is not below ``tolerance`` after ``max_newton`` steps or
        ``max_krylov`` products, or an iterate stops being finite.
    """
    import jax
    import jax.numpy as jnp
    from scipy.sparse.linalg import LinearOperator, gmres

    tolerance = check_positive(tolerance, "tolerance")
    max_newton = check_count(max_newton, "max_newton", 1)
    krylov_rtol = check_positive(krylov_rtol, "krylov_rtol")
    restart = check_count(restart, "restart", 1)
    max_krylov = check_count(max_krylov, "max_krylov", 1)
    d, shape = operator.dimension, operator.nodes.shape[:-1]
    F0 = np.asarray(start, dtype=float)
    if F0.shape != shape or not np.all(np.isfinite(F0)):
        raise InvalidArgumentError("start", f"an array of shape {F0.shape}",
                                   f"finite F on the grid, shape {shape}")
    residual_fn, product_fn = _functions(d, operator.form.separable())
    modes = np.asarray(operator.basis, dtype=float).reshape(d + 2, -1)
    maxwellian = np.exp(-0.5 * modes[-1]) / (2.0 * math.pi) ** (d / 2)
    phi = modes * maxwellian
    shifts = np.linalg.solve((phi @ modes.T) * operator.weight, phi)
    target = np.zeros(d + 2)
    target[0], target[-1] = 1.0, float(d)
    with jax.enable_x64(True):
        tables, basis, grids = operator.device_arguments()
        args = (tables, basis, grids, jnp.asarray(modes), jnp.asarray(shifts),
                jnp.asarray(target), jnp.asarray(operator.weight))

        def evaluate(x):  # the residual counts the moments' error too (λF is steady)
            g, rhs, sigma = residual_fn(jnp.asarray(x), *args)
            moments = np.max(np.abs(modes @ x * operator.weight - target))
            return (np.array(g), max(float(np.max(np.abs(rhs)) / np.max(x)), moments),
                    float(sigma))

        x = F0.reshape(-1).copy()
        g, residual, sigma = evaluate(x)
        history, steps, products = [residual], 0, 0
        while residual >= tolerance or not np.all(np.isfinite(g)):
            if steps >= max_newton or products >= max_krylov or not np.isfinite(residual):
                raise SteadyStateError(
                    f"Newton-Krylov did not reach the residual {tolerance:g}: {residual:.3g} "
                    f"after {steps} Newton steps and {products} Jacobian products "
                    f"(max_newton = {max_newton}, max_krylov = {max_krylov}); start nearer "
                    "the cooling state (a longer march)")
            count = [0]
            point = jnp.asarray(x)

            def matvec(v, point=point, count=count):
                count[0] += 1
                return np.array(product_fn(point, jnp.asarray(np.ravel(v)), *args))

            jacobian = LinearOperator((x.size, x.size), matvec=matvec, dtype=float)
            delta, _ = gmres(jacobian, -g, rtol=krylov_rtol, atol=0.0, restart=restart,
                             maxiter=max(1, (max_krylov - products) // restart + 1))
            products += count[0]
            size = float(np.max(np.abs(g)))
            for _ in range(5):  # halve a step that does not lower max|G|
                trial = x + delta
                g_new, res_new, sig_new = evaluate(trial)
                if np.all(np.isfinite(g_new)) and np.max(np.abs(g_new)) < size:
                    break
                delta = 0.5 * delta
            x, g, residual, sigma, steps = trial, g_new, res_new, sig_new, steps + 1
            history.append(residual)
    return SteadyState(x.reshape(shape), sigma, residual, steps, products, np.array(history))
