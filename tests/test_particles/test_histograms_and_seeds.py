"""Per-time histograms of a run, the distance between histograms, SeedSequence seeds and the
labelled arrays of a run."""

import dataclasses
import sys

import numpy as np
import pytest

from particles import observables as obs
from particles.driver import RunResult, simulate
from particles.lattice import Lattice
from particles.ulam import Ulam
from particles.validation import InvalidArgumentError


@dataclasses.dataclass(frozen=True)
class Interrupting:
    """Wraps an engine and raises KeyboardInterrupt in its ``after``-th advance (mid-run)."""

    inner: object
    after: int
    calls: list = dataclasses.field(default_factory=list)

    @property
    def name(self):
        return self.inner.name

    def __getattr__(self, item):
        return getattr(self.inner, item)

    def advance(self, state, until, rng):
        self.calls.append(until)
        if len(self.calls) == self.after:
            raise KeyboardInterrupt
        return self.inner.advance(state, until, rng)


def _same_histograms(a, b):
    assert len(a) == len(b)
    for x, y in zip(a, b, strict=True):
        assert np.array_equal(x.count, y.count) and x.v0 == y.v0 and x.samples == y.samples
        assert np.array_equal(x.density, y.density) and np.array_equal(x.error, y.error)


# ------------------------------------------------------------------ RunResult.histograms


@pytest.mark.parametrize("engine", [Ulam(2000, 0.5, "uniform"), Lattice(2000, 0.7, "bimodal")],
                         ids=lambda e: e.name)
def test_histograms_hold_one_rescaled_histogram_per_time(engine, tmp_path):
    times = [0.0, 0.5, 2.0, 4.0]
    edges = np.linspace(-5, 5, 41)
    run = simulate(engine, times, 3, progress=False, snapshots=True, bins=edges)
    assert len(run.histograms) == len(times)
    # each one is the rescaled histogram of the velocities recorded at its time
    for h, v in zip(run.histograms, run.snapshots, strict=True):
        _same_histograms([h], [obs.rescaled_histogram(v, edges)])
    _same_histograms([run.histograms[-1]], [run.histogram])
    assert not np.array_equal(run.histograms[0].count, run.histograms[-1].count)
    # kept through a result file
    run.save(tmp_path / "run.npz")
    _same_histograms(RunResult.load(tmp_path / "run.npz").histograms, run.histograms)


def test_histograms_resume_bit_for_bit(tmp_path):
    engine, times = Ulam(1500, 0.5), [1.0, 3.0, 6.0]
    reference = simulate(engine, times, 4, progress=False)
    path = tmp_path / "run.ckpt"
    with pytest.raises(KeyboardInterrupt):
        simulate(Interrupting(engine, after=3), times, 4, progress=False, checkpoint=path)
    resumed = simulate(engine, times, 4, progress=False, resume=path)
    _same_histograms(resumed.histograms, reference.histograms)
    assert np.array_equal(resumed.velocities, reference.velocities)


def test_histograms_memory_is_counts_per_time_whatever_n():
    edges = np.linspace(-4, 4, 17)
    run = simulate(Ulam(5000, 0.5), [0.5, 1.0, 1.5], 1, progress=False, bins=edges)
    assert run.histogram_counts.shape == (3, 16) and run.histogram_scales.shape == (3,)


# ------------------------------------------------------------------ Histogram.distance


def _hist(samples, edges):
    count = np.histogram(samples, edges)[0]
    return obs.histogram_from_counts(edges, count, len(samples), 1.0)


def test_distance_ks_equals_scipys_two_sample_statistic():
    # Samples that take integer values only, one per bin of half-integer edges: the empirical
    # CDFs are constant between edges, so the sup over the edges is scipy's exact statistic.
    from scipy import stats

    rng = np.random.default_rng(11)
    a = rng.binomial(9, 0.4, size=700).astype(float)
    b = rng.binomial(9, 0.45, size=500).astype(float)
    edges = np.arange(-0.5, 10.0, 1.0)
    d = _hist(a, edges).distance(_hist(b, edges))
    assert d.ks == pytest.approx(stats.ks_2samp(a, b).statistic, abs=1e-14)


def test_distance_chi2_equals_scipys_pearson_test_against_a_law():
    # A histogram against a law (zero error), with the error of each bin set to Pearson's
    # sqrt(expected) / (n width): χ² and its dof are scipy.stats.chisquare's (dof = bins − 1,
    # every sample inside the edges).
    from scipy import stats

    rng = np.random.default_rng(5)
    edges = np.arange(-0.5, 6.0, 1.0)
    p = stats.binom.pmf(np.arange(6), 5, 0.3)
    n = 2000
    samples = rng.binomial(5, 0.3, size=n).astype(float)
    sample = _hist(samples, edges)
    width = np.diff(edges)
    sample = dataclasses.replace(sample, error=np.sqrt(n * p) / (n * width))
    law = obs.Histogram(edges, sample.centres, p / width, np.zeros(6), np.zeros(6), 0, 1.0)
    d = sample.distance(law, min_count=0)
    expected = stats.chisquare(sample.count, n * p)
    assert d.chi2 == pytest.approx(expected.statistic, rel=1e-12)
    assert d.dof == 5 and d.chi2_dof == pytest.approx(expected.statistic / 5, rel=1e-12)
    assert stats.chi2.sf(d.chi2, d.dof) == pytest.approx(expected.pvalue, rel=1e-9)
    # χ² of k degrees of freedom has mean k and variance 2k: χ²/dof has mean 1 and standard
    # deviation √(2/5) here, as scipy's law of χ² says too
    mean, sd = d.chi2_dof_expected
    assert mean == 1.0 and sd == pytest.approx(stats.chi2.std(5) / 5, rel=1e-14)


def test_distance_of_two_samples_of_one_law_is_chi2_dof_near_1():
    # 40 pairs of independent samples of N(0, 1) (4·10⁴ each): χ²/dof of each pair has mean 1 and
    # standard deviation √(2/dof); the mean over 40 pairs is 1 within 5·√(2/dof)/√40.
    rng = np.random.default_rng(2)
    edges = np.linspace(-3, 3, 31)
    values = []
    for _ in range(40):
        a, b = _hist(rng.normal(size=40_000), edges), _hist(rng.normal(size=40_000), edges)
        d = a.distance(b)
        values.append(d.chi2_dof)
    assert d.dof == 30  # mass outside ±3: no normalisation constraint
    assert abs(np.mean(values) - 1) < 5 * np.sqrt(2 / 30) / np.sqrt(40)


def test_distance_refuses_other_edges_and_non_histograms():
    a = _hist(np.zeros(10), np.linspace(-1, 1, 5))
    b = _hist(np.zeros(10), np.linspace(-1, 1, 6))
    with pytest.raises(InvalidArgumentError, match="other.*same 5 edges"):
        a.distance(b)
    with pytest.raises(InvalidArgumentError, match="other"):
        a.distance(np.ones(4))
    with pytest.raises(InvalidArgumentError, match="min_count"):
        a.distance(a, min_count=-1)


# ------------------------------------------------------------------ seeds


def test_seed_sequence_run_equals_its_int_seed_run():
    engine, times = Ulam(1000, 0.5), [0.5, 2.0]
    a = simulate(engine, times, 7, progress=False)
    b = simulate(engine, times, np.random.SeedSequence(7), progress=False)
    assert np.array_equal(a.velocities, b.velocities) and b.seed == 7
    _same_histograms(a.histograms, b.histograms)


def test_spawned_seed_sequence_is_recorded_and_resumes_bit_for_bit(tmp_path):
    engine, times = Ulam(1000, 0.5), [1.0, 3.0, 6.0]
    child = np.random.SeedSequence(7).spawn(3)[2]
    reference = simulate(engine, times, child, progress=False)
    assert reference.seed == {"entropy": 7, "spawn_key": [2], "pool_size": 4}
    # its stream is the child's, not the root's
    expected = Ulam(1000, 0.5).initial_state(np.random.default_rng(child)).velocities
    first = simulate(engine, [0.0], child, progress=False)
    assert np.array_equal(first.velocities, expected)
    path = tmp_path / "run.ckpt"
    with pytest.raises(KeyboardInterrupt):
        simulate(Interrupting(engine, after=4), times, child, progress=False, checkpoint=path)
    resumed = simulate(engine, times, child, progress=False, resume=path, checkpoint=path)
    assert np.array_equal(resumed.velocities, reference.velocities)
    assert resumed.seed == reference.seed
    reference.save(tmp_path / "r.npz")
    assert RunResult.load(tmp_path / "r.npz").seed == reference.seed
    # another child is another run, refused as a resume of this one
    from particles.driver import CheckpointError

    with pytest.raises(CheckpointError, match="seed"):
        simulate(engine, times, np.random.SeedSequence(7).spawn(3)[1], progress=False,
                 resume=path)


@pytest.mark.parametrize("seed", [np.random.default_rng(1), np.random.PCG64(1)],
                         ids=["Generator", "PCG64"])
def test_a_generator_seed_is_refused_saying_why(seed, tmp_path):
    with pytest.raises(InvalidArgumentError, match="seed.*SeedSequence") as info:
        simulate(Ulam(100, 0.5), [1.0], seed, progress=False, checkpoint=tmp_path / "c")
    if isinstance(seed, np.random.Generator):
        assert "neither repeated nor resumed" in str(info.value)
    assert not list(tmp_path.iterdir())


# ------------------------------------------------------------------ to_xarray


def test_run_to_xarray_labels_times_and_bins():
    xr = pytest.importorskip("xarray")
    edges = np.linspace(-4, 4, 9)
    run = simulate(Ulam(500, 0.5), [0.5, 1.0], 1, progress=False, bins=edges,
                   structure_factor=True)
    ds = run.to_xarray()
    assert isinstance(ds, xr.Dataset)
    assert np.array_equal(ds["energy"].values, run.energy)
    assert np.array_equal(ds["tau"].values, run.times)
    assert np.array_equal(ds["density"].sel(tau=1.0).values, run.histograms[-1].density)
    assert np.array_equal(ds["x"].values, run.histogram.centres)
    assert np.array_equal(ds["structure_factor"].values, run.structure[1])


def test_run_to_xarray_without_xarray_names_the_extra(monkeypatch):
    run = simulate(Ulam(100, 0.5), [0.5], 1, progress=False)
    monkeypatch.setitem(sys.modules, "xarray", None)
    with pytest.raises(ImportError, match=r"maxwell-kinetics\[xarray\]"):
        run.to_xarray()
