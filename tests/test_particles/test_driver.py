"""The run driver: initial velocities, reproducibility, checkpoint/resume, Ctrl-C, results."""

import dataclasses

import numpy as np
import pytest

from particles.driver import (
    CheckpointError,
    RunResult,
    initial_velocities,
    next_grid_point,
    read_checkpoint,
    simulate,
)
from particles.initial import law_names
from particles.lattice import Lattice
from particles.ulam import Ulam
from particles.validation import InvalidArgumentError


@pytest.mark.parametrize("law", law_names())
def test_initial_velocities_have_zero_momentum_and_unit_energy(law):
    v = initial_velocities(law, 1001, np.random.default_rng(0))
    assert v.shape == (1001,)
    assert abs(v.mean()) < 1e-15
    assert np.mean(v**2) == pytest.approx(1.0, abs=1e-14)


def test_next_grid_point_is_strictly_after():
    assert next_grid_point(0.0, 0.25) == 0.25
    assert next_grid_point(0.25, 0.25) == 0.5
    assert next_grid_point(0.3, 0.25) == 0.5
    assert next_grid_point(0.1 * 3, 0.1) > 0.1 * 3


def _assert_same_run(a: RunResult, b: RunResult):
    assert np.array_equal(a.times, b.times)
    assert np.array_equal(a.energy, b.energy)
    assert np.array_equal(a.momentum, b.momentum)
    assert np.array_equal(a.collisions, b.collisions)
    assert np.array_equal(a.velocities, b.velocities)
    assert np.array_equal(a.histogram.count, b.histogram.count)
    assert (a.structure is None) == (b.structure is None)
    if a.structure is not None:
        assert np.array_equal(a.structure[1], b.structure[1])
    assert a.extras.keys() == b.extras.keys()
    for key in a.extras:
        assert np.array_equal(a.extras[key], b.extras[key])


ENGINES = [Ulam(3000, 0.5, "uniform"), Lattice(3000, 0.7, "bimodal")]


@pytest.mark.parametrize("engine", ENGINES, ids=lambda e: e.name)
def test_same_seed_same_result_other_seed_other_result(engine):
    times = [0.0, 0.5, 3.0, 9.5]
    a = simulate(engine, times, 7, progress=False, structure_factor=True)
    b = simulate(engine, times, 7, progress=False, structure_factor=True)
    _assert_same_run(a, b)
    c = simulate(engine, times, 8, progress=False)
    assert not np.array_equal(a.velocities, c.velocities)
    assert a.energy[0] == pytest.approx(1.0, abs=1e-14)
    assert a.collisions[0] == 0 and np.all(np.diff(a.collisions) > 0)


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
            rng.random(17)  # the interrupted advance has consumed randomness: must not matter
            raise KeyboardInterrupt
        return self.inner.advance(state, until, rng)


@pytest.mark.parametrize("engine", ENGINES, ids=lambda e: e.name)
def test_ctrl_c_checkpoint_then_resume_is_bit_identical(engine, tmp_path):
    times = [1.0, 6.5, 13.0]
    path = tmp_path / "run.ckpt"
    reference = simulate(engine, times, 3, progress=False, structure_factor=True)
    with pytest.raises(KeyboardInterrupt):
        simulate(
            Interrupting(engine, after=3),
            times,
            3,
            progress=False,
            structure_factor=True,
            checkpoint=path,
        )
    assert path.exists()
    resumed = simulate(
        engine, times, 3, progress=False, structure_factor=True, resume=path, checkpoint=path
    )
    _assert_same_run(reference, resumed)
    # The final checkpoint holds the finished run: resuming it again changes nothing.
    again = simulate(engine, times, 3, progress=False, structure_factor=True, resume=path)
    _assert_same_run(reference, again)


@pytest.mark.parametrize("structure", ["all", "last"])
def test_ctrl_c_while_recording_gives_a_resumable_checkpoint(structure, tmp_path, monkeypatch):
    # Ctrl-C can land while the driver records a requested time (in the S(k) FFT, the snapshot
    # copy or ``observe``), after some entries of that time were computed.  The checkpoint saved
    # then must be consistent (nothing beyond ``done``) and resume to the uninterrupted run.
    # Found by review: with energy written before ``done`` moved on, resume refused the file.
    engine = Ulam(400, 0.5)
    times = [1.0, 2.0, 3.0]
    kw = dict(progress=False, structure_factor=structure, snapshots=True)
    reference = simulate(engine, times, 5, **kw)
    from particles import observables

    real = observables.structure_factor
    calls = []

    def interrupted(v):
        calls.append(1)
        if len(calls) == (2 if structure == "all" else 1):
            raise KeyboardInterrupt
        return real(v)

    path = tmp_path / "run.ckpt"
    monkeypatch.setattr(observables, "structure_factor", interrupted)
    with pytest.raises(KeyboardInterrupt):
        simulate(engine, times, 5, checkpoint=path, **kw)
    monkeypatch.setattr(observables, "structure_factor", real)
    assert path.exists()
    resumed = simulate(engine, times, 5, resume=path, **kw)
    _assert_same_run(reference, resumed)


def test_last_only_run_resumes_a_checkpoint_that_kept_every_spectrum(tmp_path):
    # Checkpoints written before the CLI switched to structure_factor="last" hold S(k) at every
    # time (True).  The dynamics is the same, so such a file resumes a "last" run, which keeps
    # the last row only, and gives the uninterrupted "last" run bit for bit.
    engine = Ulam(400, 0.5)
    times = [1.0, 2.0, 3.0]
    reference = simulate(engine, times, 9, progress=False, structure_factor="last")
    path = tmp_path / "old.ckpt"
    with pytest.raises(KeyboardInterrupt):
        simulate(Interrupting(engine, after=2), times, 9, progress=False, structure_factor=True,
                 checkpoint=path)
    resumed = simulate(engine, times, 9, progress=False, structure_factor="last", resume=path)
    _assert_same_run(reference, resumed)
    assert resumed.structure[1].shape == (1, 201)


def test_periodic_checkpoints_do_not_change_the_run(tmp_path):
    engine = Ulam(500, 0.3)
    times = [2.0, 7.0]
    plain = simulate(engine, times, 11, progress=False)
    path = tmp_path / "c.npz"
    saved = simulate(engine, times, 11, progress=False, checkpoint=path, checkpoint_interval=0)
    _assert_same_run(plain, saved)


def test_bad_checkpoints_are_named(tmp_path):
    engine = Ulam(200, 0.5)
    good = tmp_path / "good.ckpt"
    simulate(engine, [1.0], 1, progress=False, checkpoint=good)
    garbage = tmp_path / "garbage.ckpt"
    garbage.write_bytes(b"this is not a checkpoint")
    with pytest.raises(CheckpointError, match="garbage.ckpt"):
        simulate(engine, [1.0], 1, progress=False, resume=garbage)
    with pytest.raises(CheckpointError, match="missing.ckpt.*no such file"):
        simulate(engine, [1.0], 1, progress=False, resume=tmp_path / "missing.ckpt")
    with pytest.raises(CheckpointError, match="good.ckpt.*restitution"):
        simulate(Ulam(200, 0.6), [1.0], 1, progress=False, resume=good)
    with pytest.raises(CheckpointError, match="good.ckpt.*model"):
        simulate(Lattice(200, 0.5), [1.0], 1, progress=False, resume=good)
    with pytest.raises(CheckpointError, match="seed"):
        simulate(engine, [1.0], 2, progress=False, resume=good)
    result = tmp_path / "result.npz"
    simulate(engine, [1.0], 1, progress=False).save(result)
    with pytest.raises(CheckpointError, match="result.npz.*not a checkpoint"):
        simulate(engine, [1.0], 1, progress=False, resume=result)
    assert issubclass(CheckpointError, InvalidArgumentError)


def test_structure_factor_at_the_last_time_only(tmp_path):
    engine = Lattice(300, 0.5)
    times = [1.0, 4.5, 8.0]
    every = simulate(engine, times, 2, progress=False, structure_factor="all")
    last = simulate(engine, times, 2, progress=False, structure_factor="last")
    assert every.structure[1].shape == (3, 151) and last.structure[1].shape == (1, 151)
    assert np.array_equal(every.structure[1][-1], last.structure[1][0])
    assert np.array_equal(every.structure[0], last.structure[0])
    assert np.array_equal(every.velocities, last.velocities)
    with pytest.raises(InvalidArgumentError, match="structure_factor='first'"):
        simulate(engine, times, 2, progress=False, structure_factor="first")
    path = tmp_path / "c.npz"
    simulate(engine, times, 2, progress=False, structure_factor="last", checkpoint=path)
    with pytest.raises(CheckpointError, match="structure_factor"):  # another run's records
        simulate(engine, times, 2, progress=False, structure_factor=True, resume=path)


def test_result_save_and_load_round_trip(tmp_path):
    res = simulate(
        Lattice(256, 0.5), [1.0, 4.0], 5, progress=False, structure_factor=True, snapshots=True
    )
    path = tmp_path / "res.npz"
    res.save(path)
    back = RunResult.load(path)
    _assert_same_run(res, back)
    assert back.params == res.params and back.model == "lattice" and back.seed == 5
    assert np.array_equal(back.snapshots, res.snapshots)
    assert np.array_equal(back.snapshots[-1], res.velocities)
    assert back.summary() == res.summary()


def test_read_checkpoint_gives_the_run_its_records_and_its_state(tmp_path):
    engine = Lattice(64, 0.5)
    res = simulate(engine, [1.0, 2.0], 3, progress=False, checkpoint=tmp_path / "c.npz")
    ckpt = read_checkpoint(tmp_path / "c.npz")
    assert ckpt["done"] == 2 and ckpt["run"]["seed"] == 3 and ckpt["run"]["times"] == [1.0, 2.0]
    np.testing.assert_array_equal(ckpt["records"]["energy"], res.energy)
    state = engine.state_from_arrays(ckpt["state"])
    assert state.time == 2.0 and np.array_equal(state.velocities, res.velocities)
    res.save(tmp_path / "result.npz")  # a result file is not a checkpoint
    with pytest.raises(CheckpointError, match="result.npz"):
        read_checkpoint(tmp_path / "result.npz")


def test_record_round_trip_and_final_state(tmp_path):
    # to_record/from_record is the one layout of result and task files; the final state comes
    # back with the run, also from a checkpoint whose run had already finished
    engine = Lattice(128, 0.5)
    res = simulate(engine, [1.0, 3.0], 7, progress=False, checkpoint=tmp_path / "c.npz")
    arrays, meta = res.to_record()
    back = RunResult.from_record(arrays, meta)
    _assert_same_run(res, back)
    assert back.final_state is None and back.seconds == res.seconds
    assert res.final_state.time == 3.0
    assert np.array_equal(res.final_state.velocities, res.velocities)
    again = simulate(engine, [1.0, 3.0], 7, progress=False, resume=tmp_path / "c.npz")
    assert again.final_state.time == 3.0
    assert np.array_equal(again.final_state.velocities, res.velocities)
    with pytest.raises(KeyError):
        RunResult.from_record({k: v for k, v in arrays.items() if k != "energy"}, meta)


@pytest.mark.parametrize(
    "times, match", [([1.0, 0.5], r"argument times=\[1\.0"), ([-1.0], r"argument times=\[-1"),
                     ([], r"argument times=\[\]"), ([np.nan], r"argument times=\[nan")]
)
def test_bad_times_are_rejected(times, match):
    with pytest.raises(InvalidArgumentError, match=match):
        simulate(Ulam(10, 0.5), times, 0, progress=False)


def test_bad_seed_is_rejected():
    with pytest.raises(InvalidArgumentError, match="seed=-1"):
        simulate(Ulam(10, 0.5), [1.0], -1, progress=False)


def test_particles_never_imports_jax():
    import subprocess
    import sys

    code = (
        "import sys, particles, particles.md, particles.ulam, particles.lattice\n"
        "assert 'jax' not in sys.modules, sorted(m for m in sys.modules if 'jax' in m)\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


def test_progress_bar_runs_on_stderr(capsys):
    quiet = simulate(Lattice(300, 0.5), [2.0, 9.0], 1, progress=False)
    loud = simulate(Lattice(300, 0.5), [2.0, 9.0], 1, progress=True)
    _assert_same_run(quiet, loud)
    captured = capsys.readouterr()
    assert captured.out == "" and "lattice" in captured.err


@pytest.mark.parametrize("rng", [5, None, "seed", np.random.SeedSequence(1)])
def test_initial_velocities_names_a_bad_rng(rng):
    from particles import InvalidArgumentError, initial_velocities

    with pytest.raises(InvalidArgumentError, match="rng"):
        initial_velocities("gaussian", 10, rng)
