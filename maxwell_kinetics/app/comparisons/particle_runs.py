"""Runs of the particle models for the comparisons: Ulam, lattice, MD and the sticky gas through
the run driver (:func:`particles.driver.simulate`), and lattice runs stopped at a given energy.

A :class:`ParticleRuns` object (the runner) does the runs and keeps the lattice, MD and sticky
runs per arguments, so that comparisons given the same runner share them (comparisons 4 and 7
share their MD and lattice runs, 5 and 6 their MD runs; ``reproduce`` passes one runner to all).
Each run records only what some comparison uses, and what a kept run hands out is read-only:
every array has ``flags.writeable = False`` and each call returns a new dict, so no caller can
change what the next one gets.  The module-level functions of the same names run on a new
serial runner each time (nothing kept).

Each run is one seed: ``np.random.default_rng(seed)`` drives it (MD: the initial state only).

Where the runs execute: a runner made with no folder runs them one after the other in this
process.  A runner with an output folder (``reproduce --workers N``, ``reproduce --full``) sends
the runs of fixed times (Ulam, lattice, MD) through the ensemble engine
(:func:`particles.ensemble.run_ensemble`): one dask task per seed, each written atomically to a
task file of its own in that folder, so an interrupted ``reproduce`` resumes from the finished
runs.  Each task is the same :func:`particles.driver.simulate` call as the serial path, so the
results are the same bit for bit (tested).

Every run is named by a model of the catalogue :mod:`particles.models` and its parameters, and
nothing else: the engine is built by the catalogue's factory (:func:`_engine`), in this process
or by the ensemble engine on its workers.
"""

from __future__ import annotations

import hashlib
import json
import math
import time
from pathlib import Path

import numpy as np

from particles.driver import simulate
from particles.ensemble import EnsembleSpec, load_task, run_ensemble
from particles.kernels import ConstantRate
from particles.models import get_model
from particles.progress import progress_bar
from particles.workers import check_workers

__all__ = [
    "ulam_snapshots",
    "ulam_final",
    "ulam_runs",
    "lattice_runs",
    "lattice_at_energy",
    "md_runs",
    "md_record_times",
    "sticky_runs",
    "ParticleRuns",
]

#: Stop grid of the MD runs (units of t): how often the driver may checkpoint and update its
#: progress.  Stops change no result (the MD advance is exact across them); each costs O(N)
#: (the pair predictions are rebuilt), so the engine's default of 1 made an N = 2000 run to
#: t = 3000 about 1.7x slower than advancing straight to the requested times (measured, loaded
#: machine).
MD_STOP_STEP = 10.0


def _read_only(value):
    """``value`` with every array in it (also in tuples) made read-only, in place."""
    if isinstance(value, np.ndarray):
        value.flags.writeable = False
    elif isinstance(value, tuple):
        for v in value:
            _read_only(v)
    return value


def _engine(model: str, params: dict):
    """The engine of ``model`` with ``params``, built by the catalogue."""
    return get_model(model).build(params)


def md_record_times(t_max) -> tuple[float, ...]:
    """The times at which comparisons 5 and 6 record their MD runs (36 geometric points on
    [0.05, ``t_max``], rounded to 6 digits): one list, so that the two share the runs.

    Parameters
    ----------
    t_max : float
        The last time t (physical time).

    Returns
    -------
    tuple of float
        The 36 increasing times.
    """
    return tuple(float(t) for t in np.round(np.geomspace(0.05, t_max, 36), 6))


def _checkpoint_path(directory, md_params, times, seed) -> Path:
    """A checkpoint file of its own for each MD run (``md_params``: its
    :class:`particles.md.MDParams`): parameters, seed and a hash of the times."""
    digest = hashlib.sha256(json.dumps([float(t) for t in times]).encode()).hexdigest()[:12]
    p = md_params
    return Path(directory) / (f"md_n{p.n}_r{p.restitution:g}_d{p.delta:g}_{p.initial}"
                              f"_seed{int(seed)}_{digest}.npz")


class ParticleRuns:
    """Where the comparisons' particle runs execute, and the runs done so far.

    ``ParticleRuns()`` runs them one after the other in this process.  With ``out`` (a folder)
    the runs of fixed times (Ulam, lattice, MD) go through the ensemble engine on ``workers``
    dask processes (None: one per core; more than :func:`particles.workers.max_workers`
    only with ``force``), one task file per run in ``out``.  The lattice, MD and sticky runs
    are kept for the life of the object (read-only), so comparisons given the same object share
    them; :meth:`clear` forgets them.  Every comparison takes one as ``runner`` (default: a new
    serial one), and ``reproduce`` passes one to all of its comparisons.

    Parameters
    ----------
    out : str or os.PathLike, optional
        Folder of the ensemble engine's task files; default None (serial, in this process).
    workers : int, optional
        Number of dask processes with ``out`` (None: one per core).
    force : bool, optional
        Allow more workers than :func:`particles.workers.max_workers` (default false).

    Raises
    ------
    particles.validation.InvalidArgumentError
        From ``check_workers``: too many ``workers`` without ``force``, or a ``force`` that
        is not a bool (naming it).
    """

    def __init__(self, out=None, workers: int | None = None, force: bool = False):
        self.workers = check_workers(workers, "workers", force=force)
        self.out = None if out is None else str(out)
        self.force = bool(force)  # a bool: check_workers refused anything else
        self._done: dict = {}

    def __repr__(self) -> str:
        where = "serial" if self.out is None else f"ensemble in {self.out}"
        return f"ParticleRuns({where}, {len(self._done)} runs kept)"

    def clear(self) -> None:
        """Forget every kept run (the next call runs again)."""
        self._done.clear()

    def _runs(self, model: str, params: dict, times, seeds, progress, **options) -> list:
        """One :class:`particles.driver.RunResult` per seed: ``simulate(engine, times, seed,
        **options)`` serially (the engine of ``model`` with ``params``), or the same runs as
        tasks of the ensemble engine (module docstring)."""
        if self.out is None:
            engine = _engine(model, params)
            return [simulate(engine, list(times), int(seed), progress=progress, **options)
                    for seed in seeds]
        spec = EnsembleSpec(model, params, tuple(int(s) for s in seeds), tuple(times),
                            {"structure_factor": options.get("structure_factor", False),
                             "snapshots": bool(options.get("snapshots", False))})
        report = run_ensemble(spec, self.out, workers=self.workers, progress=progress,
                              force=self.force, shared=True)  # one folder, many ensembles
        if report.failed:
            first = report.failed[0]
            raise RuntimeError(f"{len(report.failed)} {model} run(s) failed, e.g. seed "
                               f"{first['seed']}: {first['error']}")
        return [load_task(Path(self.out) / task.filename, task.identity)
                for task in spec.expand()]

    def _cached(self, key, compute) -> dict:
        """A new dict of the cached run ``key`` (computed by ``compute()`` on the first call),
        whose arrays are read-only."""
        if key not in self._done:
            self._done[key] = {k: _read_only(v) for k, v in compute().items()}
        return dict(self._done[key])

    def ulam_snapshots(self, restitution, law, n, taus, seeds, progress=None) -> np.ndarray:
        """Velocities of Ulam runs: array (len(taus), len(seeds), n), one run per seed (not
        cached: a new array each call).

        Parameters
        ----------
        restitution : float
            Coefficient of restitution r.
        law : str
            Name of the initial velocity law (zero mean, unit variance).
        n : int
            Number of particles N.
        taus : sequence of float
            Record times τ (collisions per particle).
        seeds : sequence of int
            One run per seed, in order (R runs).
        progress : bool or None, optional
            Show progress bars (None, the default: on a terminal or in a notebook only).

        Returns
        -------
        numpy.ndarray
            Velocities, shape (len(taus), len(seeds), n).
        """
        out = np.empty((len(taus), len(seeds), int(n)))
        runs = self._runs("ulam", {"n": int(n), "restitution": restitution, "initial": law},
                          taus, seeds, progress, snapshots=True)
        for j, res in enumerate(runs):
            out[:, j, :] = res.snapshots
        return out

    def ulam_final(self, params: dict, tau: float, seeds, progress=None) -> np.ndarray:
        """Final velocities of Ulam runs of any kind (``params``: the keyword arguments of
        :class:`particles.ulam.Ulam`, e.g. ``dimension``, ``angular``, ``driving``) at τ = ``tau``:
        array (len(seeds), N) in 1D, (len(seeds), N, d) in d > 1 (not cached).

        Parameters
        ----------
        params : dict
            Keyword arguments of the Ulam model.
        tau : float
            The final time τ (collisions per particle).
        seeds : sequence of int
            One run per seed, in order (R runs).
        progress : bool or None, optional
            Show progress bars (None, the default: on a terminal or in a notebook only).

        Returns
        -------
        numpy.ndarray
            Final velocities, shape (len(seeds), N) or (len(seeds), N, d).
        """
        runs = self._runs("ulam", dict(params), [float(tau)], seeds, progress)
        return np.array([r.velocities for r in runs])

    def ulam_runs(self, params: dict, times, seeds, progress=None) -> dict:
        """Ulam runs of any kind (``params``: the keyword arguments of :class:`particles.ulam.Ulam`,
        e.g. ``rate="relative_velocity"`` and ``density`` for the DSMC of the hard-rod Boltzmann
        equation, whose time is t) recorded at ``times``: ``energy`` and ``collisions`` (pair
        collisions per particle) (R, T), ``snapshots`` (R, T, N), ``seconds``.  Cached per
        arguments (read-only).

        Parameters
        ----------
        params : dict
            Keyword arguments of the Ulam model (``n`` included).
        times : sequence of float
            Record times (τ, or t with ``rate="relative_velocity"``), T of them.
        seeds : sequence of int
            One run per seed, in order (R runs).
        progress : bool or None, optional
            Show progress bars (None, the default: on a terminal or in a notebook only).

        Returns
        -------
        dict
            A new dict of ``times``, ``energy``, ``collisions``, ``snapshots`` (read-only) and
            ``seconds``.
        """
        key = ("ulam", tuple(sorted(params.items())), tuple(times), tuple(seeds))

        def compute():
            res = self._runs("ulam", dict(params), times, seeds, progress, snapshots=True)
            n = int(params["n"])
            return {"times": np.asarray(times, dtype=float),
                    "energy": np.array([r.energy for r in res]),
                    "collisions": np.array([r.collisions / n for r in res]),
                    "snapshots": np.array([r.snapshots for r in res]),
                    "seconds": float(sum(r.seconds for r in res))}

        return self._cached(key, compute)

    def lattice_runs(self, restitution, n, times, seeds, constraint=True, law="gaussian",
                     progress=None, *, structure=False, snapshots=False,
                     rate=ConstantRate.name) -> dict:
        """Lattice runs (one per seed) recorded at ``times`` (τ): ``times`` (T,), ``energy`` (R, T),
        ``seconds``; with ``structure=True`` also ``k`` and ``structure`` (R, T, ⌊N/2⌋+1), S(k) of
        :func:`particles.observables.structure_factor`; with ``snapshots=True`` ``snapshots``
        (R, T, N).  Cached per arguments (read-only).

        Parameters
        ----------
        restitution : float
            Coefficient of restitution r.
        n : int
            Number of particles N.
        times : sequence of float
            Record times τ (collisions per particle), T of them.
        seeds : sequence of int
            One run per seed, in order (R runs).
        constraint : bool, optional
            The lattice's momentum constraint (default true).
        law : str, optional
            Name of the initial velocity law (zero mean, unit variance; default ``"gaussian"``).
        progress : bool or None, optional
            Show progress bars (None, the default: on a terminal or in a notebook only).
        structure : bool, optional
            Also record the structure factor S(k) (default false).
        snapshots : bool, optional
            Also record the velocities (default false).
        rate : str, optional
            The lattice's collision rate: ``"constant"`` (default; ``times`` are τ) or
            ``"relative_velocity"`` (``times`` are MD's t at density 1).

        Returns
        -------
        dict
            A new dict of the (read-only) arrays named above.
        """
        key = ("lattice", restitution, n, tuple(times), tuple(seeds), constraint, law,
               bool(structure), bool(snapshots), rate)

        def compute():
            params = {"n": int(n), "restitution": restitution, "initial": law,
                      "constraint": bool(constraint)}
            if rate != ConstantRate.name:  # the constant-rate runs keep their parameters, tasks
                params["rate"] = rate
            res = self._runs("lattice", params, times, seeds, progress,
                             structure_factor=bool(structure), snapshots=bool(snapshots))
            out = {"times": np.asarray(times, dtype=float),
                   "energy": np.array([r.energy for r in res]),
                   "seconds": float(sum(r.seconds for r in res))}
            if structure:
                out["k"] = res[0].structure[0]
                out["structure"] = np.array([r.structure[1] for r in res])
            if snapshots:
                out["snapshots"] = np.array([r.snapshots for r in res])
            return out

        return self._cached(key, compute)

    def md_runs(self, restitution, n, delta, times, seeds, law="gaussian", progress=None,
                checkpoint_dir=None) -> dict:
        """Event-driven MD runs (density 1, one per seed) recorded at ``times`` (t): ``energy`` and
        ``tau`` (collisions per particle) (R, T), ``snapshots`` (R, T, N) of v(i), ``positions``
        (R, T, N) of the rods in [0, L), ``seconds``.  Cached per arguments (read-only).

        Each run goes through the run driver :func:`particles.driver.simulate` with a
        :class:`particles.md.MDEngine` (stops every :data:`MD_STOP_STEP` of t; stopping changes
        nothing, bit for bit).  With ``checkpoint_dir`` (an existing folder) each run checkpoints
        to a file of its own there and resumes from it when it exists (a finished run is read back,
        not run again).  The rods' positions are recorded by the driver with each snapshot
        (``MDEngine.snapshot_arrays``), checkpoints included.

        Parameters
        ----------
        restitution : float
            Coefficient of restitution r.
        n : int
            Number of particles N.
        delta : float
            The relative-velocity threshold δ below which MD collisions are elastic (passed as the
            engine's ``delta`` parameter).
        times : sequence of float
            Record times t (physical time), T of them.
        seeds : sequence of int
            One run per seed, in order (R runs).
        law : str, optional
            Name of the initial velocity law (zero mean, unit variance; default ``"gaussian"``).
        progress : bool or None, optional
            Show progress bars (None, the default: on a terminal or in a notebook only).
        checkpoint_dir : str or os.PathLike, optional
            Existing folder for per-run checkpoints (serial runner only); default none.

        Returns
        -------
        dict
            A new dict of ``times``, ``energy``, ``tau``, ``snapshots``, ``positions`` (read-only)
            and ``seconds``.
        """
        key = ("md", restitution, n, delta, tuple(times), tuple(seeds), law)

        def compute():
            params = {"n": int(n), "density": 1.0, "restitution": restitution, "delta": delta,
                      "initial": law, "stop_step": MD_STOP_STEP}
            t_all = np.asarray(times, dtype=float)
            energy = np.empty((len(seeds), t_all.size))
            tau = np.empty_like(energy)
            snaps = np.empty((len(seeds), t_all.size, int(n)))
            pos = np.empty_like(snaps)
            seconds = 0.0
            if self.out is not None:  # through the ensemble engine (its own checkpoints)
                runs = self._runs("md", params, t_all, seeds, progress, snapshots=True)
            else:
                runs = []
                for seed in seeds:
                    engine = _engine("md", params)
                    path = resume = None
                    if checkpoint_dir is not None:
                        path = _checkpoint_path(checkpoint_dir, engine.params, t_all, seed)
                        resume = path if path.exists() else None
                    runs.append(simulate(engine, t_all, int(seed), progress=progress,
                                         snapshots=True, checkpoint=path, resume=resume))
            for i, res in enumerate(runs):
                energy[i] = res.energy
                tau[i] = res.extras["collisions_per_particle"]
                snaps[i] = res.snapshots
                pos[i] = res.snapshot_extras["positions"]
                seconds += res.seconds
            return {"times": t_all, "energy": energy, "tau": tau, "snapshots": snaps,
                    "positions": pos, "seconds": seconds}

        return self._cached(key, compute)

    def sticky_runs(self, n, times, seeds, law="gaussian", progress=None, *,
                    snapshots=False) -> dict:
        """Exact sticky-gas runs (:class:`particles.sticky.StickyGas`, density 1, one per seed)
        recorded at ``times`` (t): ``energy`` and ``clusters`` (number of clusters) (R, T),
        ``seconds``; with ``snapshots=True`` also ``snapshots`` (R, T, N) of v(i).  Seed s draws
        the initial state of :func:`md_runs` with seed s (same positions and velocities), so the
        two are paired.  Cached per arguments (read-only).

        Parameters
        ----------
        n : int
            Number of particles N.
        times : sequence of float
            Record times t (physical time), T of them.
        seeds : sequence of int
            One run per seed, in order (R runs).
        law : str, optional
            Name of the initial velocity law (zero mean, unit variance; default ``"gaussian"``).
        progress : bool or None, optional
            Show progress bars (None, the default: on a terminal or in a notebook only).
        snapshots : bool, optional
            Also record the velocities (default false).

        Returns
        -------
        dict
            A new dict of ``times``, ``energy``, ``clusters`` (read-only), ``seconds`` and, if
            asked, ``snapshots``.
        """
        key = ("sticky", n, tuple(times), tuple(seeds), law, bool(snapshots))

        def compute():
            engine = _engine("sticky", {"n": int(n), "density": 1.0, "initial": law})
            res = [simulate(engine, list(times), int(s), progress=progress,
                            snapshots=bool(snapshots)) for s in seeds]
            out = {"times": np.asarray(times, dtype=float),
                   "energy": np.array([r.energy for r in res]),
                   "clusters": np.array([r.extras["clusters"] for r in res]),
                   "seconds": float(sum(r.seconds for r in res))}
            if snapshots:
                out["snapshots"] = np.array([r.snapshots for r in res])
            return out

        return self._cached(key, compute)

    def lattice_at_energy(self, restitution, n, target, seeds, constraint=True, law="gaussian",
                          progress=None, rate=ConstantRate.name) -> dict:
        """Lattice runs (one per seed) stopped at the τ where each run's energy equals ``target``
        (``rate="relative_velocity"``: the lattice whose bonds collide at a rate ∝ |Δ|, whose time
        is MD's t; "τ" below is then t).

        Each run advances on a geometric grid of τ (ratio 1.25) until E ≤ target; τ* is interpolated
        linearly in (ln τ, ln E) between the two bracketing points (E is non-increasing: collisions
        only dissipate), and the run continues from the earlier point to τ* with the same random
        stream (exact: the state is Markov and the later draws are independent of the earlier ones).
        Returns ``tau`` (R,), ``energy`` (R,) reached, ``snapshots`` (R, N), the ``traces`` (a tuple
        of (τ, E) arrays) and ``seconds``.  Cached per arguments (read-only).

        Parameters
        ----------
        restitution : float
            Coefficient of restitution r.
        n : int
            Number of particles N.
        target : float
            The energy (mean v², in units of the initial temperature) to stop at.
        seeds : sequence of int
            One run per seed, in order (R runs).
        constraint : bool, optional
            The lattice's momentum constraint (default true).
        law : str, optional
            Name of the initial velocity law (zero mean, unit variance; default ``"gaussian"``).
        progress : bool or None, optional
            Show progress bars (None, the default: on a terminal or in a notebook only).
        rate : str, optional
            The lattice's collision rate: ``"constant"`` (default) or ``"relative_velocity"``.

        Returns
        -------
        dict
            A new dict of ``tau``, ``energy``, ``snapshots``, ``traces`` and ``seconds``.
        """
        key = ("lattice_at_energy", restitution, n, float(target), tuple(seeds), constraint, law,
               rate)

        def compute():
            engine = _engine("lattice", {"n": int(n), "restitution": restitution, "initial": law,
                                         "constraint": constraint, "rate": rate})
            start = time.perf_counter()
            taus, energies, snaps, traces = [], [], [], []
            with progress_bar(len(seeds), f"lattice r={restitution:g} E={target:.2g}", "run",
                              enabled=progress) as bar:
                for seed in seeds:
                    rng = np.random.default_rng(int(seed))
                    state = engine.initial_state(rng)
                    trace = [(0.0, float(np.mean(state.velocities ** 2)))]
                    prev = state
                    tau = 1.0
                    while True:
                        new = engine.advance(prev, tau, rng)
                        e = float(np.mean(new.velocities ** 2))
                        trace.append((tau, e))
                        if e <= target:
                            break
                        prev = new
                        tau *= 1.25
                    (ta, ea), (tb, eb) = trace[-2], trace[-1]
                    if ta <= 0.0 or ea <= eb:
                        t_star = tb
                    else:
                        w = (math.log(ea) - math.log(target)) / (math.log(ea) - math.log(eb))
                        t_star = math.exp(math.log(ta) + w * (math.log(tb) - math.log(ta)))
                    final = engine.advance(prev, max(t_star, prev.time), rng) if ta > 0 else new
                    taus.append(final.time)
                    energies.append(float(np.mean(final.velocities ** 2)))
                    snaps.append(final.velocities)
                    traces.append(np.array(trace))
                    bar.update(1)
            return {"tau": np.array(taus), "energy": np.array(energies),
                    "snapshots": np.array(snaps), "traces": tuple(traces),
                    "seconds": time.perf_counter() - start}

        return self._cached(key, compute)


# Functions of a fresh serial runner, for one-off use (nothing is kept between calls).


def ulam_snapshots(restitution, law, n, taus, seeds, progress=None) -> np.ndarray:
    """:meth:`ParticleRuns.ulam_snapshots` of a new serial :class:`ParticleRuns`.

    Parameters
    ----------
    restitution, law, n, taus, seeds, progress
        As for :meth:`ParticleRuns.ulam_snapshots`.

    Returns
    -------
    numpy.ndarray
        Its result (nothing is kept between calls).
    """
    return ParticleRuns().ulam_snapshots(restitution, law, n, taus, seeds, progress)


def ulam_final(params: dict, tau: float, seeds, progress=None) -> np.ndarray:
    """:meth:`ParticleRuns.ulam_final` of a new serial :class:`ParticleRuns`.

    Parameters
    ----------
    params, tau, seeds, progress
        As for :meth:`ParticleRuns.ulam_final`.

    Returns
    -------
    numpy.ndarray
        Its result (nothing is kept between calls).
    """
    return ParticleRuns().ulam_final(params, tau, seeds, progress)


def ulam_runs(params: dict, times, seeds, progress=None) -> dict:
    """:meth:`ParticleRuns.ulam_runs` of a new serial :class:`ParticleRuns`.

    Parameters
    ----------
    params, times, seeds, progress
        As for :meth:`ParticleRuns.ulam_runs`.

    Returns
    -------
    dict
        Its result (nothing is kept between calls).
    """
    return ParticleRuns().ulam_runs(params, times, seeds, progress)


def lattice_runs(restitution, n, times, seeds, constraint=True, law="gaussian", progress=None, *,
                 structure=False, snapshots=False, rate=ConstantRate.name) -> dict:
    """:meth:`ParticleRuns.lattice_runs` of a new serial :class:`ParticleRuns`.

    Parameters
    ----------
    restitution, n, times, seeds, constraint, law, progress, structure, snapshots, rate
        As for :meth:`ParticleRuns.lattice_runs`.

    Returns
    -------
    dict
        Its result (nothing is kept between calls).
    """
    return ParticleRuns().lattice_runs(restitution, n, times, seeds, constraint, law, progress,
                                       structure=structure, snapshots=snapshots, rate=rate)


def lattice_at_energy(restitution, n, target, seeds, constraint=True, law="gaussian",
                      progress=None, rate=ConstantRate.name) -> dict:
    """:meth:`ParticleRuns.lattice_at_energy` of a new serial :class:`ParticleRuns`.

    Parameters
    ----------
    restitution, n, target, seeds, constraint, law, progress, rate
        As for :meth:`ParticleRuns.lattice_at_energy`.

    Returns
    -------
    dict
        Its result (nothing is kept between calls).
    """
    return ParticleRuns().lattice_at_energy(restitution, n, target, seeds, constraint, law,
                                            progress, rate)


def md_runs(restitution, n, delta, times, seeds, law="gaussian", progress=None,
            checkpoint_dir=None) -> dict:
    """:meth:`ParticleRuns.md_runs` of a new serial :class:`ParticleRuns`.

    Parameters
    ----------
    restitution, n, delta, times, seeds, law, progress, checkpoint_dir
        As for :meth:`ParticleRuns.md_runs`.

    Returns
    -------
    dict
        Its result (nothing is kept between calls).
    """
    return ParticleRuns().md_runs(restitution, n, delta, times, seeds, law, progress,
                                  checkpoint_dir)


def sticky_runs(n, times, seeds, law="gaussian", progress=None, *, snapshots=False) -> dict:
    """:meth:`ParticleRuns.sticky_runs` of a new serial :class:`ParticleRuns`.

    Parameters
    ----------
    n, times, seeds, law, progress, snapshots
        As for :meth:`ParticleRuns.sticky_runs`.

    Returns
    -------
    dict
        Its result (nothing is kept between calls).
    """
    return ParticleRuns().sticky_runs(n, times, seeds, law, progress, snapshots=snapshots)
