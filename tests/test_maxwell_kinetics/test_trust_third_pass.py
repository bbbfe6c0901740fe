"""Hostile input to the library, third pass: every refusal is an InvalidArgumentError naming the
argument and showing the value received, raised before any expensive work."""

from __future__ import annotations

import os

import numpy as np
import pytest

from maxwell_kinetics import compile_cache
from maxwell_kinetics import inelastic_boltzmann as ib
from maxwell_kinetics import velocity_grid as vg
from particles.validation import InvalidArgumentError


def _no_work(*args, **kwargs):
    raise AssertionError("the relaxation started instead of being refused")


@pytest.fixture
def no_relaxation(monkeypatch):
    monkeypatch.setattr(ib, "tables_for", _no_work)


def test_a_relaxation_past_the_integrators_steps_is_refused_first(no_relaxation):
    with pytest.raises(InvalidArgumentError, match=r"relaxation=100000\.0.*time steps"):
        ib.scaling_state(0.5, relaxation=1e5)


def test_a_relaxation_of_more_than_a_day_is_refused_unless_forced(no_relaxation):
    grid = vg.VelocityGrid(1601, 12.0)
    with pytest.raises(InvalidArgumentError, match=r"relaxation=1000\.0.*86400 s"):
        ib.scaling_state(0.5, grid=grid, relaxation=1000)
    with pytest.raises(InvalidArgumentError, match="force='no'"):
        ib.scaling_state(0.5, grid=grid, relaxation=1000, force="no")
    # the estimate reads the rate: a larger exponent takes more steps on the same grid
    kernel = ib.kernel_of(0.5, 1.0)
    assert ib.relaxation_steps(kernel, grid, 10.0) < ib.relaxation_steps(
        ib.kernel_of(0.5, 2.0), grid, 10.0)


@pytest.mark.parametrize("path", [123, True, "", "   ", b"folder"])
def test_compile_cache_enable_refuses_what_is_not_a_folder(path, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    before = compile_cache.current_choice()
    try:
        with pytest.raises(InvalidArgumentError, match="argument path="):
            compile_cache.enable(path)
    finally:
        compile_cache.restore_choice(before)
    assert os.listdir(tmp_path) == []


@pytest.mark.parametrize("half_width", [1e300, 1e31, float(np.finfo(float).max)])
def test_an_absurd_mapped_half_width_is_blamed_on_the_half_width(half_width):
    with pytest.raises(InvalidArgumentError, match="argument half_width="):
        vg.MappedGrid(161, half_width, 0.07)
