"""Exact event-driven molecular dynamics of inelastic hard rods on a ring.

Model
-----
N rods of length σ on a ring of length L = N / n fly freely between collisions.  A collision of
the left rod i with its right neighbour j = i + 1 (they collide only when approaching,
v_i > v_j) uses the collision rule with Δ = v_i − v_j:

    v_i' = v_i − p Δ,    v_j' = v_j + p Δ,    p = (1 + r)/2,

except that a collision with Δ < δ is elastic (p = 1, the Ben-Naim et al. regularisation); δ = 0
switches the regularisation off.  Elastic collisions (r = 1 or Δ < δ) are carried out as an exact
swap of the two velocities, so they conserve momentum and energy bit for bit.

Coordinates
-----------
Everything is done with point particles on the reduced ring of length L_r = L − N σ:
the rod i sits at y_i = x_i + i σ.  Point coordinates are *unwrapped* and particle
labels never change order, so at any common time

    x_0 ≤ x_1 ≤ … ≤ x_{N−1} ≤ x_0 + L_r .

Pair b is the neighbour pair (b, b + 1); the seam pair N − 1 is (N − 1, 0) with the partner seen
at x_0 + L_r.  Each particle is stored lazily: its position ``x[i]`` at its own last-update time
``t_last[i]``; at a time t it is at x[i] + v[i] (t − t_last[i]).

Exactness
---------
Every collision is processed at its true time in causal order (no time step, no overlap
correction).  Two engines share one prediction formula and one collision formula, written once
in :mod:`particles.md.kernel` (with its floating-point guards: a gap that round-off made negative
is treated as zero; after an inelastic collision the pair must separate, so the new velocities
are clipped to the old interval and swapped if round-off left them approaching):

* ``method="reference"``: a plain sequential loop, a binary heap (``heapq``) over the N pair
  predictions with lazy invalidation, ties broken by the pair index
  (:mod:`particles.md.reference`).
* ``method="fast"``: the light-cone scheme (:mod:`particles.md.lightcone`):
  vectorised NumPy passes over all the collisions that no other pending collision can reach,
  and, where a pass would fire only a handful, the scalar heap loop on the same data, with
  zero-gap bursts run as a sort.

Both engines apply the same floating-point operations to the same data, so in non-chaotic
settings they agree bit for bit (tested).  Where a scalar loop writes a kernel formula out by
hand for speed, the copy is marked ``kernel copy``, and a test
(``tests/test_particles/test_md_kernel.py``) runs the very lines of that copy against the kernel,
bit for bit.

Modules
-------
:mod:`~particles.md.engine` (MDParams, MDState, MDEngine, InelasticCollapseError: the driver
interface), :mod:`~particles.md.kernel`, :mod:`~particles.md.reference`,
:mod:`~particles.md.lightcone`, :mod:`~particles.md.observables` (τ(t), momentum, rod positions,
profiles, Haff's law) and :mod:`~particles.md.analysis` (causal depth and cluster anatomy of a
window, for the benchmarks).

Runs
----
:class:`MDEngine` is an engine of the shared run driver (:func:`particles.driver.simulate`: stops,
progress bar, checkpoint / resume bit for bit, Ctrl-C, :class:`particles.driver.RunResult`).
Energy, histogram, S(k) and C(r) are those of :mod:`particles.observables` applied to the
velocities in label order (the lattice conventions); :mod:`particles.md.observables` adds what is
MD-specific.  Inelastic collapse (δ = 0) raises :class:`InelasticCollapseError` (see
:mod:`particles.md.engine`).
"""

from __future__ import annotations

from .engine import InelasticCollapseError, MDEngine, MDParams, MDState
from .observables import (
    collisions_per_particle,
    haff_energy,
    initial_cooling_rate,
    profile_i,
    profile_x,
    rod_positions,
    total_momentum,
)

__all__ = [
    "InelasticCollapseError",
    "MDParams",
    "MDState",
    "MDEngine",
    "collisions_per_particle",
    "total_momentum",
    "rod_positions",
    "profile_x",
    "profile_i",
    "haff_energy",
    "initial_cooling_rate",
]
