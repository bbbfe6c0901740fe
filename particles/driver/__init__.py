"""The run driver shared by every particle model: initial velocities, the run loop, progress bar,
checkpoint / resume, Ctrl-C, and saving / loading results.

Engine protocol
---------------
An engine (``particles.ulam.Ulam``, ``particles.lattice.Lattice``, the MD engine) is an object with

* ``name: str`` — ``"ulam"``, ``"lattice"``, ``"md"``;
* ``params() -> dict`` — JSON-able parameters, including ``"n"`` (the number of particles);
  a checkpoint written with other parameters is rejected;
* ``initial_state(rng) -> state``;
* ``advance(state, until, rng) -> state`` — the exact dynamics from ``state.time`` up to ``until``
  (τ for Ulam and lattice, t for MD).  It must not modify ``state`` (the driver keeps the last
  completed state for Ctrl-C), and its result may depend on ``until`` only through the exact
  dynamics and the RNG stream, so the driver only calls it with deterministic stopping points;
* ``next_stop(time) -> float`` — the next deterministic stopping point strictly after ``time``
  (a fixed grid of the model's time): the driver advances to ``min(next_stop(t), next requested
  time)``.  Because stops never depend on wall-clock time, a resumed run repeats an uninterrupted
  one bit for bit;
* ``state_from_arrays(arrays) -> state`` — rebuild a state from ``state.to_arrays()``;
* optionally ``observe(state) -> dict[str, float]`` — extra scalars recorded at each requested
  time (e.g. τ(t) for MD).
* optionally ``snapshot_fields: tuple[str, ...]`` and ``snapshot_arrays(state) -> dict`` —
  per-particle arrays recorded with each snapshot (``snapshots=True``), e.g. the MD rods'
  positions; they are kept in checkpoints and in ``RunResult.snapshot_extras``;
* optionally ``time_name: str`` — the name of the model's time in messages (default ``"tau"``;
  ``"t"`` for MD).

A state is a frozen dataclass with at least ``time: float``, ``velocities: ndarray``,
``collisions: int`` and ``to_arrays() -> dict[str, ndarray]``.

All randomness comes from one ``np.random.default_rng(seed)``.
"""

from __future__ import annotations

from .checkpoint import read_checkpoint
from .result import FORMAT_VERSION, CheckpointError, RunResult
from .run import Engine, initial_velocities, next_grid_point, simulate

__all__ = [
    "FORMAT_VERSION",
    "CheckpointError",
    "read_checkpoint",
    "Engine",
    "RunResult",
    "initial_velocities",
    "simulate",
    "next_grid_point",
]

