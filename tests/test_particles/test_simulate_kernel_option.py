"""``simulate ulam --kernel NAME`` and ``ensemble ulam --kernel NAME``: the kernels are read from
the registry (:data:`particles.kernels.KERNELS`) when the parser is built, so a kernel
registered by a test (here, soft rods with a declared parameter) is a choice, with its
parameter an option; ``--rate`` stays an alias of ``--kernel`` (same numbers, bit for bit); a
parameter of another kernel than the one chosen is refused by name; the JSON keeps its keys and
adds the kernel; the run's time is the kernel's."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest
from helpers import run_error, run_json

from particles.driver import simulate
from particles.kernels import KERNELS, Kernel, KernelParameter, RelativeVelocity, register
from particles.lattice import Lattice
from particles.ulam import Ulam

#: The power p of the soft rods' rate |v − w|^p.
POWER = KernelParameter("power", 0.0, 1.0, 0.5, "power p of the rate |v - w|^p")


@dataclass(frozen=True)
class SoftRods(Kernel):
    """Soft rods: rate |v − w|^p (p = 1/2 by default) in physical time t."""

    name: ClassVar[str] = "soft_rods"
    time_name: ClassVar[str] = "t"
    parameters: ClassVar[tuple[KernelParameter, ...]] = (POWER,)

    power: float = 0.5

    def rate(self, v, w, xp=np):
        return xp.abs(v - w) ** self.power

    def rate_bound(self, spread):
        return float(spread) ** self.power


@pytest.fixture
def soft_rods():
    register(SoftRods)
    yield SoftRods
    KERNELS.pop(SoftRods.name)


ULAM = ["simulate", "ulam", "--n", "200", "--restitution", "0.5", "--seed", "3"]

#: The keys of ``simulate ulam --rate relative_velocity --json`` before the kernel was added.
DSMC_KEYS = {"model", "t", "energy", "kurtosis", "collisions", "seconds", "histogram", "params",
             "seed"}


def _help(capsys, argv) -> str:
    from maxwell_kinetics.app.cli import main

    with pytest.raises(SystemExit) as exc:
        main([*argv, "--help"])
    assert exc.value.code == 0
    return capsys.readouterr().out


def test_a_kernel_registered_before_main_is_a_choice_and_runs_in_its_time(capsys, soft_rods):
    text = _help(capsys, ["simulate", "ulam"])
    assert "soft_rods" in text and "--power" in text and "power p of the rate" in text
    out = run_json(capsys, [*ULAM, "--kernel", "soft_rods", "--t", "0.5,1", "--json"])
    assert out["t"] == [0.5, 1.0] and "tau" not in out
    assert out["kernel"] == {"kernel": "soft_rods", "restitution": 0.5, "power": 0.5}
    assert out["params"]["rate"] == "soft_rods"
    run = simulate(Ulam(200, 0.5, rate="soft_rods"), [0.5, 1.0], 3, progress=False)
    assert run.time_name == "t"
    assert out["energy"] == run.energy.tolist() and out["collisions"] == run.collisions[-1]
    # its declared parameter is an option, passed to the kernel as it is built
    out = run_json(capsys, [*ULAM, "--kernel", "soft_rods", "--power", "0.25", "--t", "1",
                            "--json"])
    assert out["kernel"] == {"kernel": "soft_rods", "restitution": 0.5, "power": 0.25}
    run = simulate(Ulam(200, 0.5, rate=SoftRods(0.5, power=0.25)), [1.0], 3, progress=False)
    assert out["energy"] == run.energy.tolist()
    err = run_error(capsys, [*ULAM, "--kernel", "soft_rods", "--power", "2", "--t", "1"])
    assert "power=" in err and "[0, 1]" in err


def test_an_unknown_kernel_is_refused_naming_kernel_and_listing_the_accepted(capsys,
                                                                           soft_rods):
    err = run_error(capsys, [*ULAM, "--kernel", "nosuch", "--t", "1"])
    assert "kernel='nosuch'" in err
    assert all(repr(name) in err for name in ("constant", "relative_velocity", "soft_rods"))


def test_a_kernel_no_longer_registered_is_no_choice(capsys):
    assert "soft_rods" not in KERNELS
    err = run_error(capsys, [*ULAM, "--kernel", "soft_rods", "--t", "1"])
    assert "kernel='soft_rods'" in err and "'relative_velocity'" in err


def test_rate_is_an_alias_of_kernel_with_the_same_numbers(capsys):
    rest = ["--density", "2", "--t", "0.5,1", "--json"]
    by_rate = run_json(capsys, [*ULAM, "--rate", "relative_velocity", *rest])
    by_kernel = run_json(capsys, [*ULAM, "--kernel", "relative_velocity", *rest])
    assert by_rate == {**by_kernel, "seconds": by_rate["seconds"]}  # bit for bit
    assert DSMC_KEYS <= by_rate.keys()  # every key written before is still there
    assert by_rate["params"]["rate"] == "relative_velocity" and by_rate["params"]["density"] == 2
    assert by_rate["kernel"] == {"kernel": "relative_velocity", "restitution": 0.5,
                                 "exponent": 1.0}
    text = _help(capsys, ["simulate", "ulam"])
    assert "alias of --kernel (kept for one release)" in " ".join(text.split())
    # a value given to both is refused by the parser
    err = run_error(capsys, [*ULAM, "--kernel", "constant", "--rate", "constant", "--tau", "1"])
    assert "not allowed with" in err


def test_exponent_is_an_option_of_the_relative_velocity_kernel_only(capsys, soft_rods):
    out = run_json(capsys, [*ULAM, "--kernel", "relative_velocity", "--exponent", "0.5",
                            "--t", "1", "--json"])
    assert out["kernel"]["exponent"] == 0.5 and out["params"]["exponent"] == 0.5
    run = simulate(Ulam(200, 0.5, rate=RelativeVelocity(0.5, exponent=0.5)), [1.0], 3,
                   progress=False)
    assert out["energy"] == run.energy.tolist()
    for argv, named in [(["--kernel", "constant", "--exponent", "0.5", "--tau", "1"],
                         "exponent=0.5"),
                        (["--exponent", "0.5", "--tau", "1"], "exponent=0.5"),
                        (["--kernel", "soft_rods", "--exponent", "0.5", "--t", "1"],
                         "exponent=0.5"),
                        (["--kernel", "relative_velocity", "--power", "0.5", "--t", "1"],
                         "power=0.5")]:
        err = run_error(capsys, [*ULAM, *argv])
        assert named in err and "--kernel" in err, err


def test_the_lattice_offers_only_the_kernels_it_carries(capsys, soft_rods):
    text = _help(capsys, ["simulate", "lattice"])
    assert "relative_velocity" in text and "soft_rods" not in text
    assert "alias of --kernel" in " ".join(text.split()) and "--exponent" not in text
    base = ["simulate", "lattice", "--n", "50", "--restitution", "0.5", "--seed", "2"]
    err = run_error(capsys, [*base, "--kernel", "soft_rods", "--t", "1"])
    assert "kernel='soft_rods'" in err
    a = run_json(capsys, [*base, "--rate", "relative_velocity", "--t", "1", "--json"])
    b = run_json(capsys, [*base, "--kernel", "relative_velocity", "--t", "1", "--json"])
    assert a == {**b, "seconds": a["seconds"]} and "t" in a
    assert a["kernel"]["kernel"] == "relative_velocity"
    assert Lattice(50, 0.5, rate="relative_velocity").time_name == "t"
    assert Lattice(50, 0.5).time_name == "tau"


def test_ensemble_takes_kernel_and_its_alias(capsys, tmp_path, soft_rods):
    base = ["ensemble", "ulam", "--n", "60", "--restitution", "0.5", "--t", "0.5", "--seeds",
            "1", "--serial", "--no-progress", "--json"]
    report = run_json(capsys, [*base, "--kernel", "soft_rods", "--power", "0.25,0.5",
                               "--out", str(tmp_path / "a")])
    sets = report["aggregate"]["sets"]
    assert [s["kernel"] for s in sets] == [
        {"kernel": "soft_rods", "restitution": 0.5, "power": p} for p in (0.25, 0.5)]
    assert report["aggregate"]["t"] == [0.5]
    report = run_json(capsys, [*base, "--rate", "relative_velocity",
                               "--out", str(tmp_path / "b")])
    assert report["ok"] and report["aggregate"]["sets"][0]["params"]["rate"] == \
        "relative_velocity"
    err = run_error(capsys, [*base, "--kernel", "nosuch", "--out", str(tmp_path / "c")])
    assert "kernel='nosuch'" in err and not (tmp_path / "c").exists()
