"""The cooling state's scaled speeds from the exact DSMC in rescaled chunks
(particles.cooling_state_sample): exact identities (the elastic gas, the Maxwell model's
cooling rate), the real-time engine as the reference, and the record's contract.

Statistical checks state their tolerance: the mean over the seeds against the reference within
4 standard errors of that mean (the seeds are independent runs; with 8–16 seeds a 4σ miss has
a two-sided probability below 0.5 % under the t law with 7–15 degrees of freedom)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from particles.cooling_state_sample import (
    BIN_WIDTH,
    CoolingStateSample,
    sample_cooling_state,
    shell_volume,
)
from particles.hard_sphere_dsmc import SphereDSMC
from particles.sphere_kernels import VariableHardSpheres
from particles.sphere_observables import sonine_coefficients, window_times
from particles.validation import InvalidArgumentError

Z = 4.0


def _maxwell_beyond(speed: float, d: int) -> float:
    """P(|c| ≥ speed) for the unit Maxwellian (unit variance per component)."""
    if d == 2:
        return math.exp(-0.5 * speed * speed)
    return math.erfc(speed / math.sqrt(2.0)) + math.sqrt(2.0 / math.pi) * speed * math.exp(
        -0.5 * speed * speed)


def _fraction_beyond(sample: CoolingStateSample, speed: float) -> np.ndarray:
    """Per seed: the fraction of the recorded speeds at |c| ≥ speed."""
    first = int(round(speed / BIN_WIDTH))
    total = sample.counts.sum(axis=1) + sample.beyond
    return (sample.counts[:, first:].sum(axis=1) + sample.beyond) / total


@pytest.mark.parametrize("d", [2, 3])
def test_the_elastic_gas_keeps_its_temperature_and_the_maxwell_speeds(d):
    sample = sample_cooling_state(2000, 1.0, dimension=d, seeds=range(8), snapshots=8,
                                  warmup=2, progress=False)
    # exact: elastic collisions conserve the energy, so every chunk ends at T = 1 to round-off
    assert np.all(np.abs(sample.cooling_rate) < 1e-9)
    # and the Maxwellian keeps its collision frequency: a chunk is `spacing` = 1 collision per
    # particle (the chunk's length comes from the rate of the seed's own initial sample)
    mean, err = sample.seed_values("collisions_per_snapshot")
    assert abs(mean - 1.0) < Z * err
    fraction = _fraction_beyond(sample, 2.0)
    mean, err = fraction.mean(), fraction.std(ddof=1) / math.sqrt(fraction.size)
    assert abs(mean - _maxwell_beyond(2.0, d)) < Z * err


@pytest.mark.parametrize("density", [1.0, 2.5])
def test_the_maxwell_model_cools_at_its_exact_rate(density):
    # γ = 0: every pair collides at rate 1 and dE/dt = −(1 − α²)E/4 in any state, so
    # ζ* = −d ln T/dτ = (1 − α²)/4 per unit τ = n t, whatever the density
    alpha = 0.5
    kernel = VariableHardSpheres(alpha, exponent=0.0)
    sample = sample_cooling_state(2000, alpha, dimension=2, seeds=range(8), snapshots=6,
                                  warmup=1, rate=kernel, density=density, progress=False)
    mean, err = sample.seed_values("cooling_rate")
    assert abs(mean - (1.0 - alpha**2) / 4.0) < Z * err


def test_the_density_changes_the_clock_and_nothing_else():
    # hard spheres at density 2.5 collide 2.5 times as often per unit t; per unit τ = n√T t and
    # per collision nothing changes: the same ζ* and the same collisions per snapshot
    runs = [sample_cooling_state(2000, 0.5, dimension=3, seeds=range(8), snapshots=4,
                                 warmup=4, density=density, progress=False)
            for density in (1.0, 2.5)]
    for name in ("cooling_rate", "collisions_per_snapshot"):
        (m1, e1), (m2, e2) = (run.seed_values(name) for run in runs)
        assert abs(m1 - m2) < Z * math.hypot(e1, e2), name


def test_the_rescaled_chunks_sample_the_real_time_cooling_state():
    # the reference: the same engine in real time, never rescaled, at 10 … 16 collisions per
    # particle on Haff's clock; its cooling rate from T^(−1/2) growing as n ζ* t/2
    alpha, d, n, seeds = 0.5, 2, 4000, 16
    sample = sample_cooling_state(n, alpha, dimension=d, seeds=range(100, 100 + seeds),
                                  snapshots=6, warmup=10, progress=False)
    times = window_times(alpha, d, [10, 12, 14, 16])
    a2, zeta, tail = [], [], []
    for seed in range(seeds):
        engine = SphereDSMC(n, alpha, dimension=d)
        rng = np.random.default_rng(seed)
        state = engine.initial_state(rng)
        temps, values, beyond = [], [], []
        for t in times:
            state = engine.advance(state, float(t), rng)
            obs = sonine_coefficients(state.velocities)
            temps.append(obs["temperature"])
            values.append(obs["a2"])
            c = state.velocities - state.velocities.mean(axis=0)
            speed = np.sqrt(np.sum(c * c, axis=1) / obs["temperature"])
            beyond.append(np.mean(speed >= 3.0))
        a2.append(np.mean(values))
        tail.append(np.mean(beyond))
        zeta.append(2.0 * (temps[-1] ** -0.5 - temps[0] ** -0.5) / (times[-1] - times[0]))
    pairs = [(sample.seed_values("a2"), a2), (sample.seed_values("cooling_rate"), zeta),
             ((float(np.mean(_fraction_beyond(sample, 3.0))),
               float(np.std(_fraction_beyond(sample, 3.0), ddof=1) / math.sqrt(seeds))), tail)]
    for (mean, err), reference in pairs:
        ref = np.asarray(reference)
        ref_err = ref.std(ddof=1) / math.sqrt(ref.size)
        assert abs(mean - ref.mean()) < Z * math.hypot(err, ref_err), (mean, ref.mean())


def test_the_density_is_normalised_and_bins_merge():
    sample = sample_cooling_state(500, 0.5, dimension=3, seeds=[1, 2], snapshots=3, warmup=1,
                                  progress=False)
    assert sample.samples == 500 * 3 * 2
    for merge in (1, 5):
        dens = sample.density(merge)
        volume = shell_volume(dens["lower"], dens["upper"], 3)
        inside = float(np.sum(dens["density"] * volume))
        assert inside + sample.beyond.sum() / sample.samples == pytest.approx(1.0, abs=1e-12)
        assert np.all(dens["upper"] - dens["lower"] == pytest.approx(merge * BIN_WIDTH))
        seed_total = np.sum(dens["seed_density"] * volume, axis=1)
        assert np.all(seed_total <= 1.0 + 1e-12)
        filled = dens["counts"] > 0
        assert np.all((dens["speed"][filled] >= dens["lower"][filled])
                      & (dens["speed"][filled] < dens["upper"][filled]))
    assert sample.density(5)["counts"].sum() == sample.density(1)["counts"].sum()


def test_the_same_seed_gives_the_same_sample_and_it_reloads(tmp_path):
    def run():
        return sample_cooling_state(400, 0.3, dimension=2, seeds=[7, 8], snapshots=2, warmup=1,
                                    progress=False)

    first, second = run(), run()
    assert np.array_equal(first.counts, second.counts)
    assert np.array_equal(first.cooling_rate, second.cooling_rate)
    loaded = CoolingStateSample.load(first.save(tmp_path / "sample.json"))
    assert loaded.parameters == first.parameters
    for name in ("counts", "speed_sums", "beyond", "cooling_rate", "a2", "a3",
                 "collisions_per_snapshot"):
        assert np.array_equal(getattr(loaded, name), getattr(first, name)), name
    assert loaded.counts.dtype == np.int64
    other = sample_cooling_state(400, 0.3, dimension=2, seeds=[9, 8], snapshots=2, warmup=1,
                                 progress=False)
    assert not np.array_equal(other.counts[0], first.counts[0])
    assert np.array_equal(other.counts[1], first.counts[1])


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"seeds": []}, "seeds"), ({"seeds": 3}, "seeds"), ({"seeds": [-1]}, "seeds"),
    ({"seeds": "12"}, "seeds"),
    ({"snapshots": 0}, "snapshots"), ({"spacing": -1.0}, "spacing"),
    ({"spacing": math.nan}, "spacing"), ({"warmup": -1}, "warmup"),
    ({"dimension": 4}, "dimension"), ({"restitution": 1.5}, "restitution"),
    ({"n": 1}, "n"), ({"rate": "no_such_kernel"}, "rate")])
def test_bad_arguments_name_themselves(kwargs, name):
    args = {"n": 100, "restitution": 0.5, **kwargs}
    with pytest.raises(InvalidArgumentError, match=rf"\b{name}\b"):
        sample_cooling_state(args.pop("n"), args.pop("restitution"), progress=False, **args)


def test_the_record_and_its_helpers_refuse_what_they_cannot_read():
    sample = sample_cooling_state(100, 0.5, dimension=2, seeds=[0], snapshots=1, warmup=0,
                                  progress=False)
    with pytest.raises(InvalidArgumentError, match="name"):
        sample.seed_values("temperature")
    assert math.isnan(sample.seed_values("a2")[1])  # one seed: no spread
    with pytest.raises(InvalidArgumentError, match="merge"):
        sample.density(0)
    with pytest.raises(InvalidArgumentError, match="data"):
        CoolingStateSample.from_dict({"parameters": {}})
    with pytest.raises(InvalidArgumentError, match="dimension"):
        shell_volume(0.0, 1.0, 1)


def test_a_long_run_reports_its_progress(capsys):
    sample_cooling_state(100, 0.5, dimension=2, seeds=[0, 1], snapshots=2, warmup=1,
                         progress=True)
    assert "cooling-state DSMC" in capsys.readouterr().err
