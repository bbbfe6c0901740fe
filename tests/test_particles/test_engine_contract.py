"""The engine contract (particles.driver.Engine / EngineBase): a toy engine written only against
it runs through simulate, checkpoint, resume (bit for bit) and a serial ensemble; an engine
without the cost estimates is refused by name; the four engines share one construction idiom
and one error type for bad state arrays; and one seed rule holds for the library, the
``simulate`` command and the ensembles."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from helpers import run_error, run_json

from particles import budget
from particles.driver import CheckpointError, Engine, EngineBase, RunResult, simulate
from particles.ensemble import EnsembleSpec, register_model, run_ensemble
from particles.ensemble.tasks import load_task
from particles.lattice import Lattice
from particles.md import MDEngine, MDParams
from particles.models import MODELS
from particles.sticky import StickyGas, StickyParams
from particles.ulam import Ulam
from particles.validation import InvalidArgumentError, check_seed

# --------------------------------------------------------------------------- the toy engine


@dataclasses.dataclass(frozen=True)
class WalkState:
    time: float
    velocities: np.ndarray
    collisions: int

    def to_arrays(self):
        return {"time": np.array(self.time), "velocities": self.velocities,
                "collisions": np.array(self.collisions, dtype=np.int64)}


class ToyRotation(EngineBase):
    """A Kac-like toy: at every integer time one random pair rotates its velocities by a random
    angle (energy kept).  Written only against the contract: EngineBase's next_stop and
    state_from_arrays, its own physics and estimates."""

    name = "toy-rotation"
    stop_step = 2.0

    def __init__(self, n: int):
        self.n = int(n)

    def to_dict(self):
        return {"n": self.n}

    def initial_state(self, rng):
        v = rng.standard_normal(self.n)
        v -= v.mean()
        return WalkState(0.0, v / math.sqrt(np.mean(v * v)), 0)

    def advance(self, state, until, rng):
        v = state.velocities.copy()
        k = state.collisions
        for _ in range(math.floor(until) - math.floor(state.time)):  # events at 1, 2, 3, ...
            i, j = rng.choice(self.n, 2, replace=False)
            c, s = math.cos(theta := rng.uniform(0, 2 * math.pi)), math.sin(theta)
            v[i], v[j] = c * v[i] - s * v[j], s * v[i] + c * v[j]
            k += 1
        return WalkState(float(until), v, k)

    def rebuild_state(self, arrays):
        v = np.asarray(arrays["velocities"], dtype=float)
        if v.shape != (self.n,):
            raise ValueError(f"velocities of shape {v.shape}")
        return WalkState(float(arrays["time"]), v.copy(), int(arrays["collisions"]))

    def observe(self, state):
        return {"max_speed": float(np.max(np.abs(state.velocities)))}

    def memory_per_particle(self):
        return 8.0

    def expected_events(self, t_max, n_times):
        return math.floor(t_max), "rotations"


class NoEstimates(ToyRotation):
    """The toy without its cost estimates (EngineBase's refusing defaults)."""

    name = "toy-no-estimates"
    memory_per_particle = EngineBase.memory_per_particle
    expected_events = EngineBase.expected_events


def _toy(n):  # module level: the ensemble's factory
    return ToyRotation(n)


TIMES = [3.0, 7.5, 20.0]


def _same(a: RunResult, b: RunResult):
    for name in ("times", "energy", "momentum", "collisions", "velocities"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), strict=True)
    assert a.extras.keys() == b.extras.keys() == {"max_speed"}
    np.testing.assert_array_equal(a.extras["max_speed"], b.extras["max_speed"])


def test_toy_engine_runs_and_resumes_bit_for_bit(tmp_path):
    ref = simulate(ToyRotation(6), TIMES, 5, progress=False)
    assert ref.collisions.tolist() == [3, 7, 20]  # one event per integer time
    np.testing.assert_allclose(ref.energy, 1.0, rtol=1e-13)  # rotations keep the energy

    class Stop(ToyRotation):
        def advance(self, state, until, rng):
            if until > 8.0:
                raise KeyboardInterrupt
            return super().advance(state, until, rng)

    path = tmp_path / "toy.ckpt"
    with pytest.raises(KeyboardInterrupt):
        simulate(Stop(6), TIMES, 5, progress=False, checkpoint=path, checkpoint_interval=0)
    resumed = simulate(ToyRotation(6), TIMES, 5, progress=False, resume=path)
    _same(resumed, ref)


def test_toy_engine_bad_checkpoint_state_is_a_checkpoint_error(tmp_path):
    from helpers import edited_file

    path = tmp_path / "toy.ckpt"
    simulate(ToyRotation(6), TIMES, 5, progress=False, checkpoint=path)
    bad = edited_file(path, tmp_path / "bad.ckpt", arrays={"state.velocities": np.zeros(4)})
    with pytest.raises(CheckpointError, match="bad.ckpt.*velocities of shape"):
        simulate(ToyRotation(6), TIMES, 5, progress=False, resume=bad)


def test_toy_engine_runs_in_a_serial_ensemble(tmp_path):
    register_model("toy-rotation", _toy)
    try:
        spec = EnsembleSpec("toy-rotation", {"n": [5, 7]}, "1-2", tuple(TIMES))
        report = run_ensemble(spec, tmp_path, executor="serial", progress=False)
        assert report.ok and len(report.ran) == 4
        for task in spec.expand():
            got = load_task(tmp_path / task.filename, task.identity)
            _same(got, simulate(ToyRotation(task.params["n"]), TIMES, task.seed, progress=False))
    finally:
        MODELS.pop("toy-rotation", None)


def test_an_engine_without_estimates_is_refused_by_name():
    with pytest.raises(InvalidArgumentError, match=r"engine=.*NoEstimates \('toy-no-estimates'\)"
                       r".*estimates"):
        simulate(NoEstimates(6), TIMES, 5, progress=False)
    with pytest.raises(InvalidArgumentError, match=r"NoEstimates.*never costed by guess"):
        budget.estimate_run(NoEstimates(6), 1.0)
    with pytest.raises(InvalidArgumentError, match=r"engine='ulam'.*never costed by guess"):
        budget.estimate_run("ulam", 1.0)  # a model's name alone is not costed


def test_an_object_missing_members_of_the_contract_is_refused_naming_them():
    class Duck:  # every member of the old six, nothing more
        name = "duck"
        to_dict = initial_state = advance = next_stop = state_from_arrays = None

    with pytest.raises(InvalidArgumentError, match=r"Duck \('duck'\).*'time_name'.*'observe'"
                       r".*'memory_per_particle', 'expected_events'"):
        simulate(Duck(), [1.0], 0, progress=False)


class _Counted(ToyRotation):
    """The toy counting its advances and what the driver observes (records)."""

    def __init__(self, n):
        super().__init__(n)
        self.advances = 0
        self.observed = 0

    def observe(self, state):
        self.observed += 1
        return super().observe(state)


class Overshoot(_Counted):
    """Breaks the contract: advance returns a state past the stop it was given."""

    name = "toy-overshoot"

    def advance(self, state, until, rng):
        self.advances += 1
        new = super().advance(state, until, rng)
        return dataclasses.replace(new, time=until + 0.5)


class Stalled(_Counted):
    """Breaks the contract: advance returns a state whose time never moves."""

    name = "toy-stalled"

    def advance(self, state, until, rng):
        self.advances += 1
        if self.advances > 3:  # the driver looped: stop the test instead of hanging
            raise RuntimeError("the driver kept advancing a state whose time does not move")
        return dataclasses.replace(state, velocities=state.velocities.copy())


def test_an_engine_whose_advance_overshoots_the_stop_is_refused_before_recording():
    """A state past the stop (here, past the requested time 3) was recorded as
    the state at time 3."""
    engine = Overshoot(6)
    with pytest.raises(InvalidArgumentError,
                       match=r"engine=\"Overshoot \('toy-overshoot'\)\".*2\.5.*stop 2"):
        simulate(engine, TIMES, 5, progress=False)
    assert engine.advances == 1 and engine.observed == 0


def test_an_engine_whose_time_does_not_move_is_refused_at_the_first_step():
    """A state whose time never moves made the run loop forever; it is
    refused at the first such step, naming the engine (and a time that moves back, or is not a
    number, too)."""
    engine = Stalled(6)
    with pytest.raises(InvalidArgumentError,
                       match=r"engine=\"Stalled \('toy-stalled'\)\".*from 0\.0 to 0\.0"):
        simulate(engine, TIMES, 5, progress=False)
    assert engine.advances == 1 and engine.observed == 0

    class Backwards(_Counted):
        def advance(self, state, until, rng):
            self.advances += 1
            new = super().advance(state, until, rng)
            return dataclasses.replace(new, time=-1.0 if self.advances > 1 else new.time)

    class NotANumber(_Counted):
        def advance(self, state, until, rng):
            self.advances += 1
            return dataclasses.replace(super().advance(state, until, rng), time=math.nan)

    for broken in (Backwards(6), NotANumber(6)):
        with pytest.raises(InvalidArgumentError, match=type(broken).__name__):
            simulate(broken, TIMES, 5, progress=False)
        assert broken.observed == 0


def test_a_stop_grid_of_more_than_ten_million_stops_is_refused_naming_stop_step(capsys):
    """``simulate md --stop-step 1e-300`` looped for ever (each stop is an ``advance``, and
    t + 1e-300 is t); more than 10⁷ stops up to the last time is refused before any work,
    naming ``stop_step`` (1.01·10⁷ stops already: the bound is that close)."""
    from particles.driver.run import MAX_STOPS

    assert MAX_STOPS == 1e7
    for step in (1e-300, 0.99e-7):
        engine = MDEngine(MDParams(50, 1.0, 0.9), stop_step=step)
        with pytest.raises(InvalidArgumentError, match=r"stop_step=.*at most 1e\+07 stops"):
            simulate(engine, [0.0, 1.0], 1, progress=False)
    err = run_error(capsys, ["simulate", "md", "--n", "50", "--density", "1",
                             "--restitution", "0.9", "--t", "1", "--stop-step", "1e-300"])
    assert "stop_step=1e-300" in err and "--force" in err


def test_an_engine_without_a_name_or_a_stop_step_gets_no_guess():
    class Nameless(ToyRotation):
        name = ""

    with pytest.raises(InvalidArgumentError, match=r"engine=.*Nameless.*an engine with a name"):
        simulate(Nameless(4), [1.0], 0, progress=False)

    class NoGrid(ToyRotation):  # EngineBase's default: no stops between requested times
        stop_step = EngineBase.stop_step

    assert NoGrid(4).next_stop(3.0) == math.inf
    with pytest.raises(InvalidArgumentError, match="engine='Ulam'.*not its class"):
        simulate(Ulam, [1.0], 0, progress=False)
    _same(simulate(NoGrid(6), TIMES, 2, progress=False),
          simulate(ToyRotation(6), TIMES, 2, progress=False))


def test_the_contract_lists_what_engine_base_and_the_four_engines_have():
    members = [m for m in vars(Engine) if not m.startswith("_")] + list(Engine.__annotations__)
    for engine in (Ulam(10, 0.5), Lattice(10, 0.5), MDEngine(n=10, density=1.0, restitution=0.5),
                   StickyGas(n=10, density=1.0), ToyRotation(4),
                   Ulam(10, 0.5, rate="relative_velocity", density=2.0)):
        assert isinstance(engine, EngineBase)
        assert all(hasattr(engine, m) for m in members), type(engine).__name__


# --------------------------------------------------------------------------- one idiom


def test_every_engine_is_built_from_its_parameters_by_keyword():
    md = MDEngine(n=50, density=0.5, restitution=0.7, delta=1e-3, rod_length=0.1,
                  initial="uniform", stop_step=0.5)
    assert md.to_dict() == MDEngine(MDParams(50, 0.5, 0.7, 1e-3, 0.1, "uniform"),
                                    stop_step=0.5).to_dict()
    sticky = StickyGas(n=50, density=2.0, initial="uniform")
    assert sticky.to_dict() == StickyGas(StickyParams(50, 2.0, "uniform")).to_dict()
    assert Ulam(n=50, restitution=0.5).to_dict() == Ulam(50, 0.5).to_dict()
    assert (Ulam(n=50, restitution=0.5, rate="relative_velocity", density=2.0).to_dict()
            == Ulam(50, 0.5, "gaussian", 1, "uniform", 0.0, "relative_velocity", 2.0).to_dict())
    assert Lattice(n=50, restitution=0.5).to_dict() == Lattice(50, 0.5).to_dict()
    with pytest.raises(InvalidArgumentError, match="params=.*not both"):
        MDEngine(MDParams(50, 0.5, 0.7), n=50)
    with pytest.raises(InvalidArgumentError, match="params=.*not both"):
        StickyGas(StickyParams(50, 2.0), density=2.0)
    with pytest.raises(InvalidArgumentError, match="argument density=None"):
        MDEngine(n=50, restitution=0.5)
    with pytest.raises(InvalidArgumentError, match="argument n=None"):
        StickyGas(density=1.0)


@pytest.mark.parametrize("engine", [
    Ulam(8, 0.5), Lattice(8, 0.5), MDEngine(n=8, density=1.0, restitution=0.5),
    StickyGas(n=8, density=1.0), Ulam(8, 0.5, rate="relative_velocity")],
    ids=lambda e: e.name + ("-" + e.rate if isinstance(e, Ulam) else ""))
def test_bad_state_arrays_raise_one_error_type_naming_checkpoint(engine):
    good = engine.initial_state(np.random.default_rng(0)).to_arrays()
    bad_shape = dict(good, velocities=np.zeros(5))
    missing = {k: v for k, v in good.items() if k != "velocities"}
    for arrays in (bad_shape, missing, [1, 2]):
        with pytest.raises(InvalidArgumentError, match="argument checkpoint="):
            engine.state_from_arrays(arrays)


# --------------------------------------------------------------------------- one seed rule


SEEDS = [(0, True), (2**64 - 1, True), (2**64, False), (-1, False), (2**70, False),
         (7.0, True), (True, False), (2.5, False)]


@pytest.mark.parametrize("seed, accepted", SEEDS)
def test_one_seed_rule_for_library_command_and_ensemble(capsys, tmp_path, seed, accepted):
    outcomes = {}
    try:  # the library
        simulate(Ulam(10, 0.5), [0.5], seed, progress=False)
        outcomes["simulate"] = True
    except InvalidArgumentError as exc:
        assert exc.name == "seed"
        outcomes["simulate"] = False
    argv = ["simulate", "ulam", "--n", "10", "--restitution", "0.5", "--tau", "0.5",
            f"--seed={seed}", "--json"]
    if accepted:  # the command
        assert run_json(capsys, argv)["seed"] == seed
        outcomes["command"] = True
    else:
        assert f"seed='{seed}'" in run_error(capsys, argv)
        outcomes["command"] = False
    try:  # the ensembles
        spec = EnsembleSpec("ulam", {"n": 10, "restitution": 0.5}, (seed,), (0.5,))
        report = run_ensemble(spec, tmp_path, executor="serial", progress=False)
        outcomes["ensemble"] = report.ok
    except InvalidArgumentError as exc:
        assert exc.name == "seeds"
        outcomes["ensemble"] = False
    assert outcomes == dict.fromkeys(("simulate", "command", "ensemble"), accepted)


@pytest.mark.parametrize("seed, expected", [
    (True, None), (1.5, None), ("3", None), (None, None), (7.0, 7),
    (np.uint64(2**64 - 1), 2**64 - 1), (np.int64(-1), None)])
def test_check_seed_is_the_one_rule(seed, expected):
    if expected is not None:
        assert check_seed(seed) == expected
    else:
        with pytest.raises(InvalidArgumentError, match="argument seed="):
            check_seed(seed)
