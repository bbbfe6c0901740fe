"""The observables read a run's velocities without copying them: at N = 10⁷ every extra array
of N values is 80 MB at the peak of a run (a copy in the input check, |v| for the largest
velocity, pyfftw's aligned copy of the input and a scratch array kept alive through the
structure factor took the lattice's peak from 784 MB to 938 MB).  Peaks are measured with
tracemalloc, in units of one array of N float64 values."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from particles import observables as obs
from particles.driver import simulate
from particles.lattice import Lattice
from particles.ulam import Ulam

N = 400_000


def _peak(call) -> float:
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        base = tracemalloc.get_traced_memory()[0]
        call()
        return (tracemalloc.get_traced_memory()[1] - base) / (8 * N)
    finally:
        tracemalloc.stop()


@pytest.fixture(scope="module")
def velocities():
    v = np.random.default_rng(1).standard_normal(N)
    obs.structure_factor(v[:64].copy())  # pyfftw's first import and plan, outside the count
    return v


def test_the_input_check_keeps_the_callers_array(velocities):
    assert _peak(lambda: obs.energy(velocities)) < 1.2  # v*v only (2.0 with a copy of v)
    assert _peak(lambda: obs.kurtosis(velocities)) < 1.2


def test_the_structure_factor_makes_no_copy_of_the_velocities(velocities):
    # measured 3.0 arrays (the transform, N/2 complex values, and |v̂|²); 4.0 with the copy of
    # v in the input check or the temporary |v|, and pyfftw's aligned copy of an unaligned v
    assert _peak(lambda: obs.structure_factor(velocities)) < 3.2
    unaligned = np.empty(N + 1)[1:]  # 8 bytes past an aligned start: pyfftw copied such input
    unaligned[:] = velocities
    assert _peak(lambda: obs.structure_factor(unaligned)) < 3.2
    np.testing.assert_allclose(obs.structure_factor(unaligned)[1],
                               obs.structure_factor(velocities)[1], rtol=1e-12)


@pytest.mark.parametrize("engine, t", [(Ulam, 0.5), (Lattice, 2.0)])
def test_a_run_with_its_structure_factor_peaks_below_its_engine_and_records(engine, t):
    # measured at N = 4e5: Ulam 5.51, lattice 8.12 arrays of N values, as in 0.2.0; 8.51 and
    # 10.51 before this change (the input check's copy, |v| and the record's scratch array)
    limit = {Ulam: 5.8, Lattice: 8.4}[engine]
    assert _peak(lambda: simulate(engine(N, 0.5), [t], 0, progress=False,
                                  structure_factor=True)) < limit
