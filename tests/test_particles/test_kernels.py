"""The collision-kernel contract: declarations checked once, the registry and its readers, and a
kernel defined here, in the test file, that the Ulam DSMC runs with no other change."""

from __future__ import annotations

import dataclasses
import math
from typing import ClassVar

import numpy as np
import pytest

from particles import Lattice, Ulam, simulate
from particles.collision import collide_arrays
from particles.kernels import (
    KERNELS,
    ConstantRate,
    Kernel,
    KernelParameter,
    RelativeVelocity,
    describe_kernels,
    kernel_class,
    make_kernel,
    register,
)
from particles.ulam import UlamReference
from particles.validation import InvalidArgumentError


@dataclasses.dataclass(frozen=True)
class SoftRods(Kernel):
    """Pairs collide at rate n|v − w|^(1/2), in time t (a kernel no module of the package
    knows)."""

    name: ClassVar[str] = "soft_rods_for_a_test"
    time_name: ClassVar[str] = "t"

    def rate(self, v, w, xp=np):
        return xp.sqrt(xp.abs(v - w))

    def rate_bound(self, spread):
        return math.sqrt(spread)


@pytest.fixture
def soft_rods():
    register(SoftRods)
    yield SoftRods
    KERNELS.pop(SoftRods.name)


def test_the_registry_lists_the_kernels_with_their_time_and_parameters():
    assert KERNELS["constant"] is ConstantRate and KERNELS["relative_velocity"] is RelativeVelocity
    rows = {row["name"]: row for row in describe_kernels()}
    assert rows["constant"]["time"] == "tau" and rows["relative_velocity"]["time"] == "t"
    assert rows["constant"]["fourier_closed"] and not rows["relative_velocity"]["fourier_closed"]
    gamma = rows["relative_velocity"]["parameters"][1]
    assert (gamma["name"], gamma["low"], gamma["high"], gamma["default"]) == ("exponent", 0.0,
                                                                             2.0, 1.0)
    assert [p["name"] for p in rows["constant"]["parameters"]] == ["restitution"]


def test_parameters_are_checked_once_at_construction_by_name():
    assert RelativeVelocity(0.5).exponent == 1.0
    assert RelativeVelocity(0.5, exponent=2).exponent == 2.0
    for bad in (-0.1, 2.5, math.nan, True, 1j, "x"):
        with pytest.raises(InvalidArgumentError, match="exponent"):
            RelativeVelocity(0.5, exponent=bad)
    with pytest.raises(InvalidArgumentError, match="restitution"):
        ConstantRate(1.5)
    with pytest.raises(dataclasses.FrozenInstanceError):
        RelativeVelocity(0.5).exponent = 0.5


def test_names_are_read_from_the_registry_with_one_message():
    assert kernel_class("constant") is ConstantRate
    for bad in ("hard_rods", 3, None, ["constant"]):
        with pytest.raises(InvalidArgumentError,
                           match=r"argument kernel=.* expected a registered kernel: 'constant', "
                                 r"'relative_velocity'"):
            kernel_class(bad)
    with pytest.raises(InvalidArgumentError, match="argument rate="):
        kernel_class("relative_velocity", "rate", among=("constant",))
    assert make_kernel("relative_velocity", 0.3, exponent=0.5) == RelativeVelocity(0.3, 0.5)
    k = RelativeVelocity(0.3)
    assert make_kernel(k) is k
    with pytest.raises(InvalidArgumentError, match="argument kernel="):
        make_kernel(k, 0.3)
    with pytest.raises(InvalidArgumentError, match="argument restitution="):
        make_kernel("constant")
    with pytest.raises(InvalidArgumentError, match="argument exponent=.*no parameter"):
        make_kernel("constant", 0.3, exponent=1.0)
    # the engines read the same registry, with the same message, naming their own argument
    for engine in (Ulam, Lattice):
        with pytest.raises(InvalidArgumentError,
                           match=r"argument rate='hard_rods' is invalid: expected a registered "
                                 r"kernel"):
            engine(10, 0.5, rate="hard_rods")


def test_register_checks_the_declarations():
    @dataclasses.dataclass(frozen=True)
    class NoTime(Kernel):
        name: ClassVar[str] = "no_time_for_a_test"
        time_name: ClassVar[str] = "seconds"

    with pytest.raises(TypeError, match="time_name"):
        register(NoTime)

    @dataclasses.dataclass(frozen=True)
    class Undeclared(Kernel):
        name: ClassVar[str] = "undeclared_for_a_test"
        parameters: ClassVar[tuple] = (KernelParameter("width", 0.0, 1.0, 0.5, "a width"),)

    with pytest.raises(TypeError, match="width"):
        register(Undeclared)

    @dataclasses.dataclass(frozen=True)
    class Impostor(Kernel):
        name: ClassVar[str] = "constant"

    with pytest.raises(ValueError, match="already registered"):
        register(Impostor)
    with pytest.raises(TypeError):
        register(int)
    assert KERNELS["constant"] is ConstantRate
    assert "no_time_for_a_test" not in KERNELS and "undeclared_for_a_test" not in KERNELS


def test_the_post_collision_map_is_the_engines_bit_for_bit():
    rng = np.random.default_rng(5)
    va, vb = rng.standard_normal(1000), rng.standard_normal(1000)
    for r in (0.0, 0.3, 0.9, 1.0):
        a, b = va.copy(), vb.copy()
        collide_arrays(a, b, (1 + r) / 2)
        new_a, new_b = RelativeVelocity(r).post_collision(va, vb)
        assert np.array_equal(new_a, a) and np.array_equal(new_b, b)


@pytest.mark.parametrize("gamma", [0.0, 0.5, 1.0, 1.7, 2.0])
def test_the_rate_bound_bounds_every_pair_within_the_spread(gamma):
    kernel = RelativeVelocity(0.5, gamma)
    v = np.random.default_rng(6).standard_normal(300)
    spread = float(v.max() - v.min())
    rates = kernel.rate(v[:, None], v[None, :])
    assert rates.max() <= kernel.rate_bound(spread)
    np.testing.assert_allclose(rates, np.abs(v[:, None] - v[None, :]) ** gamma, rtol=1e-15)


def test_a_kernel_defined_in_a_test_runs_in_the_ulam_dsmc_bit_for_bit_with_its_reference(
        soft_rods):
    kernel = soft_rods(0.4)
    assert kernel_class(soft_rods.name) is soft_rods
    assert soft_rods.name in {row["name"] for row in describe_kernels()}
    fast = Ulam(300, 0.4, "laplace", rate=kernel, density=2.0)
    slow = UlamReference(300, 0.4, "laplace", rate=kernel, density=2.0)
    assert fast.time_name == "t" and fast.to_dict()["rate"] == soft_rods.name
    a = simulate(fast, [0.5, 2.0], seed=3, progress=False)
    b = simulate(slow, [0.5, 2.0], seed=3, progress=False)
    assert a.collisions[-1] > 300  # a few collisions per particle
    assert np.array_equal(a.velocities, b.velocities)
    assert np.array_equal(a.collisions, b.collisions)
    with pytest.raises(InvalidArgumentError, match="restitution"):
        Ulam(300, 0.5, rate=kernel)


def test_the_soft_rod_dsmc_loses_energy_at_its_own_rate(soft_rods):
    # From one state, R short runs of length t: E[ΔE]/t → dE/dt =
    # −(1 − r²)/4 · n · (1/N²) Σ_{i≠j} |v_i − v_j|^(γ+2), γ = 1/2 (each collision removes
    # (1 − r²)/2 · g²/N of E = (1/N)Σv², at rate (n/N)|g|^γ per pair).  Tolerance: 4 standard
    # errors of the mean of the R samples of ΔE/t; the O(t) bias (the gas cools during t) is
    # relative ≈ 2K/N · (1 − r²) ≈ 1e-2 with K ≈ 12 collisions per run, under a third of the
    # standard error that the test resolves (a few per cent).
    n_particles, r, density, replicas = 2_000, 0.5, 1.5, 1500
    engine = Ulam(n_particles, r, rate=soft_rods(r), density=density)
    state = engine.initial_state(np.random.default_rng(31))
    v0 = state.velocities
    g = np.abs(v0[:, None] - v0[None, :])
    rate = -(1 - r * r) / 4 * density * float(np.sum(g**2.5)) / n_particles**2
    t = 4e-3
    e0 = float(np.mean(v0 * v0))
    rng = np.random.default_rng(32)
    changes = np.array([np.mean(engine.advance(state, t, rng).velocities ** 2) - e0
                        for _ in range(replicas)]) / t
    se = changes.std(ddof=1) / math.sqrt(replicas)
    assert abs(changes.mean() - rate) < 4 * se, (changes.mean(), rate, se)
    assert se < 0.06 * abs(rate)  # the test resolves the rate to a few per cent


def test_the_hard_rod_rate_by_name_and_by_value_are_one_engine():
    by_name = Ulam(500, 0.6, rate="relative_velocity", density=3.0)
    by_value = Ulam(500, 0.6, rate=RelativeVelocity(0.6), density=3.0)
    assert by_name == by_value and by_name.to_dict() == by_value.to_dict()
    a = simulate(by_name, [1.0], seed=4, progress=False)
    b = simulate(by_value, [1.0], seed=4, progress=False)
    assert np.array_equal(a.velocities, b.velocities)
    assert "exponent" not in by_name.to_dict()  # a hard-rod run keeps its identity
    assert Ulam(500, 0.6, rate=RelativeVelocity(0.6, 0.5)).to_dict()["exponent"] == 0.5


def test_the_kernels_command_lists_the_registry_with_what_carries_each(capsys, soft_rods):
    import json

    from maxwell_kinetics.app.cli import main

    assert main(["kernels", "--json"]) == 0
    rows = {row["name"]: row for row in json.loads(capsys.readouterr().out)["kernels"]}
    assert rows["constant"]["methods"] == ["fourier"]
    assert rows["constant"]["engines"] == ["ulam", "lattice"]
    assert rows["relative_velocity"]["methods"] == ["velocity_grid"]
    assert rows["relative_velocity"]["time"] == "t"
    # the kernel defined in this file: listed, carried by the Ulam DSMC (its rate and bound),
    # by no solver yet
    assert rows[soft_rods.name]["engines"] == ["ulam"]
    assert rows[soft_rods.name]["methods"] == []
    assert main(["kernels"]) == 0
    table = capsys.readouterr().out
    assert "relative_velocity  (time t; d = 1)" in table
    assert "exponent in [0, 2] (default 1)" in table


def test_solve_and_fixed_point_read_the_rate_from_the_registry(capsys):
    from helpers import run_error

    for command in (["solve", "--rate", "hard", "-r", "0.5", "--tau", "1"],
                    ["fixed-point", "--rate", "hard", "-r", "0.5"]):
        err = run_error(capsys, command)
        assert "argument rate='hard' is invalid: expected a registered kernel: 'constant', " \
               "'relative_velocity'" in err


def test_a_kernel_defined_again_replaces_itself(soft_rods):
    # a notebook cell run twice defines the class twice: the second replaces the first
    again = dataclasses.make_dataclass("SoftRods", [], bases=(soft_rods,), frozen=True)
    again.__module__, again.__qualname__ = soft_rods.__module__, soft_rods.__qualname__
    assert register(again) is again and KERNELS[soft_rods.name] is again


def test_a_result_keeps_the_time_its_engine_counts(soft_rods, tmp_path):
    from particles.driver import RunResult
    from particles.driver.result import time_name_of

    run = simulate(Ulam(200, 0.5, rate=soft_rods(0.5)), [0.5], seed=1, progress=False)
    assert run.time_name == "t"
    run.save(tmp_path / "run.npz")
    assert RunResult.load(tmp_path / "run.npz").time_name == "t"
    assert simulate(Lattice(20, 0.5), [0.5], seed=1, progress=False).time_name == "tau"
    # a file written before results kept it: from the model, else from its rate's kernel
    assert time_name_of("md", {}) == "t" and time_name_of("ulam", {}) == "tau"
    assert time_name_of("ulam", {"rate": "relative_velocity"}) == "t"
    assert time_name_of("ulam", {"rate": soft_rods.name}) == "t"


def test_a_kernel_whose_bound_does_not_hold_is_refused_not_run():
    @dataclasses.dataclass(frozen=True)
    class Loose(Kernel):
        name: ClassVar[str] = "loose_for_a_test"
        time_name: ClassVar[str] = "t"

        def rate(self, v, w, xp=np):
            return xp.abs(v - w)

        def rate_bound(self, spread):
            return 0.5 * spread  # below the largest rate: acceptance would pass 1

    @dataclasses.dataclass(frozen=True)
    class NoBound(Loose):
        name: ClassVar[str] = "no_bound_for_a_test"

        def rate_bound(self, spread):
            return math.nan

    engine = Ulam(400, 0.5, rate=Loose(0.5))
    with pytest.raises(InvalidArgumentError, match="rate stays <= its bound"):
        simulate(engine, [2.0], seed=1, progress=False)
    with pytest.raises(InvalidArgumentError, match="rate_bound is a finite number"):
        simulate(Ulam(400, 0.5, rate=NoBound(0.5)), [2.0], seed=1, progress=False)


def test_the_lattice_takes_a_kernel_value_it_carries():
    by_value = simulate(Lattice(200, 0.5, rate=RelativeVelocity(0.5)), [1.0], seed=3,
                        progress=False)
    by_name = simulate(Lattice(200, 0.5, rate="relative_velocity"), [1.0], seed=3,
                       progress=False)
    assert by_value.time_name == "t" and np.array_equal(by_value.energy, by_name.energy)
    assert Lattice(50, 0.5, rate=ConstantRate(0.5)).rate == "constant"
    for wrong in (RelativeVelocity(0.4), RelativeVelocity(0.5, 0.5)):
        with pytest.raises(InvalidArgumentError, match="this lattice's restitution"):
            Lattice(50, 0.5, rate=wrong)


def test_a_registered_kernel_that_is_not_carried_is_named_as_such():
    with pytest.raises(InvalidArgumentError, match="'relative_velocity' is registered, but not "
                       "carried here") as info:
        kernel_class("relative_velocity", "kernel", among=("constant",))
    assert info.value.name == "kernel" and "a registered kernel" not in str(info.value)


def test_defines_rate_is_a_predicate_that_never_raises():
    # defines_rate(1.0) raised AttributeError ('float' object has no attribute 'rate'); a kernel
    # instance was always "True" (a bound method is never the class's function)
    from particles.kernels import ConstantRate, RelativeVelocity, defines_rate

    for value in (1.0, 1 + 1j, None, "relative_velocity", object, int):
        assert defines_rate(value) is False
    assert defines_rate(RelativeVelocity) and defines_rate(RelativeVelocity(0.5))
    assert defines_rate(ConstantRate) == defines_rate(ConstantRate(0.5))
