"""What the driver records at each requested time: the same numbers as the public observables,
computed without validating or copying the engine's own N-particle arrays again.

The sticky gas gives its velocities as clusters (value, mass): the kurtosis and the rescaled
histogram are then computed over the clusters, and must equal those of the particles' velocities
(the histogram's counts and scale bit for bit: each particle's x = v/v0 is the same division).
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

from particles import observables as obs
from particles.driver import simulate
from particles.sticky import StickyGas, StickyParams
from particles.ulam import Ulam

N = 4000


def test_weighted_kurtosis_by_hand():
    # values 1 (three particles) and -2 (one): <v^2> = 7/4, <v^4> = 19/4, kurtosis 76/49
    assert obs.weighted_kurtosis([1.0, -2.0], [3, 1]) == pytest.approx(76 / 49, rel=1e-15)
    assert obs.kurtosis([1.0, 1.0, 1.0, -2.0]) == pytest.approx(76 / 49, rel=1e-15)
    # scale-free: 1e200 times the values gives the same (no overflow of v^4)
    assert obs.weighted_kurtosis([1e200, -2e200], [3, 1]) == pytest.approx(76 / 49, rel=1e-15)
    assert np.isnan(obs.weighted_kurtosis([0.0, 0.0], [2, 5]))
    assert np.isnan(obs.weighted_kurtosis([1.0, np.nan], [2, 5]))
    assert np.isnan(obs.weighted_kurtosis([], []))


def test_kurtosis_keeps_its_values_at_the_float_limits():
    # the largest |v| without an |v| temporary: a negative extreme sets the scale too
    assert obs.kurtosis([-3.0, 1.0, 1.0, 1.0]) == pytest.approx((81 + 3) / 4 / (12 / 4) ** 2)
    assert obs.kurtosis([1e300, -1e300]) == 1.0
    assert obs.kurtosis([1e-300, -1e-300, 0.0, 0.0]) == pytest.approx(2.0, rel=1e-15)
    assert np.isnan(obs.kurtosis([1.0, np.inf])) and np.isnan(obs.kurtosis([-np.inf, 1.0]))
    assert np.isnan(obs.kurtosis([1.0, np.nan])) and np.isnan(obs.kurtosis([]))


@pytest.mark.parametrize("initial", ["gaussian", "uniform"])
def test_sticky_records_are_those_of_the_particles(initial):
    times = [0.5, 3.0, 30.0, 3000.0]  # from most particles alone to a few clusters
    engine = StickyGas(StickyParams(N, 1.0, initial))
    run = simulate(engine, times, seed=4, progress=False)
    state = engine.initial_state(np.random.default_rng(4))
    for i, t in enumerate(times):
        v = engine.advance(state, t).velocities
        h = obs.rescaled_histogram(v, run.histogram_edges)
        assert np.array_equal(run.histogram_counts[i], h.count)
        assert run.histogram_scales[i] == h.v0
        assert run.energy[i] == obs.energy(v) and run.momentum[i] == obs.momentum(v)
        assert run.kurtosis[i] == pytest.approx(obs.kurtosis(v), rel=1e-13)
    assert run.extras["clusters"][-1] < N / 10  # the last time has few clusters


def test_ulam_records_are_those_of_the_particles():
    times = [0.5, 2.0]
    engine = Ulam(n=N, restitution=0.3)
    run = simulate(engine, times, seed=2, progress=False)
    again = simulate(engine, times[:1], seed=2, progress=False)
    v = again.velocities  # the state at times[0] (the engine's stream stops there too)
    h = obs.rescaled_histogram(v, run.histogram_edges)
    assert np.array_equal(run.histogram_counts[0], h.count) and run.histogram_scales[0] == h.v0
    assert run.energy[0] == obs.energy(v)
    assert run.kurtosis[0] == pytest.approx(obs.kurtosis(v), rel=1e-13)


def _count_validations(monkeypatch, n: int) -> list[int]:
    """Count calls of every ``check_real_array`` the particle modules hold that receive an
    array of ``n`` values or more."""
    big = []
    for name, module in list(sys.modules.items()):
        if not name.startswith("particles") or module is None:
            continue
        original = getattr(module, "check_real_array", None)
        if original is None:
            continue

        def counting(values, *args, _original=original, **kwargs):
            if np.size(values) >= n:
                big.append(np.size(values))
            return _original(values, *args, **kwargs)

        monkeypatch.setattr(module, "check_real_array", counting)
    return big


@pytest.mark.parametrize("make", [lambda: StickyGas(n=N, density=1.0),
                                  lambda: Ulam(n=N, restitution=0.5)])
def test_a_run_validates_its_particle_arrays_a_number_of_times_independent_of_the_outputs(
        monkeypatch, make):
    # Validation belongs at the boundary: the number of checks of N-value arrays must not grow
    # with the number of requested times (each check is a copy and a pass over N values).
    big = _count_validations(monkeypatch, N)
    simulate(make(), [1.0, 2.0], seed=1, progress=False)
    few = len(big)
    big.clear()
    simulate(make(), list(np.linspace(1.0, 2.0, 12)), seed=1, progress=False)
    assert len(big) == few


class _Velocities:
    """A state of given velocities, and an engine with no hooks beyond the driver's defaults."""

    def __init__(self, v):
        self.velocities, self.collisions, self.time = v, 0, 1.0

    @staticmethod
    def observe(state):
        return {}

    @staticmethod
    def snapshot_arrays(state):
        return {}


@pytest.mark.parametrize("scale", [1e-200, 1e-75, 1.0, 1e70, 1e150])
def test_recorded_kurtosis_and_histogram_at_the_float_limits(scale):
    # v⁴ underflows below |v| ~ 1e-77 and overflows above ~1e77: the record falls back to the
    # scaled kurtosis there, and gives the kurtosis of the unscaled velocities (1.8 for these
    # five values: ⟨v⁴⟩/⟨v²⟩² = (2·16 + 2 + 0)/5 / ((2·4 + 2)/5)² = 6.8/4 = 1.7) at every scale.
    from particles.driver.checkpoint import Records

    v = scale * np.array([2.0, -2.0, 1.0, -1.0, 0.0])
    records = Records(1, v.size, None, False, edges=obs.DEFAULT_EDGES)
    records.record(_Velocities(v), _Velocities(v), 1)
    assert records.kurtosis[0] == pytest.approx(1.7, rel=1e-14)
    h = obs.rescaled_histogram(v, obs.DEFAULT_EDGES)
    assert np.array_equal(records.hist_count[0], h.count)
    assert records.hist_v0[0] == pytest.approx(h.v0, rel=1e-15)


def test_per_time_histograms_only_when_asked(tmp_path):
    # histograms=False records the same numbers but no per-time histograms; the last time's
    # histogram is there either way, and the option is part of a checkpoint's identity only
    # where it is off (the runs before it keep theirs)
    engine = StickyGas(n=N, density=1.0)
    times = [1.0, 10.0]
    both = simulate(engine, times, seed=3, progress=False)
    last = simulate(engine, times, seed=3, progress=False, histograms=False)
    assert last.histograms == () and len(both.histograms) == 2
    assert np.array_equal(last.histogram.count, both.histogram.count)
    assert np.array_equal(last.energy, both.energy) and np.array_equal(last.kurtosis,
                                                                       both.kurtosis)
    with pytest.raises(Exception, match="histograms"):
        simulate(engine, times, seed=3, progress=False, histograms="no")
    simulate(engine, times, seed=3, progress=False, histograms=False,
             checkpoint=tmp_path / "c.npz")
    again = simulate(engine, times, seed=3, progress=False, histograms=False,
                     resume=tmp_path / "c.npz")
    assert np.array_equal(again.energy, last.energy)
    with pytest.raises(Exception, match="checkpoint|resume"):
        simulate(engine, times, seed=3, progress=False, resume=tmp_path / "c.npz")


def test_the_command_line_records_per_time_histograms_only_for_a_file(tmp_path, capsys):
    import json

    from maxwell_kinetics.app.cli import main
    from particles.driver import RunResult

    args = ["simulate", "sticky", "--n", "500", "--density", "1", "--t", "1,10", "--seed", "2"]
    assert main([*args, "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert main([*args, "--json", "--save", str(tmp_path / "r.npz")]) == 0
    with_file = json.loads(capsys.readouterr().out)
    with_file.pop("seconds"), printed.pop("seconds")
    assert with_file == printed  # the same printed numbers, with or without the file
    saved = RunResult.load(tmp_path / "r.npz")
    assert len(saved.histograms) == 2
    assert saved.energy.tolist() == printed["energy"]
