"""Exact DSMC of inelastic hard spheres (d = 3) and disks (d = 2), and of any kernel of
:mod:`particles.sphere_kernels` (a rate of d-vectors and a ``direction_law``): the ``ulam`` model
with ``--kernel hard_spheres`` (or ``variable_hard_spheres``) and ``--dimension 2`` or ``3``.

Model.  N particles with velocities v_i ∈ ℝᵈ, in time t at density n: a given pair (i, j)
collides at rate (n/N) R(v_i, v_j), R the kernel's :meth:`~particles.kernels.Kernel.rate` (for
hard spheres R = β_d |v_i − v_j|, the integral ∫ dn |g·n| over the whole sphere), and then along
a direction drawn from the kernel's law given g (hard spheres: n of density |ĝ·n|/β_d), with the
kernel's post-collision map.  As N → ∞ the one-particle law obeys the kernel's Boltzmann equation
(for hard spheres ∂f/∂t = Q(f, f), :class:`~particles.sphere_kernels.HardSpheres`); particle i
collides at rate (n/N) Σ_j R(v_i, v_j) → n ν, and pair collisions happen ν/2 times per particle
and unit t.  ``collisions`` counts pair collisions.

Exact scheme (uniformisation and thinning).  Time is cut into blocks.  At a block's start the
centre c₀ (the mean velocity) and the radius ρ = (1 + ``RADIUS_MARGIN``) max_i |v_i − c₀| are
computed; while every velocity stays in the ball B(c₀, ρ), every pair has |v_i − v_j| ≤ 2ρ and
so R ≤ B = ``rate_bound(2ρ, d)``.  Candidates (uniform ordered pairs i ≠ j) come at the
uniformised rate n(N − 1)B/2 per unit t, each with a uniform mark U and its angular draws; a
candidate collides iff U·B < R(v_i, v_j) at its turn (acceptance R/B).  Unlike the 1D hull, the
ball does not stay invariant in d ≥ 2 (an elastic collision can speed a particle up: the two
outgoing velocities lie on the sphere of diameter [v, w], which pokes out of a ball that holds v
and w), so the scheme watches it: when an accepted collision puts a velocity outside B(c₀, ρ),
the candidates after it are dropped, the time of that candidate is drawn (given K candidates in
a window (a, b), the j-th of them in time order is at a + (b − a) Beta(j + 1, K − j)), and a new
block starts there with a new ball.  This is exact: the candidates' times are independent of
their pairs, marks and directions, the collision that leaves the ball is at a stopping time of
the candidate process, and after a stopping time a Poisson process starts afresh (strong Markov
property), so the dropped candidates may be replaced by new ones.  The same windows, sub-windows
and stop grid as the 1D DSMC (:func:`~particles.pair_schedule.thinned_windows`); recentring
(:func:`particles.ulam.recentre`) at the multiples of ``stop_step``.

Fast path and reference.  :class:`SphereDSMC` fires a window's candidates in rounds of
non-overlapping pairs (``particles.pair_schedule.fire_rounds_with_rows``), each candidate
when it is the earliest pending one of both its particles, so it sees the velocities of a
sequential loop; it fires the whole window, then, if a velocity left the ball, restores the
velocities the window touched and replays the candidates up to the earliest one (in time) that
left it.  :class:`SphereDSMCReference` loops over the candidates one at a time in time order and
stops at the first collision that leaves the ball.  Both draw the same numbers in the same order,
compute each collision with the same element-wise operations, and agree bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from .driver import EngineBase, initial_velocities
from .initial import get_law
from .kernels import Kernel, kernel_class, make_kernel
from .pair_schedule import (
    BLOCK_WINDOWS,
    draw_pairs_unchecked,
    fire_rounds_with_rows,
    power_of_two_near,
    thinned_windows,
)
from .sphere_kernels import DIRECTION_LAWS, HardSpheres
from .sphere_observables import sonine_coefficients
from .ulam import UlamState, recentre
from .ulam_kinematics import AngularDraws, collision_directions, draw_angles, scatter_rows
from .ulam_kinematics import subset_draws as _subset
from .validation import InvalidArgumentError, check_count, check_positive, check_restitution

__all__ = [
    "RADIUS_MARGIN",
    "TARGET_CANDIDATES",
    "SphereDSMC",
    "SphereDSMCReference",
    "draw_directions",
    "directions",
    "ulam_sphere_dsmc",
]

#: Relative margin of the ball's radius over the largest |v_i − c₀| at a block's start: the
#: bound costs (1 + margin) in acceptance, and a block ends early only when a velocity passes
#: it.
RADIUS_MARGIN = 0.05

#: Candidates per sub-window aimed at (at most N): large enough to amortise NumPy's call
#: overhead, small enough that a particle has few candidates per window (few rounds).
TARGET_CANDIDATES = 50_000


def draw_directions(rng: np.random.Generator, k: int, dimension: int, law: str) -> AngularDraws:
    """The angular variables of ``k`` candidates, drawn with their window.  ``"hard"`` (n of
    density ∝ |ĝ·n|): :func:`particles.ulam_kinematics.draw_angles` with ``angular="hard"``
    (d = 2: sin φ uniform on [−1, 1]; d = 3: a normal vector and η = (ĝ·n)² uniform).
    ``"isotropic"`` (σ uniform on the sphere): d = 3, normal vectors (normalised when fired);
    d = 2, (cos θ, sin θ) with θ = 2πu.

    Parameters
    ----------
    rng : numpy.random.Generator
        The generator.
    k : int
        The number of candidates.
    dimension : int
        d, 2 or 3.
    law : str
        ``"hard"`` or ``"isotropic"``.

    Returns
    -------
    particles.ulam_kinematics.AngularDraws
        ``z`` (k, d) for "isotropic"; that of :func:`~particles.ulam_kinematics.draw_angles`
        for "hard".
    """
    if law == "hard":
        return draw_angles(rng, k, dimension, "hard")
    if dimension == 3:
        return AngularDraws(rng.standard_normal((k, 3)))
    theta = rng.random(k) * (2.0 * math.pi)
    return AngularDraws(np.stack([np.cos(theta), np.sin(theta)], axis=1))


def directions(g: np.ndarray, draws: AngularDraws, law: str) -> np.ndarray:
    """The unit directions (m, d) of m collisions with relative velocities ``g`` (m, d) and
    their ``draws`` (:func:`draw_directions`), from element-wise +, −, ×, ÷ and √ only (the same
    bits for one collision as for many).  ``"hard"``, d = 2: n = ĝ e^{iφ}, i.e.
    (ĝ_x c − ĝ_y s, ĝ_x s + ĝ_y c) with s = sin φ, c = √((1 − s)(1 + s)) (ĝ = x̂ where g = 0,
    a collision that changes nothing); d = 3:
    :func:`~particles.ulam_kinematics.collision_directions`.  ``"isotropic"``: z/|z| (d = 3), the
    drawn (cos θ, sin θ) (d = 2).

    Parameters
    ----------
    g : numpy.ndarray
        v_a − v_b, shape ``(m, d)``.
    draws : particles.ulam_kinematics.AngularDraws
        The draws of the m collisions.
    law : str
        ``"hard"`` or ``"isotropic"``.

    Returns
    -------
    numpy.ndarray
        Shape ``(m, d)``.
    """
    d = g.shape[1]
    if law == "isotropic":
        return collision_directions(g, draws, "uniform") if d == 3 else draws.z
    if d == 3:
        return collision_directions(g, draws, "hard")
    gx, gy = g[:, 0], g[:, 1]
    norm = np.sqrt(gx * gx + gy * gy)
    moving = norm > 0.0
    safe = np.where(moving, norm, 1.0)
    ux, uy = np.where(moving, gx / safe, 1.0), gy / safe
    s = draws.sine
    c = np.sqrt((1.0 - s) * (1.0 + s))
    return np.stack([ux * c - uy * s, ux * s + uy * c], axis=1)


def _distance2(v: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """|v − c₀|² per row, summed component by component."""
    x = v - centre
    out = x[:, 0] * x[:, 0]
    for c in range(1, x.shape[1]):
        out += x[:, c] * x[:, c]
    return out


def _ball(v: np.ndarray) -> tuple[np.ndarray, float]:
    """The centre c₀ (the mean) and radius (1 + margin) max |v_i − c₀| of a block."""
    centre = v.mean(axis=0)
    return centre, math.sqrt(float(_distance2(v, centre).max())) * (1.0 + RADIUS_MARGIN)


@dataclass
class _Window:
    """The candidates of one sub-window, row 0 the last in time, with the block's bound."""

    pairs: np.ndarray
    marks: np.ndarray
    draws: AngularDraws
    bound: float
    centre: np.ndarray
    radius2: float

    def subset(self, start: int) -> _Window:
        """The candidates of rows ``start``.. (those up to row ``start`` in time order)."""
        rows = np.arange(start, len(self.pairs))
        return _Window(np.ascontiguousarray(self.pairs[start:]), self.marks[start:],
                       _subset(self.draws, rows), self.bound, self.centre, self.radius2)


def _refuse_rate(rate: float, bound: float):
    raise InvalidArgumentError("rate", f"a pair's rate {rate!r}",
                               f"a kernel whose rate stays <= its bound {bound!r}")


@dataclass(frozen=True)
class SphereDSMC(EngineBase):
    """Exact DSMC (module docstring) of ``n`` ≥ 2 particles in ``dimension`` d = 2 or 3 with
    the kernel ``rate`` (default ``"hard_spheres"``) of restitution ``restitution``, at density
    ``density``, from the initial law ``initial`` (each Cartesian component drawn, centred and
    scaled to unit variance: T(0) = 1).  Time t; its state is :class:`particles.ulam.UlamState`
    (velocities (N, d)).  At each requested time it records the temperature and the Sonine
    coefficients a₂, a₃ (:func:`particles.sphere_observables.sonine_coefficients`).

    Parameters
    ----------
    n : int
        Number of particles N, 2 ≤ N ≤ 2³¹ − 1.
    restitution : float
        α ∈ [0, 1].
    initial : str, optional
        The initial law's name (default ``"gaussian"``; one with a sampler).
    dimension : int, optional
        2 or 3 (default 3).
    rate : str or particles.kernels.Kernel, optional
        A kernel with a ``direction_law`` (:data:`particles.sphere_kernels.DIRECTION_LAWS`),
        or its name (default ``"hard_spheres"``).
    density : float, optional
        n > 0 (default 1).

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``n``, ``restitution``, ``initial``, ``dimension`` (not one of the kernel's),
        ``rate`` (not a registered kernel, one of another restitution, or one without a
        direction law) or ``density``.
    """

    n: int
    restitution: float
    initial: str = "gaussian"
    dimension: int = 3
    rate: str | Kernel = HardSpheres.name
    density: float = 1.0
    name: ClassVar[str] = "ulam"
    #: The collision kernel that ``rate`` names or is.
    kernel: Kernel = field(init=False, repr=False)

    def __post_init__(self):
        object.__setattr__(self, "n", check_count(self.n, "n", 2))
        if self.n > 2**31 - 1:
            raise InvalidArgumentError("n", self.n, "an integer <= 2**31 - 1")
        object.__setattr__(self, "restitution", check_restitution(self.restitution))
        law = get_law(self.initial)
        if law.sampler is None:
            raise InvalidArgumentError("initial", law.name, "a law with a sampler")
        object.__setattr__(self, "initial", law.name)
        if isinstance(self.rate, Kernel):
            kernel = self.rate
            if kernel.restitution != self.restitution:
                raise InvalidArgumentError(
                    "rate", kernel, f"a kernel of the engine's restitution {self.restitution}")
        else:
            kernel = make_kernel(kernel_class(self.rate, "rate").name, self.restitution, "rate")
        if getattr(kernel, "direction_law", None) not in DIRECTION_LAWS:
            raise InvalidArgumentError("rate", kernel.name, "a kernel with a direction law "
                                       f"({', '.join(DIRECTION_LAWS)}) in d = 2, 3")
        if isinstance(self.dimension, bool) or self.dimension not in kernel.dimensions:
            raise InvalidArgumentError("dimension", self.dimension, f"one of "
                                       f"{kernel.dimensions} for the kernel {kernel.name!r}")
        object.__setattr__(self, "dimension", int(self.dimension))
        object.__setattr__(self, "rate", kernel.name)
        object.__setattr__(self, "kernel", kernel)
        object.__setattr__(self, "density", check_positive(self.density, "density"))

    @property
    def time_name(self) -> str:
        """The kernel's time, ``"t"``."""
        return self.kernel.time_name

    @property
    def stop_step(self) -> float:
        """The stop grid (recentring, checkpoints, progress): the power of two nearest 1/(2n)
        in t (about 3.5 pair collisions per particle for hard spheres at T = 1 in d = 3, fewer
        as the gas cools)."""
        return power_of_two_near(0.5 / self.density)

    def to_dict(self) -> dict:
        """JSON-able parameters, recorded with every result (they name its checkpoints).

        Returns
        -------
        dict
            ``n``, ``restitution``, ``initial``, ``dimension``, ``rate``, ``density``, the
            scheme's constants and the kernel's parameters that differ from their defaults.
        """
        out = {"n": self.n, "restitution": self.restitution, "initial": self.initial,
               "dimension": self.dimension, "rate": self.rate, "density": self.density,
               "target_events": min(TARGET_CANDIDATES, self.n), "block_windows": BLOCK_WINDOWS,
               "radius_margin": RADIUS_MARGIN}
        for parameter in self.kernel.parameters:
            value = getattr(self.kernel, parameter.name)
            if value != parameter.default:
                out[parameter.name] = value
        return out

    def initial_state(self, rng: np.random.Generator) -> UlamState:
        """The state at t = 0: each of the d components of the velocities drawn by
        :func:`particles.driver.initial_velocities` (T = 1).

        Parameters
        ----------
        rng : numpy.random.Generator
            The generator.

        Returns
        -------
        particles.UlamState
        """
        columns = [initial_velocities(self.initial, self.n, rng) for _ in range(self.dimension)]
        return UlamState(0.0, np.stack(columns, axis=1), 0)

    def rebuild_state(self, arrays) -> UlamState:
        """A checkpointed state (:meth:`particles.UlamState.from_arrays` with this N and d).

        Parameters
        ----------
        arrays : mapping
            The arrays of :meth:`particles.UlamState.to_arrays`.

        Returns
        -------
        particles.UlamState

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``checkpoint``, from :meth:`particles.UlamState.from_arrays`.
        """
        return UlamState.from_arrays(arrays, self.n, self.dimension)

    def observe(self, state) -> dict[str, float]:
        """The temperature and Sonine coefficients at a requested time.

        Parameters
        ----------
        state : particles.UlamState
            The state.

        Returns
        -------
        dict of str to float
            ``temperature``, ``a2``, ``a3``.
        """
        return sonine_coefficients(state.velocities)

    def memory_per_particle(self) -> float:
        """Working bytes per particle: 96 per velocity component.

        Returns
        -------
        float
        """
        return 96.0 * self.dimension

    def expected_events(self, t_max: float, n_times: int) -> tuple[float, str]:
        """An upper bound on the candidates to t = ``t_max``: n(N − 1)B t/2 with B the rate
        bound at spread 12√d (six standard deviations of a unit-temperature speed, twice); the
        real count is far smaller as the gas cools.

        Parameters
        ----------
        t_max : float
            The last requested time.
        n_times : int
            The number of requested times (unused).

        Returns
        -------
        tuple of (float, str)
            ``(count, "candidates")``.
        """
        bound = self._bound(6.0 * math.sqrt(self.dimension))
        return 0.5 * self.density * (self.n - 1) * bound * t_max, "candidates"

    def _bound(self, radius: float) -> float:
        """The kernel's rate bound at spread 2ρ in this d, refused unless finite and ≥ 0."""
        spread = 2.0 * radius * (1.0 + 1e-9)  # covers the round-off of |v_i − v_j| ≤ 2ρ
        bound = self.kernel.rate_bound(spread, self.dimension)
        if not 0.0 <= bound < math.inf:
            raise InvalidArgumentError("rate", self.kernel, f"a kernel whose rate_bound is a "
                                       f"finite number >= 0 (got {bound!r} at {spread!r})")
        return bound

    def advance(self, state: UlamState, until: float, rng: np.random.Generator) -> UlamState:
        """Exact dynamics from ``state.time`` to ``until`` (block by block).

        Parameters
        ----------
        state : particles.UlamState
            The state (not modified).
        until : float
            The time t to reach, ≥ ``state.time``.
        rng : numpy.random.Generator
            The run's generator.

        Returns
        -------
        particles.UlamState
            The state at ``until``.

        Raises
        ------
        particles.InvalidArgumentError
            Naming ``until`` if it is before the state's time.
        """
        if not until >= state.time:
            raise InvalidArgumentError("until", until, f"a time >= {state.time}")
        v = np.array(state.velocities, dtype=float, order="C", copy=True)
        collisions = int(state.collisions)
        s, target = float(state.time), float(until)
        half_rate = 0.5 * self.density * (self.n - 1)
        law = self.kernel.direction_law
        while s < target:
            centre, radius = _ball(v)
            bound = self._bound(radius)
            windows = thinned_windows(s, target, half_rate * bound, self.stop_step,
                                      min(TARGET_CANDIDATES, self.n))
            end = windows[-1][1]
            for a, b in windows:
                k = int(rng.poisson(half_rate * bound * (b - a))) if bound > 0.0 else 0
                if not k:
                    continue
                pairs = draw_pairs_unchecked(rng, self.n, k)  # row 0: the last candidate
                marks = rng.random(k)
                draws = draw_directions(rng, k, self.dimension, law)
                window = _Window(pairs, marks, draws, bound, centre, radius * radius)
                accepted, row = self._fire(v, window)
                collisions += accepted
                if row is not None:  # candidate `row` left the ball: a new block at its time
                    j = k - 1 - row  # its place in time order
                    end = a + (b - a) * float(rng.beta(j + 1, k - j))
                    break
            s = end
            if s > 0.0 and s % self.stop_step == 0.0:
                recentre(v)
        return UlamState(target, v, collisions)

    def _fire(self, v: np.ndarray, window: _Window) -> tuple[int, int | None]:
        """Fire a window's candidates in rounds: (accepted, None), or, when a collision left
        the ball, (accepted up to the earliest such candidate, its row), with ``v`` as the
        sequential loop leaves it there."""
        touched = window.pairs.reshape(-1).astype(np.intp)
        saved = np.take(v, touched, axis=0)
        accepted, largest, left = self._fire_rounds(v, window)
        if left.size == 0:
            if largest > window.bound:  # no velocity left the ball, yet the bound failed
                _refuse_rate(largest, window.bound)
            return accepted, None
        row = int(left.max())  # the earliest in time of those that left the ball
        scatter_rows(v, touched, saved)  # the window's start, then a replay
        accepted, _, _ = self._fire_rounds(v, window.subset(row))
        return accepted, row

    def _fire_rounds(self, v, window: _Window):
        """Every candidate of ``window`` in rounds of disjoint pairs: (accepted, the largest
        rate seen, the rows of the collisions that put a velocity outside the ball)."""
        kernel, law = self.kernel, self.kernel.direction_law
        k = len(window.pairs)
        first = np.empty(self.n, dtype=np.int32)
        occurrence = np.arange(2 * k, dtype=np.int32)
        counts = {"accepted": 0, "largest": 0.0}
        left = []

        def collide(w, fired, rows):
            vv = np.take(w, fired, axis=0)
            va, vb = vv[0::2], vv[1::2]
            rate = kernel.rate(va, vb)
            if rate.size:
                counts["largest"] = max(counts["largest"], float(rate.max()))
            hit = np.flatnonzero(np.take(window.marks, rows) * window.bound < rate)
            if not hit.size:
                return
            hit_rows = np.take(rows, hit)
            a, b = np.take(va, hit, axis=0), np.take(vb, hit, axis=0)
            n = directions(a - b, _subset(window.draws, hit_rows), law)
            a, b = kernel.post_collision(a, b, direction=n)
            outside = (_distance2(a, window.centre) > window.radius2) | \
                (_distance2(b, window.centre) > window.radius2)
            if outside.any():
                left.append(hit_rows[outside])
            particles = np.empty(2 * hit.size, dtype=np.intp)
            particles[0::2] = np.take(fired[0::2], hit)
            particles[1::2] = np.take(fired[1::2], hit)
            values = np.empty((2 * hit.size, v.shape[1]))
            values[0::2] = a
            values[1::2] = b
            scatter_rows(w, particles, values)
            counts["accepted"] += int(hit.size)

        fire_rounds_with_rows(v, window.pairs, first, occurrence, collide)
        rows = np.concatenate(left) if left else np.empty(0, dtype=np.intp)
        return counts["accepted"], counts["largest"], rows


@dataclass(frozen=True)
class SphereDSMCReference(SphereDSMC):
    """Sequential reference of :class:`SphereDSMC` (for tests): the same blocks, windows and
    draws; the candidates applied one at a time in time order by a Python loop, which stops at
    the first collision that puts a velocity outside the block's ball.  Equal to the fast path
    bit for bit.

    Parameters
    ----------
    n, restitution, initial, dimension, rate, density
        As for :class:`SphereDSMC`.
    """

    name: ClassVar[str] = "ulam-reference"

    def _fire(self, v: np.ndarray, window: _Window) -> tuple[int, int | None]:
        kernel, law = self.kernel, self.kernel.direction_law
        accepted = 0
        for k in range(len(window.pairs) - 1, -1, -1):  # time order: the last row first
            i, j = int(window.pairs[k, 0]), int(window.pairs[k, 1])
            va, vb = v[i : i + 1].copy(), v[j : j + 1].copy()
            rate = float(kernel.rate(va, vb)[0])
            if rate > window.bound:
                _refuse_rate(rate, window.bound)
            if not window.marks[k] * window.bound < rate:
                continue
            n = directions(va - vb, _subset(window.draws, np.array([k])), law)
            va, vb = kernel.post_collision(va, vb, direction=n)
            v[i], v[j] = va[0], vb[0]
            accepted += 1
            if max(_distance2(va, window.centre)[0],
                   _distance2(vb, window.centre)[0]) > window.radius2:
                return accepted, k
        return accepted, None


def ulam_sphere_dsmc(n, restitution, initial, dimension, angular, driving, rate, density):
    """The engine of the ``ulam`` model for a kernel of d = 2, 3 with a direction law: a
    :class:`SphereDSMC` (the kernel draws its own collision direction, so ``angular`` stays at
    its default; no driving).

    Parameters
    ----------
    n, restitution, initial, dimension, rate, density
        As for :class:`SphereDSMC`.
    angular : str
        ``"uniform"``, the ``ulam`` model's default (any other value is refused).
    driving : float
        0.

    Returns
    -------
    SphereDSMC

    Raises
    ------
    particles.InvalidArgumentError
        Naming ``angular`` or ``driving`` when set, or what :class:`SphereDSMC` refuses.
    """
    name = rate.name if isinstance(rate, Kernel) else rate
    if angular != "uniform":
        raise InvalidArgumentError("angular", angular, f"no --angular with --kernel {name} "
                                   "(the kernel draws its own collision direction)")
    if driving != 0.0:
        raise InvalidArgumentError("driving", driving, f"0 with --kernel {name}")
    return SphereDSMC(n, restitution, initial, dimension=dimension, rate=rate, density=density)
