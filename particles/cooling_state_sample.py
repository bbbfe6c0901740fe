"""The scaled speeds of the homogeneous cooling state (HCS) sampled by the exact DSMC of
:mod:`particles.hard_sphere_dsmc`, far into the tail: a histogram of |c| over many snapshots,
the cooling rate ζ* and the Sonine coefficients.

Conventions.  c = (v − u)/√T is the scaled velocity of unit variance per component, with
T = ⟨|v − u|²⟩/d and u the mean velocity (as :mod:`particles.sphere_observables`); the density
F(c) is normalised to ∫F dc = 1, so a shell [a, b) of |c| holds the fraction F · V(a, b) of the
particles, V the shell's volume (π(b² − a²) in d = 2, 4π(b³ − a³)/3 in d = 3).  The scaled time
is τ = ∫ n T^{γ/2} dt (γ the kernel's homogeneity: 1 for hard spheres, τ = ∫n√T dt) and the
cooling rate ζ* = −d ln T/dτ.

Scheme.  The gas cools without end (T ∝ t⁻² for hard spheres), so a run in real time soon
holds velocities and times of absurd scales.  The sampler instead runs in chunks: each chunk
starts from the scaled velocities c (T = 1 exactly, u = 0), runs the exact DSMC for a fixed
time Δt, and the state at its end, scaled again, is the next snapshot.  This is exact: the
kernels of :mod:`particles.sphere_kernels` have rates homogeneous in g of degree γ, so the
N-particle process started from λv is the process started from v with velocities ×λ and time
÷λ^γ; rescaling changes the clock, not the sequence of scaled states.  Δt is fixed for the run
(``spacing`` collisions per particle at the initial state's collision frequency, n⟨R(v_i, v_j)⟩
over neighbouring pairs of the initial sample), so the snapshots are at equal τ-steps up to the
fluctuation of T within a chunk.  The first ``warmup`` chunks are not recorded.

The cooling rate of one chunk is exact for the time-averaged instantaneous rate:
d(T^{−γ/2})/dt = (γ/2) n ζ*, so ζ* = 2(T₁^{−γ/2} − 1)/(γ n Δt) with T₁ the temperature at the
chunk's end (γ = 0: −ln T₁/(n Δt)).

Statistics.  Successive snapshots are correlated (a particle keeps its speed until it collides,
about once per chunk), so a bin's counts are not Poisson; the seeds are independent, and the
spread over them is the honest error (:meth:`CoolingStateSample.seed_values`).
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .hard_sphere_dsmc import SphereDSMC
from .persistence import write_text
from .progress import progress_bar
from .sphere_kernels import HardSpheres
from .sphere_observables import sonine_coefficients
from .ulam import UlamState
from .validation import InvalidArgumentError, check_count, check_positive, check_seed

__all__ = ["BIN_WIDTH", "SPEED_MAX", "CoolingStateSample", "sample_cooling_state",
           "shell_volume"]

#: The histogram's bin width in |c| (bins [k w, (k + 1) w)); coarser bins are sums of these.
BIN_WIDTH = 0.05
#: The histogram's last edge in |c|; speeds beyond are counted in ``beyond``.
SPEED_MAX = 15.0


def shell_volume(lower, upper, dimension: int) -> np.ndarray:
    """The volume of the shells lower ≤ |c| < upper in d dimensions.

    Parameters
    ----------
    lower, upper : array_like
        The shells' radii, 0 ≤ lower < upper.
    dimension : int
        d, 2 or 3.

    Returns
    -------
    numpy.ndarray

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``dimension`` when it is not 2 or 3.
    """
    if dimension not in (2, 3) or isinstance(dimension, bool):
        raise InvalidArgumentError("dimension", dimension, "2 or 3")
    a, b = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
    if dimension == 2:
        return math.pi * (b * b - a * a)
    return 4.0 * math.pi * (b**3 - a**3) / 3.0


@dataclass(frozen=True)
class CoolingStateSample:
    """The scaled speeds of the cooling state (:func:`sample_cooling_state`), per seed.

    Attributes
    ----------
    parameters : dict
        ``n``, ``restitution``, ``dimension``, ``rate``, ``density``, ``seeds``, ``snapshots``,
        ``warmup``, ``spacing``, ``chunks`` (each seed's Δt at unit temperature) and
        ``bin_width``.
    counts : numpy.ndarray
        (seeds, bins) int: speeds |c| in [k w, (k + 1) w), w = ``bin_width``, over the
        snapshots.
    speed_sums : numpy.ndarray
        (seeds, bins): the sum of |c| in each bin (its mean |c| is ``speed_sums / counts``).
    beyond : numpy.ndarray
        (seeds,) int: speeds at or beyond the last edge.
    cooling_rate : numpy.ndarray
        (seeds,): ζ* per unit τ, the mean over the recorded chunks.
    a2, a3 : numpy.ndarray
        (seeds,): the Sonine coefficients, the mean over the snapshots.
    collisions_per_snapshot : numpy.ndarray
        (seeds,): pair collisions × 2/N per recorded chunk, the mean.
    seconds : float
        Wall-clock time of the sampling.
    """

    parameters: dict
    counts: np.ndarray = field(repr=False)
    speed_sums: np.ndarray = field(repr=False)
    beyond: np.ndarray = field(repr=False)
    cooling_rate: np.ndarray = field(repr=False)
    a2: np.ndarray = field(repr=False)
    a3: np.ndarray = field(repr=False)
    collisions_per_snapshot: np.ndarray = field(repr=False)
    seconds: float = 0.0

    @property
    def edges(self) -> np.ndarray:
        """The bin edges in |c|, 0, w, 2w, …, ``SPEED_MAX``."""
        bins = self.counts.shape[1]
        return np.arange(bins + 1) * float(self.parameters["bin_width"])

    @property
    def samples(self) -> int:
        """Speeds recorded over all seeds: N × snapshots × seeds."""
        return int(self.counts.sum() + self.beyond.sum())

    def density(self, merge: int = 1) -> dict:
        """The pooled density over bins of ``merge`` × ``bin_width``.

        Parameters
        ----------
        merge : int, default 1
            Fine bins per bin (the last incomplete group is dropped).

        Returns
        -------
        dict
            ``lower``, ``upper`` (the bins' edges), ``counts`` (pooled over the seeds),
            ``speed`` (the mean |c| of the bin's speeds; NaN where empty), ``density`` (F:
            counts / (samples × shell volume)), ``seed_counts`` and ``seed_density`` (seeds,
            bins) and ``seed_samples`` (the speeds of each seed).

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``merge`` when it is not a count ≥ 1.
        """
        merge = check_count(merge, "merge", 1)
        bins = (self.counts.shape[1] // merge) * merge
        per_seed = self.counts[:, :bins].reshape(len(self.counts), -1, merge).sum(axis=2)
        sums = self.speed_sums[:, :bins].reshape(len(self.counts), -1, merge).sum(axis=2)
        edges = self.edges[:bins + 1:merge]
        volume = shell_volume(edges[:-1], edges[1:], int(self.parameters["dimension"]))
        pooled = per_seed.sum(axis=0)
        seed_samples = self.counts.sum(axis=1) + self.beyond
        with np.errstate(invalid="ignore", divide="ignore"):
            speed = sums.sum(axis=0) / pooled
        return {"lower": edges[:-1], "upper": edges[1:], "counts": pooled, "speed": speed,
                "density": pooled / (self.samples * volume),
                "seed_counts": per_seed, "seed_samples": seed_samples,
                "seed_density": per_seed / (seed_samples[:, None] * volume)}

    def seed_values(self, name: str) -> tuple[float, float]:
        """The mean over the seeds of a per-seed quantity and its standard error.

        Parameters
        ----------
        name : str
            ``"cooling_rate"``, ``"a2"``, ``"a3"`` or ``"collisions_per_snapshot"``.

        Returns
        -------
        tuple of float
            (mean, standard error of the mean over the seeds; NaN for one seed).

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``name`` when it is not one of these.
        """
        if name not in _PER_SEED:
            raise InvalidArgumentError("name", name, f"one of {', '.join(_PER_SEED)}")
        x = np.asarray(getattr(self, name), dtype=float)
        err = float(np.std(x, ddof=1) / math.sqrt(x.size)) if x.size > 1 else math.nan
        return float(np.mean(x)), err

    def to_dict(self) -> dict:
        """The sample as a JSON-able dict (:meth:`from_dict` reads it back).

        Returns
        -------
        dict
        """
        out = {"parameters": dict(self.parameters), "seconds": self.seconds}
        for name in _ARRAYS:
            out[name] = np.asarray(getattr(self, name)).tolist()
        return out

    @classmethod
    def from_dict(cls, data: dict) -> CoolingStateSample:
        """The sample written by :meth:`to_dict`.

        Parameters
        ----------
        data : dict
            What :meth:`to_dict` returned (or its JSON).

        Returns
        -------
        CoolingStateSample

        Raises
        ------
        particles.validation.InvalidArgumentError
            Naming ``data`` when a field is missing.
        """
        missing = [k for k in ("parameters", *_ARRAYS) if k not in data]
        if missing:
            raise InvalidArgumentError("data", sorted(data), f"a dict with {', '.join(missing)}")
        arrays = {name: np.asarray(data[name], dtype=np.int64 if name in ("counts", "beyond")
                                   else float) for name in _ARRAYS}
        return cls(dict(data["parameters"]), seconds=float(data.get("seconds", 0.0)), **arrays)

    def save(self, path) -> Path:
        """Write the sample as JSON to ``path``.

        Parameters
        ----------
        path : str or os.PathLike
            The file.

        Returns
        -------
        pathlib.Path
        """
        return write_text(path, json.dumps(self.to_dict()))

    @classmethod
    def load(cls, path) -> CoolingStateSample:
        """Read a sample written by :meth:`save`.

        Parameters
        ----------
        path : str or os.PathLike
            The file.

        Returns
        -------
        CoolingStateSample
        """
        return cls.from_dict(json.loads(Path(path).read_text()))


_PER_SEED = ("cooling_rate", "a2", "a3", "collisions_per_snapshot")
_ARRAYS = ("counts", "speed_sums", "beyond", *_PER_SEED)


def _scaled(v: np.ndarray) -> tuple[np.ndarray, float]:
    """(c, T): the velocities centred and scaled to T = 1, and their temperature."""
    c = v - v.mean(axis=0)
    temperature = float(np.mean(np.sum(c * c, axis=1))) / v.shape[1]
    return c / math.sqrt(temperature), temperature


def _neighbour_rate(engine: SphereDSMC, c: np.ndarray) -> float:
    """n ⟨R(c_i, c_{i+1})⟩ over neighbouring pairs (the sample is in random order): the
    collision frequency per particle and unit t of the state ``c``."""
    rates = np.asarray(engine.kernel.rate(c, np.roll(c, -1, axis=0), np), dtype=float)
    return engine.density * float(np.mean(rates))


def sample_cooling_state(n: int, restitution: float, *, dimension: int = 3, seeds=(0,),
                         snapshots: int = 40, spacing: float = 1.0, warmup: int = 16,
                         rate=HardSpheres.name, density: float = 1.0,
                         progress: bool | None = None) -> CoolingStateSample:
    """Sample the scaled speeds of the cooling state with the exact DSMC (module docstring).

    For each seed: a :class:`particles.hard_sphere_dsmc.SphereDSMC` of ``n`` particles from
    the unit Maxwellian, ``warmup`` chunks not recorded, then ``snapshots`` chunks, each
    followed by a snapshot of |c|, ζ*, a₂ and a₃.

    Parameters
    ----------
    n : int
        Particles N ≥ 2.
    restitution : float
        α ∈ [0, 1].
    dimension : int, default 3
        d, 2 or 3.
    seeds : sequence of int, default (0,)
        One run per seed (``numpy.random.default_rng(seed)``); at least one.
    snapshots : int, default 40
        Recorded chunks per seed, ≥ 1.
    spacing : float, default 1
        A chunk's length in collisions per particle (at the initial state's rate), > 0.
    warmup : int, default 16
        Chunks before the first snapshot, ≥ 0.
    rate : str or particles.kernels.Kernel, default "hard_spheres"
        The kernel (:class:`particles.hard_sphere_dsmc.SphereDSMC`).
    density : float, default 1
        n > 0.
    progress : bool or None, optional
        A progress bar over the chunks (None: on a terminal or in a notebook).

    Returns
    -------
    CoolingStateSample

    Raises
    ------
    particles.validation.InvalidArgumentError
        Naming ``seeds`` (empty, or not seeds), ``snapshots``, ``spacing``, ``warmup``, or an
        argument of :class:`particles.hard_sphere_dsmc.SphereDSMC`.
    """
    engine = SphereDSMC(n, restitution, dimension=dimension, rate=rate, density=density)
    if (isinstance(seeds, (int, np.integer, str, bytes)) or not hasattr(seeds, "__len__")
            or not len(seeds)):
        raise InvalidArgumentError("seeds", seeds, "a non-empty sequence of seeds")
    seeds = [check_seed(s, "seeds") for s in seeds]
    snapshots = check_count(snapshots, "snapshots", 1)
    spacing = check_positive(spacing, "spacing")
    warmup = check_count(warmup, "warmup", 0)
    gamma = float(engine.kernel.homogeneity)
    bins = int(round(SPEED_MAX / BIN_WIDTH))
    counts = np.zeros((len(seeds), bins), dtype=np.int64)
    sums = np.zeros((len(seeds), bins))
    beyond = np.zeros(len(seeds), dtype=np.int64)
    per_seed = {name: np.zeros(len(seeds)) for name in _PER_SEED}
    start = time.perf_counter()
    chunks = []
    with progress_bar(len(seeds) * (warmup + snapshots), desc="cooling-state DSMC",
                      unit="chunk", enabled=progress) as bar:
        for i, seed in enumerate(seeds):
            rng = np.random.default_rng(seed)
            c, _ = _scaled(engine.initial_state(rng).velocities)
            dt = spacing / _neighbour_rate(engine, c)
            chunks.append(dt)
            for k in range(warmup + snapshots):
                state = engine.advance(UlamState(0.0, c, 0), dt, rng)
                c, t1 = _scaled(state.velocities)
                bar.update(1)
                if k < warmup:
                    continue
                if gamma > 0.0:
                    zeta = 2.0 * (t1 ** (-0.5 * gamma) - 1.0) / (gamma * density * dt)
                else:
                    zeta = -math.log(t1) / (density * dt)
                obs = sonine_coefficients(c)
                per_seed["cooling_rate"][i] += zeta / snapshots
                per_seed["a2"][i] += obs["a2"] / snapshots
                per_seed["a3"][i] += obs["a3"] / snapshots
                per_seed["collisions_per_snapshot"][i] += 2.0 * state.collisions / (n * snapshots)
                speed = np.sqrt(np.sum(c * c, axis=1))
                index = np.floor(speed / BIN_WIDTH).astype(np.int64)
                inside = index < bins
                counts[i] += np.bincount(index[inside], minlength=bins)
                sums[i] += np.bincount(index[inside], weights=speed[inside], minlength=bins)
                beyond[i] += int(np.count_nonzero(~inside))
    parameters = {"n": engine.n, "restitution": engine.restitution,
                  "dimension": engine.dimension, "rate": engine.rate, "density": engine.density,
                  "seeds": seeds, "snapshots": snapshots, "warmup": warmup, "spacing": spacing,
                  "chunks": chunks, "bin_width": BIN_WIDTH}
    return CoolingStateSample(parameters, counts, sums, beyond, seconds=time.perf_counter()
                              - start, **per_seed)
