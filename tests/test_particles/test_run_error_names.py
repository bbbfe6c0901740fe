"""The run driver's refusals (particles.driver.run) name what the user typed, the keyword of
``simulate`` or of the engine, with the command-line option beside it, and show the value
received: not the engine's internal stop grid (``stop_step=4.0`` for a run of Ulam that was
given only its times), not the engine's time name (``tau=``, ``t=``) for ``times``, not
``True`` for ``structure_factor="last"``."""

from __future__ import annotations

import pytest
from helpers import run_error

from particles import Lattice, MDEngine, Ulam, simulate
from particles.md import MDParams
from particles.validation import InvalidArgumentError


@pytest.mark.parametrize("engine, option", [(Ulam(n=2, restitution=0.5), "--tau"),
                                            (Lattice(10, 0.5), "--tau")])
def test_too_many_stops_of_a_fixed_stop_grid_name_the_times(engine, option):
    with pytest.raises(InvalidArgumentError) as info:
        simulate(engine, [0.0, 1e8], 1, progress=False)
    assert info.value.name == "times" and info.value.value == [0.0, 1e8]
    message = str(info.value)
    assert "argument times=[0.0, 100000000.0]" in message and option in message
    assert "stop_step" not in message and "--force" in message


def test_too_many_stops_of_a_chosen_stop_step_name_stop_step():
    engine = MDEngine(MDParams(50, 1.0, 0.9), stop_step=1e-9)
    with pytest.raises(InvalidArgumentError, match=r"argument stop_step=1e-09 .*--stop-step"):
        simulate(engine, [0.0, 1.0], 1, progress=False)


def test_the_command_line_names_the_time_option_not_the_stop_grid(capsys):
    err = run_error(capsys, ["simulate", "ulam", "--n", "2", "--restitution", "0.5",
                             "--tau", "0,1e8"])
    assert "argument times=[0.0, 100000000.0]" in err and "(--tau)" in err
    assert "stop_step" not in err


@pytest.mark.parametrize("engine", [Ulam(n=10, restitution=0.5),
                                    MDEngine(MDParams(100, 1.0, 0.5, delta=1e-3))])
@pytest.mark.parametrize("times", [[1.0, 0.5], [-1.0]])
def test_bad_times_are_named_times_as_typed(engine, times):
    with pytest.raises(InvalidArgumentError, match=rf"argument times=\[{times[0]}"):
        simulate(engine, times, 0, progress=False)


@pytest.mark.parametrize("given", ["last", "all", True])
def test_structure_factor_in_d_2_shows_the_value_received(given):
    engine = Ulam(n=10, restitution=0.5, dimension=2)
    with pytest.raises(InvalidArgumentError) as info:
        simulate(engine, [1.0], 0, progress=False, structure_factor=given)
    assert info.value.name == "structure_factor" and info.value.value == given
    assert f"argument structure_factor={given!r}" in str(info.value)
    assert "--structure-factor" in str(info.value)


def test_snapshots_in_d_2_show_the_value_received():
    engine = Ulam(n=10, restitution=0.5, dimension=2)
    with pytest.raises(InvalidArgumentError, match="argument snapshots=1 "):
        simulate(engine, [1.0], 0, progress=False, snapshots=1)


def test_an_engine_whose_stop_grid_has_a_zero_step_is_refused_by_name():
    class ZeroStep(Ulam):
        stop_step = 0.0  # an engine's own grid (a class attribute, as the lattice's)

    with pytest.raises(InvalidArgumentError, match=r"argument engine=.*ZeroStep.*stop_step"):
        simulate(ZeroStep(n=10, restitution=0.5), [1.0], 0, progress=False)
