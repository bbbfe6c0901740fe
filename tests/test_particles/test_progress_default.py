"""One ``progress`` default across the API: a bar in a terminal or a notebook, nothing otherwise."""

import inspect
import io

import pytest

from particles import progress
from particles.driver import simulate
from particles.ensemble import run_ensemble
from particles.lattice import Lattice


def test_the_default_prints_nothing_where_no_bar_can_be_drawn(capsys):
    simulate(Lattice(300, 0.5), [2.0, 9.0], 1)  # stderr captured: not a terminal
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == ""


def test_true_still_prints_plain_lines_for_a_log(capsys):
    simulate(Lattice(300, 0.5), [2.0, 9.0], 1, progress=True)
    assert "lattice" in capsys.readouterr().err


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_the_default_draws_a_bar_on_a_terminal():
    from tqdm import tqdm

    bar = progress.progress_bar(10, "x", enabled=None, stream=_Terminal())
    assert isinstance(bar, tqdm)
    bar.close()
    assert isinstance(progress.progress_bar(10, "x", enabled=None, stream=io.StringIO()),
                      progress.NoProgress)


def test_the_default_draws_tqdms_notebook_widget_in_a_notebook(monkeypatch):
    import tqdm.notebook

    made = []

    class Widget:
        def __init__(self, **kwargs):
            made.append(kwargs)

    monkeypatch.setattr(progress, "in_notebook", lambda: True)
    monkeypatch.setattr(tqdm.notebook, "tqdm", Widget)
    assert isinstance(progress.progress_bar(5, "run", "τ", enabled=None), Widget)
    assert made[0]["total"] == 5.0 and made[0]["desc"] == "run"
    assert isinstance(progress.progress_bar(5, enabled=False), progress.NoProgress)


def test_not_a_notebook_outside_a_kernel():
    assert progress.in_notebook() is False


def test_every_function_with_progress_defaults_to_none():
    from maxwell_kinetics import solve
    from maxwell_kinetics.app import comparisons, convergence
    from maxwell_kinetics.app.comparisons.kinetic_predictions import kinetic_solution

    functions = [simulate, run_ensemble, solve, convergence.convergence_study, kinetic_solution]
    functions += [getattr(comparisons, n) for n in comparisons.__all__
                  if callable(getattr(comparisons, n))]
    checked = 0
    for f in functions:
        try:
            parameter = inspect.signature(f).parameters.get("progress")
        except (TypeError, ValueError):
            continue
        if parameter is not None:
            assert parameter.default is None, f
            checked += 1
    assert checked >= 12


def test_ensemble_progress_must_be_a_bool_or_none(tmp_path):
    from particles.ensemble import EnsembleSpec
    from particles.validation import InvalidArgumentError

    spec = EnsembleSpec(model="ulam", params={"n": 100, "restitution": 0.5}, seeds="1",
                        times=[1.0])
    with pytest.raises(InvalidArgumentError, match="progress='yes'"):
        run_ensemble(spec, tmp_path / "out", executor="serial", progress="yes")
    assert not (tmp_path / "out").exists()


def test_a_plain_solve_prints_nothing_where_no_bar_can_be_drawn(capsys):
    from maxwell_kinetics import solve

    solve(0.5, "gaussian", tau=[0.5], resolution="coarse")
    assert capsys.readouterr().err == ""
    solve(0.5, "gaussian", tau=[0.5], resolution="coarse", progress=True)
    assert "solve r=0.5" in capsys.readouterr().err


@pytest.mark.parametrize("value", ["yes", 1, 0.0])
def test_simulate_progress_must_be_a_bool_or_none(value, capsys):
    from particles.validation import InvalidArgumentError

    with pytest.raises(InvalidArgumentError, match="progress="):
        simulate(Lattice(30, 0.5), [1.0], 1, progress=value)
    assert capsys.readouterr().err == ""


def test_progress_enabled_reads_none_as_a_terminal_or_a_notebook(monkeypatch):
    from particles.progress import progress_enabled

    assert progress_enabled(True) and not progress_enabled(False)
    monkeypatch.setattr("sys.stderr", io.StringIO())  # not a terminal, not a notebook
    assert not progress_enabled(None)

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    monkeypatch.setattr("sys.stderr", Terminal())
    assert progress_enabled(None)


def test_reproduce_run_all_defaults_to_none():
    from maxwell_kinetics.app.reproduce import run_all

    assert inspect.signature(run_all).parameters["progress"].default is None
