"""The registry of the comparisons: one registration puts a comparison in ``COMPARISONS``,
``PRESETS``, ``VERDICTS``, ``Comparison.figure()`` and ``reproduce``; a name taken by another
comparison is refused; the registry's order is the order ``reproduce`` runs.

The comparison registered here is a toy defined in this file (a straight line of ``n`` points
and one exact claim about it), registered only for the duration of a test (``registered``), so
no other file is touched and the registry is as before afterwards."""

from __future__ import annotations

import matplotlib.figure
import numpy as np
import pytest

from maxwell_kinetics.app import comparisons
from maxwell_kinetics.app.comparisons import (
    COMPARISONS,
    PRESETS,
    REGISTRY,
    VERDICTS,
    Comparison,
    ComparisonSpec,
    comparison_spec,
    register,
    registered,
    unregister,
)
from maxwell_kinetics.app.comparisons.base import jsonable, preset
from maxwell_kinetics.app.comparisons.verdicts import Check, Verdict, judge, with_verdicts
from particles.validation import InvalidArgumentError

#: The comparisons of the paper, in the order ``reproduce`` has always run them, then the ones
#: added after them (13: hard_spheres).
PAPER_ORDER = ["kinetic_theory", "kinetic_vs_ulam", "ulam_collapse", "velocity_distributions",
               "energy_decay", "structure_factors", "velocity_profiles", "sticky_vs_md",
               "late_stage", "tail_exponents", "driven_steady", "rate_vs_correlations",
               "hard_spheres"]

# --------------------------------------------------------------------------- the toy comparison

NAME = "toy_line"

PRESETS_TOY = {"small": {"n": 3, "slope": 2.0}, "default": {"n": 5, "slope": 2.0},
               "full": {"n": 9, "slope": 2.0}}


def toy_verdicts(s: dict) -> list:
    """One exact claim: the fitted slope of the line is the slope it was drawn with."""
    return [judge("the toy line has its slope",
                  Check("fitted slope", s["fitted_slope"], None, s["parameters"]["slope"],
                        "exact: the line's definition", tolerance=1e-9))]


def toy_run(size=None, progress=None, runner=None, **overrides) -> Comparison:
    """A line y = slope·x on ``n`` points, its fitted slope, and the verdict on it."""
    params = preset(PRESETS_TOY, size, overrides)
    x = np.arange(params["n"], dtype=float)
    y = params["slope"] * x
    summary = {"parameters": jsonable(params), "fitted_slope": float(np.polyfit(x, y, 1)[0]),
               "seconds": 0.0}
    return Comparison(NAME, with_verdicts(summary, toy_verdicts), {"x": x, "y": y})


def toy_plot(c, ax=None):
    """The line, on a new figure (or on ``ax[0]``)."""
    if ax is None:
        fig = matplotlib.figure.Figure()
        axis = fig.add_subplot()
    else:
        axis = ax[0]
        fig = axis.figure
    axis.plot(c.data["x"], c.data["y"], label=c.name)
    return fig


#: Between velocity_distributions (4) and energy_decay (5): a number between two places it there.
TOY = ComparisonSpec(NAME, PRESETS_TOY, toy_run, toy_plot, toy_verdicts, order=4.5)


def _lists():
    """Every list the registry feeds, as plain copies."""
    return (dict(REGISTRY), dict(COMPARISONS), dict(PRESETS), dict(VERDICTS))


@pytest.fixture
def toy():
    """The toy comparison, registered for the test and removed after it."""
    before = _lists()
    with registered(TOY) as spec:
        yield spec
    assert _lists() == before
    assert list(COMPARISONS) == list(before[1])


# --------------------------------------------------------------------------- one registration


def test_one_registration_reaches_every_list_and_the_figure(toy):
    assert toy is TOY and REGISTRY[NAME] is TOY and comparison_spec(NAME) is TOY
    assert COMPARISONS[NAME] is toy_run
    assert PRESETS[NAME] is PRESETS_TOY
    assert VERDICTS[NAME] is toy_verdicts
    # at the place of its order: after velocity_distributions, before energy_decay
    names = list(COMPARISONS)
    assert names.index(NAME) == names.index("velocity_distributions") + 1
    assert names.index("energy_decay") == names.index(NAME) + 1
    assert list(PRESETS) == list(VERDICTS) == list(REGISTRY) == names

    result = COMPARISONS[NAME]("small")
    assert result.summary["fitted_slope"] == pytest.approx(2.0)
    (verdict,) = VERDICTS[NAME](result.summary)
    assert isinstance(verdict, Verdict) and verdict.status == "agrees"
    assert result.summary["verdicts"] == [verdict.to_dict()]
    fig = result.figure()
    assert isinstance(fig, matplotlib.figure.Figure)
    np.testing.assert_array_equal(fig.axes[0].lines[0].get_ydata(), [0.0, 2.0, 4.0])


def test_a_saved_toy_redraws_from_its_file(toy, tmp_path):
    toy_run("default").save(tmp_path / "toy.npz")
    loaded = Comparison.load(tmp_path / "toy.npz")
    assert loaded.name == NAME
    assert len(loaded.figure().axes[0].lines[0].get_xdata()) == PRESETS_TOY["default"]["n"]


def test_after_the_block_the_toy_is_gone_everywhere():
    with registered(TOY):
        result = toy_run("small")
    for listing in (REGISTRY, COMPARISONS, PRESETS, VERDICTS):
        assert NAME not in listing
    with pytest.raises(InvalidArgumentError, match=f"name='{NAME}'") as caught:
        result.figure()
    assert "kinetic_theory" in str(caught.value)  # the message lists the registered names


def test_register_and_unregister_by_hand():
    assert register(TOY) is TOY
    try:
        assert register(TOY) is TOY  # the same object again: nothing changes
        assert list(COMPARISONS).count(NAME) == 1
    finally:
        assert unregister(NAME) is TOY
    assert NAME not in COMPARISONS
    with pytest.raises(InvalidArgumentError, match=f"name='{NAME}'"):
        unregister(NAME)


# --------------------------------------------------------------------------- refusals


def other_run(size=None, progress=None, **overrides) -> Comparison:
    """Another comparison's run, under the toy's name."""
    return Comparison(NAME, {}, {})


def test_a_name_registered_twice_with_another_comparison_is_refused(toy):
    other = ComparisonSpec(NAME, PRESETS_TOY, other_run, toy_plot, toy_verdicts, order=4.5)
    before = _lists()
    with pytest.raises(ValueError, match=f"comparison named '{NAME}' is already registered"
                                         r".*toy_run"):
        register(other)
    with pytest.raises(ValueError, match=f"'{NAME}' is already registered"):
        with registered(other):
            pass
    assert _lists() == before and REGISTRY[NAME] is TOY
    # and one of the paper's names as well
    taken = ComparisonSpec("energy_decay", PRESETS_TOY, other_run, toy_plot, toy_verdicts,
                           order=99)
    with pytest.raises(ValueError, match="'energy_decay' is already registered"):
        register(taken)
    assert _lists() == before


def _defined(order):
    """The toy defined again (a notebook cell run twice): a new run of the same qualified name."""
    def run(size=None, progress=None, **overrides):
        return toy_run(size, progress, **overrides)

    return ComparisonSpec(NAME, PRESETS_TOY, run, toy_plot, toy_verdicts, order=order)


def test_a_comparison_defined_again_replaces_itself():
    first, again = _defined(50), _defined(60)
    assert first.run is not again.run
    with registered(first):
        with registered(again):
            assert REGISTRY[NAME] is again and COMPARISONS[NAME] is again.run
        assert REGISTRY[NAME] is first  # the block puts back what it replaced
    assert NAME not in REGISTRY


def test_an_order_taken_by_another_comparison_is_refused():
    at_energy_decay = ComparisonSpec(NAME, PRESETS_TOY, toy_run, toy_plot, toy_verdicts,
                                     order=REGISTRY["energy_decay"].order)
    with pytest.raises(ValueError, match=f"'{NAME}'.*already taken by 'energy_decay'"):
        register(at_energy_decay)
    assert NAME not in REGISTRY


@pytest.mark.parametrize(("change", "match"), [
    ({"name": "toy line"}, "identifier"),
    ({"presets": {"small": {}, "default": {}}}, "presets must map each size"),
    ({"plot": None}, "plot must be callable"),
    ({"verdicts": "no"}, "verdicts must be callable"),
    ({"order": float("nan")}, "order must be a finite number"),
    ({"order": True}, "order must be a finite number"),
])
def test_an_incomplete_comparison_is_refused_when_made(change, match):
    fields = {"name": NAME, "presets": PRESETS_TOY, "run": toy_run, "plot": toy_plot,
              "verdicts": toy_verdicts, "order": 4.5, **change}
    with pytest.raises(TypeError, match=match):
        ComparisonSpec(**fields)
    with pytest.raises(TypeError, match="ComparisonSpec"):
        register(toy_run)


# --------------------------------------------------------------------------- the order


def test_the_registry_order_is_the_order_of_the_paper_and_of_the_lists():
    assert list(REGISTRY) == PAPER_ORDER
    orders = [spec.order for spec in REGISTRY.values()]
    assert orders == sorted(orders) and len(set(orders)) == len(orders)
    assert list(COMPARISONS) == list(PRESETS) == list(VERDICTS) == PAPER_ORDER
    for name, spec in REGISTRY.items():
        assert spec.name == name
        assert COMPARISONS[name] is spec.run and PRESETS[name] is spec.presets
        assert VERDICTS[name] is spec.verdicts
        # the package's function of each comparison is its registered run, and it is public
        assert getattr(comparisons, name) is spec.run and name in comparisons.__all__


def test_reproduce_runs_the_comparisons_in_the_registry_order(toy, monkeypatch, tmp_path):
    """Every registered run replaced by one that records its name and returns the toy (whose
    figure and file cost nothing): ``run_all`` calls them in the registry's order, the toy at
    its place among them, and ``summary.json`` lists them in that order."""
    from maxwell_kinetics.app.reproduce import run_all

    called = []

    def recorder(name):
        def run(size=None, progress=None, **overrides):
            called.append(name)
            return toy_run(size)
        return run

    for name in list(COMPARISONS):
        monkeypatch.setitem(COMPARISONS, name, recorder(name))
    summary = run_all(out=tmp_path, size="small", progress=False)
    assert called == list(REGISTRY) == PAPER_ORDER[:4] + [NAME] + PAPER_ORDER[4:]
    assert list(summary["comparisons"]) == called
