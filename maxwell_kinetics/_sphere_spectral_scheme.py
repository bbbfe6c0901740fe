"""The numerics of :mod:`maxwell_kinetics.sphere_spectral`: the quadrature rules and the Fourier
multipliers of the collision operator (host side, NumPy and SciPy, computed once per grid and
kernel), and the jitted collision operator, conservative projection and dilation (JAX).

Conventions.  The grid holds N points c_j = −L + j h, h = 2L/N, along each of the d axes; the
wavenumbers are k = 2π·fftfreq(N, h) (the last axis of a real FFT: rfftfreq), the Nyquist
mode is set to zero.  A collision kernel B(g, n) = C |g|^{γ−a} |g·n|^a (:class:`KernelForm`)
is truncated to the cylinder |g·n| ≤ R, |g − (g·n) n| ≤ R about each n.  With g = s n + g⊥,
the gain is (the module docstring of :mod:`maxwell_kinetics.sphere_spectral` derives it)

    Q⁺(c) = 2 ∫_{S^{d−1}} dn ∫_0^R ds  F(c + β s n) · [IFFT(F̂ e^{−i(1−β) s k·n} Φ(s, |k⊥|))](c),

Φ(s, p) = ∫_{|g⊥|≤R} B(s, |g⊥|) e^{−i g⊥·k⊥} dg⊥, k⊥ = k − (k·n) n, β = (1 + α)/2; the sphere
by a Lebedev rule (d = 3) or equally spaced angles (d = 2), s by Gauss–Legendre on [0, R].  The
loss is F · IFFT(F̂ L(|k|)), L the Fourier transform of the truncated rate W(|g|) =
∫ dn B(g, n) 1[g in the cylinder about n], computed by a radial quadrature
(:func:`loss_multiplier`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["KernelForm", "Tables", "sphere_rule", "radial_rule", "loss_multiplier",
           "cross_multiplier", "build_tables", "collision", "project", "dilation",
           "scaled_rhs", "moment_basis", "sponge"]


@dataclass(frozen=True)
class KernelForm:
    """A collision kernel B(g, n) = C |g|^{γ−a} |g·n|^a (m = 1, n over the whole unit sphere).

    Attributes
    ----------
    constant : float
        C.
    exponent : float
        γ ∈ [0, 1]: B is homogeneous of degree γ in g.
    angular : int
        a (1: hard spheres' |g·n|; d − 2: the isotropic scattering of variable hard spheres).
    """

    constant: float
    exponent: float
    angular: int

    def separable(self) -> bool:
        """Whether Φ(s, p) = C |s|^a Ψ(p) (γ = a): then the kernel does not depend on |g⊥|.

        Returns
        -------
        bool
        """
        return self.exponent == self.angular


def sphere_rule(dimension: int, order: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes and weights on the unit sphere S^{d−1}: a Lebedev rule of degree ``order``
    (:func:`scipy.integrate.lebedev_rule`, d = 3) or ``order`` equally spaced angles (d = 2);
    the weights sum to the sphere's area (4π, 2π).

    Parameters
    ----------
    dimension : int
        d, 2 or 3.
    order : int
        The Lebedev degree (d = 3) or the number of angles (d = 2).

    Returns
    -------
    nodes, weights : numpy.ndarray
        Shapes (M, d) and (M,).
    """
    if dimension == 2:
        theta = 2.0 * math.pi * (np.arange(order) + 0.5) / order
        return np.stack([np.cos(theta), np.sin(theta)], axis=1), np.full(order, 2 * math.pi / order)
    from scipy.integrate import lebedev_rule

    x, w = lebedev_rule(order)
    return np.ascontiguousarray(x.T), np.asarray(w)


def radial_rule(cutoff: float, nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights of s ∈ [0, R].

    Parameters
    ----------
    cutoff : float
        R.
    nodes : int
        The number of nodes.

    Returns
    -------
    s, weights : numpy.ndarray
        Shapes (nodes,).
    """
    x, w = np.polynomial.legendre.leggauss(nodes)
    return cutoff * (x + 1.0) / 2.0, w * cutoff / 2.0


def _window(r: np.ndarray, form: KernelForm, dimension: int, cutoff: float) -> np.ndarray:
    """W(r) = ∫ dn B(g, n) over the n whose cylinder holds g, |g| = r ∈ [R, √2 R]: C r^γ times
    the integral of |μ|^a over R/r ≥ |μ| ≥ √(1 − R²/r²), μ = ĝ·n."""
    hi = np.clip(cutoff / r, 0.0, 1.0)
    lo = np.sqrt(np.clip(1.0 - hi * hi, 0.0, 1.0))
    a = form.angular
    if dimension == 3:
        measure = 4.0 * math.pi * (hi ** (a + 1) - lo ** (a + 1)) / (a + 1)
    elif a == 1:  # d = 2: 4 ∫ cos θ dθ over cos θ ∈ [lo, hi]
        measure = 4.0 * (np.sqrt(1.0 - lo * lo) - np.sqrt(1.0 - hi * hi))
    else:
        measure = 4.0 * (np.arccos(lo) - np.arccos(hi))
    return form.constant * r ** form.exponent * np.clip(measure, 0.0, None)


def _full_rate(form: KernelForm, dimension: int) -> float:
    """∫ dn C |ĝ·n|^a over the whole sphere: the rate of a pair at |g| = 1."""
    a = form.angular
    if dimension == 3:
        return form.constant * 4.0 * math.pi / (a + 1)
    return form.constant * (4.0 if a == 1 else 2.0 * math.pi)


def loss_multiplier(q: np.ndarray, form: KernelForm, dimension: int, cutoff: float,
                    nodes: int = 512) -> np.ndarray:
    """L(q) = ∫ W(|g|) e^{−i k·g} dg at |k| = q, W the rate of the truncated kernel (full for
    |g| ≤ R, the cylinders' share up to √2 R, 0 beyond): 4π ∫ W r² sin(qr)/(qr) dr (d = 3),
    2π ∫ W r J₀(qr) dr (d = 2), by Gauss–Legendre on [0, R] (in u, r = R u², which smooths
    r^γ at 0) and on [R, √2 R].

    Parameters
    ----------
    q : numpy.ndarray
        Wavenumbers |k| ≥ 0.
    form : KernelForm
        The kernel.
    dimension : int
        d.
    cutoff : float
        R.
    nodes : int, optional
        Nodes of each of the two Gauss–Legendre rules.

    Returns
    -------
    numpy.ndarray
        L(q), of the shape of ``q``.
    """
    from scipy.special import j0

    x, w = np.polynomial.legendre.leggauss(nodes)
    u = (x + 1.0) / 2.0
    r_in, w_in = cutoff * u * u, w * cutoff * u  # dr = 2 R u du, du = dx/2
    r_out = cutoff * (1.0 + (math.sqrt(2.0) - 1.0) * u)
    w_out = w * cutoff * (math.sqrt(2.0) - 1.0) / 2.0
    r = np.concatenate([r_in, r_out])
    weight = np.concatenate([w_in * _full_rate(form, dimension) * r_in ** form.exponent,
                             w_out * _window(r_out, form, dimension, cutoff)])
    qr = np.asarray(q, dtype=float).reshape(-1)[:, None] * r[None, :]
    if dimension == 3:
        kernel = 4.0 * math.pi * r * r * np.sinc(qr / math.pi)
    else:
        kernel = 2.0 * math.pi * r * j0(qr)
    return (kernel @ weight).reshape(np.shape(q))


def cross_multiplier(s: np.ndarray, p: np.ndarray, form: KernelForm, dimension: int,
                     cutoff: float, nodes: int = 600) -> np.ndarray:
    """Φ(s, p) = ∫_{|g⊥| ≤ R} B(s, |g⊥|) e^{−i g⊥·k⊥} dg⊥ at |k⊥| = p, for s ∈ (0, R]:
    C s^a · 2π ∫₀^R ρ J₀(ρp) (s² + ρ²)^e dρ (d = 3) or C s^a · 2 ∫₀^R cos(ρp) (s² + ρ²)^e dρ
    (d = 2), e = (γ − a)/2; in closed form when e = 0 (2πR J₁(Rp)/p, 2 sin(Rp)/p), otherwise
    by Gauss–Legendre in u, ρ = s sinh u (smooth at ρ ~ s).

    Parameters
    ----------
    s : numpy.ndarray
        Shape (S,), the s nodes (> 0).
    p : numpy.ndarray
        The |k⊥| ≥ 0, any shape.
    form : KernelForm
        The kernel.
    dimension : int
        d.
    cutoff : float
        R.
    nodes : int, optional
        Gauss–Legendre nodes in u (e ≠ 0).

    Returns
    -------
    numpy.ndarray
        Shape (S,) + p.shape (e ≠ 0), or p.shape: Ψ(p) alone, without C s^a (e = 0).
    """
    from scipy.special import j0, j1

    p = np.asarray(p, dtype=float)
    e = (form.exponent - form.angular) / 2.0
    if e == 0.0:
        small = p * cutoff < 1e-8
        safe = np.where(small, 1.0, p)
        if dimension == 3:
            return np.where(small, math.pi * cutoff**2,
                            2 * math.pi * cutoff * j1(cutoff * safe) / safe)
        return np.where(small, 2.0 * cutoff, 2.0 * np.sin(cutoff * safe) / safe)
    x, w = np.polynomial.legendre.leggauss(nodes)
    out = np.empty((len(s),) + p.shape)
    flat = p.reshape(-1)
    for j, sj in enumerate(np.asarray(s, dtype=float)):
        top = math.asinh(cutoff / sj)
        u = top * (x + 1.0) / 2.0
        wu = w * top / 2.0
        rho = sj * np.sinh(u)
        jac = sj * np.cosh(u) * (sj * np.cosh(u)) ** (2.0 * e)  # dρ/du (s² + ρ²)^e
        if dimension == 3:
            vals = 2.0 * math.pi * j0(flat[:, None] * rho[None, :]) @ (wu * rho * jac)
        else:
            vals = 2.0 * np.cos(flat[:, None] * rho[None, :]) @ (wu * jac)
        out[j] = (form.constant * sj ** form.angular * vals).reshape(p.shape)
    return out


@dataclass(frozen=True)
class Tables:
    """The host-side data of one (grid, kernel, restitution): what :func:`collision` reads.

    Attributes
    ----------
    dimension, points : int
        d and N.
    half_width, cutoff, beta : float
        L, R and β = (1 + α)/2.
    c : numpy.ndarray
        The nodes along one axis, shape (N,).
    axes_k : tuple of numpy.ndarray
        The wavenumbers of each axis (the last one of a real FFT), Nyquist set to 0.
    mask : numpy.ndarray
        1, and 0 on the Nyquist modes, in the real-FFT layout.
    directions, weights : numpy.ndarray
        The sphere nodes (M, d) and 2 × their weights (M,).
    s, s_weights : numpy.ndarray
        The s nodes (S,) and weights (S,), times C s^a for a separable kernel.
    cross : numpy.ndarray
        Φ: shape (M, K) (separable, Ψ(|k⊥|)) or (M, S, K), K the real-FFT layout.
    loss : numpy.ndarray
        L(|k|) in the real-FFT layout.
    sponge : numpy.ndarray
        κ(c) at the nodes, shape (N,)*d (:func:`sponge`).
    """

    dimension: int
    points: int
    half_width: float
    cutoff: float
    beta: float
    c: np.ndarray
    axes_k: tuple
    mask: np.ndarray
    directions: np.ndarray
    weights: np.ndarray
    s: np.ndarray
    s_weights: np.ndarray
    cross: np.ndarray
    loss: np.ndarray
    sponge: np.ndarray


def build_tables(dimension: int, points: int, half_width: float, cutoff: float,
                 sphere_order: int, radial_nodes: int, form: KernelForm,
                 transfer: float) -> Tables:
    """The :class:`Tables` of a grid and kernel (NumPy and SciPy; seconds at N = 32, d = 3).

    Parameters
    ----------
    dimension, points : int
        d and N.
    half_width, cutoff : float
        L and R.
    sphere_order, radial_nodes : int
        The sphere rule (:func:`sphere_rule`) and the number of s nodes.
    form : KernelForm
        The kernel.
    transfer : float
        β = (1 + α)/2, the kernel's transfer fraction
        (:attr:`particles.kernels.Kernel.p`).

    Returns
    -------
    Tables
    """
    d, n = dimension, points
    h = 2.0 * half_width / n
    k_full = 2.0 * math.pi * np.fft.fftfreq(n, h)
    k_half = 2.0 * math.pi * np.fft.rfftfreq(n, h)
    k_full[n // 2] = 0.0
    k_half[-1] = 0.0
    axes_k = tuple([k_full] * (d - 1) + [k_half])
    grids = np.meshgrid(*axes_k, indexing="ij")
    mask = np.ones(grids[0].shape)
    for axis in range(d):
        index = [slice(None)] * d
        index[axis] = n // 2 if axis < d - 1 else -1
        mask[tuple(index)] = 0.0
    k2 = sum(g * g for g in grids)
    directions, w_sphere = sphere_rule(d, sphere_order)
    s, w_s = radial_rule(cutoff, radial_nodes)
    kn = np.einsum("a...,ma->m...", np.stack(grids), directions)
    perp = np.sqrt(np.clip(k2[None] - kn * kn, 0.0, None))
    if form.separable():
        cross = cross_multiplier(s, perp, form, d, cutoff)
        w_s = w_s * form.constant * s ** form.angular
    else:
        p_top = float(np.sqrt(k2.max())) * 1.0001 + 1e-12
        p_grid = np.linspace(0.0, p_top, 2049)
        table = cross_multiplier(s, p_grid, form, d, cutoff)
        from scipy.interpolate import CubicSpline

        cross = np.stack([CubicSpline(p_grid, row)(perp) for row in table], axis=1)
    magnitude = np.sqrt(k2)
    unique, inverse = np.unique(np.round(magnitude, 12), return_inverse=True)
    loss = loss_multiplier(unique, form, d, cutoff)[inverse].reshape(magnitude.shape)
    c = -half_width + h * np.arange(n)
    return Tables(d, n, float(half_width), float(cutoff), float(transfer), c, axes_k,
                  mask, directions, 2.0 * w_sphere, s, w_s, cross * mask, loss * mask,
                  sponge(c, d, cutoff, half_width, _full_rate(form, d)
                         * cutoff ** form.exponent))


def sponge(c: np.ndarray, dimension: int, start: float, half_width: float,
           rate: float) -> np.ndarray:
    """The absorbing layer κ(c) = κ₀ Σ_a S((|c_a| − R)/(L − R)), S the smoothstep 3x² − 2x³
    clipped to [0, 1]: 0 inside the cube |c_a| ≤ R, κ₀ at the box's faces.  In the scaled
    equation the dilation carries F outward; at the box edge the periodic flows of both sides
    meet, and there the truncated kernel (relative speeds ≤ √2 R) no longer damps F: without
    the layer an instability grows there (measured: from τ ≈ 2 on, d = 2, N = 32, L = 10,
    R = 7).  Mass it removes (of order F at |c| ≥ R) is restored by the projection.

    Parameters
    ----------
    c : numpy.ndarray
        The nodes along one axis.
    dimension : int
        d.
    start, half_width : float
        R and L.
    rate : float
        κ₀.

    Returns
    -------
    numpy.ndarray
        Shape (N,)*d.
    """
    x = np.clip((np.abs(c) - start) / (half_width - start), 0.0, 1.0)
    ramp = x * x * (3.0 - 2.0 * x)
    grids = np.meshgrid(*([ramp] * dimension), indexing="ij")
    return rate * sum(grids)


def _phases(jnp, axes_k, direction, theta):
    """e^{i θ_j k·n} for every s node j, shape (S,) + K, as a product over the axes."""
    d = len(axes_k)
    out = None
    for axis, k in enumerate(axes_k):
        factor = jnp.exp(1j * theta[:, None] * (k * direction[axis])[None, :])
        shape = [theta.shape[0]] + [1] * d
        shape[axis + 1] = k.shape[0]
        factor = factor.reshape(shape)
        out = factor if out is None else out * factor
    return out


def collision(F, tables: dict, dimension: int, separable: bool):
    """Q⁺ and Q⁻ of F on the grid (JAX, traceable; ``tables`` the arrays of a :class:`Tables`
    as JAX arrays, by field name).

    Parameters
    ----------
    F : jax.Array
        F at the nodes, shape (N,)*d.
    tables : dict
        ``axes_k`` (tuple), ``mask``, ``directions``, ``weights``, ``s``, ``s_weights``,
        ``cross``, ``loss``, ``beta``.
    dimension : int
        d.
    separable : bool
        Whether ``cross`` is (M, K) (else (M, S, K)).

    Returns
    -------
    gain, loss : jax.Array
        Shape (N,)*d each.
    """
    import jax
    import jax.numpy as jnp

    shape = F.shape
    axes = tuple(range(1, dimension + 1))
    Fh = jnp.fft.rfftn(F) * tables["mask"]
    beta, s, ws = tables["beta"], tables["s"], tables["s_weights"]

    def one(total, x):
        direction, weight, cross = x
        forward = _phases(jnp, tables["axes_k"], direction, beta * s)
        backward = _phases(jnp, tables["axes_k"], direction, -(1.0 - beta) * s)
        a = jnp.fft.irfftn(Fh[None] * forward, s=shape, axes=axes)
        b = jnp.fft.irfftn((Fh * cross if separable else Fh[None] * cross) * backward,
                           s=shape, axes=axes)
        return total + weight * jnp.tensordot(ws, a * b, axes=1), None

    gain, _ = jax.lax.scan(one, jnp.zeros(shape, F.dtype),
                           (tables["directions"], tables["weights"], tables["cross"]))
    loss = F * jnp.fft.irfftn(Fh * tables["loss"], s=shape)
    return gain, loss


def moment_basis(c: np.ndarray, dimension: int) -> np.ndarray:
    """1, c_1, …, c_d, |c|² at the nodes, shape (d + 2,) + (N,)*d.

    Parameters
    ----------
    c : numpy.ndarray
        The nodes along one axis.
    dimension : int
        d.

    Returns
    -------
    numpy.ndarray
    """
    grids = np.meshgrid(*([c] * dimension), indexing="ij")
    return np.stack([np.ones_like(grids[0])] + list(grids) + [sum(g * g for g in grids)])


def project(X, F, basis, energy=None):
    """X − F (λ₀ + λ·c + λ_e |c|²) with the λ that make Σ X = 0 and Σ c X = 0 and Σ|c|² X =
    ``energy`` (the least-squares correction in the norm Σ X²/F): the conservative projection
    (JAX).

    Parameters
    ----------
    X, F : jax.Array
        Shape (N,)*d.
    basis : jax.Array
        :func:`moment_basis`.
    energy : jax.Array, optional
        The energy change to keep (default Σ|c|² X, X's own).

    Returns
    -------
    jax.Array
    """
    import jax.numpy as jnp

    d2 = basis.shape[0]
    flat = basis.reshape(d2, -1)
    gram = (flat * F.reshape(1, -1)) @ flat.T
    rhs = flat @ X.reshape(-1)
    rhs = rhs.at[-1].set(0.0 if energy is None else rhs[-1] - energy)
    lam = jnp.linalg.solve(gram, rhs)
    return X - F * (lam @ flat).reshape(F.shape)


def dilation(F, tables: dict, c_grids):
    """∇·(cF) = d F + Σ_a c_a ∂_a F, the derivatives spectral (JAX).  The advective form: c is
    not periodic, and the flux form's spectral derivative of the jump of c F at the box edge
    feeds an instability there; the product c_a ∂_a F has no jump to differentiate.

    Parameters
    ----------
    F : jax.Array
        Shape (N,)*d.
    tables : dict
        ``axes_k`` and ``mask`` (:func:`collision`).
    c_grids : sequence of jax.Array
        c_a at the nodes, one per axis.

    Returns
    -------
    jax.Array
    """
    import jax.numpy as jnp

    d = len(c_grids)
    Fh = jnp.fft.rfftn(F) * tables["mask"]
    total = d * F
    for axis, ca in enumerate(c_grids):
        shape = [1] * d
        shape[axis] = tables["axes_k"][axis].shape[0]
        derivative = jnp.fft.irfftn(1j * tables["axes_k"][axis].reshape(shape) * Fh, s=F.shape)
        total = total + ca * derivative
    return total


def scaled_rhs(F, tables: dict, dimension: int, separable: bool, basis, c_grids):
    """The right-hand side of the scaled equation ∂F/∂τ = Q̃ + σ′ D̃ (Q̃, D̃ the projected
    collision operator and dilation, :func:`project`) and σ′ = −Σ|c|² Q̃ / Σ|c|² D̃, which holds
    Σ|c|² F fixed (JAX).

    Parameters
    ----------
    F : jax.Array
        Shape (N,)*d.
    tables : dict
        As for :func:`collision`.
    dimension : int
        d.
    separable : bool
        As for :func:`collision`.
    basis : jax.Array
        :func:`moment_basis`.
    c_grids : sequence of jax.Array
        c_a at the nodes.

    Returns
    -------
    rhs, sigma : jax.Array
        dF/dτ (shape of F) and σ′ = d ln s/dτ (a scalar).
    """
    gain, loss = collision(F, tables, dimension, separable)
    q = project(gain - loss - tables["sponge"] * F, F, basis, (basis[-1] * (gain - loss)).sum())
    # ∫|c|² ∇·(cF) = −2 ∫|c|² F exactly: then d⟨|v|²⟩/dt is the collisions' Σ|c|² Q alone
    dil = project(dilation(F, tables, c_grids), F, basis, -2.0 * (basis[-1] * F).sum())
    sigma = -(basis[-1] * q).sum() / (basis[-1] * dil).sum()
    return q + sigma * dil, sigma
