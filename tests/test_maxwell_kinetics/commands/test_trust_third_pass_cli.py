"""Hostile input to the command line, third pass: a refusal names the option the user typed and
shows the text typed, before any expensive work."""

from __future__ import annotations

import math

import pytest
from helpers import run_error

from particles.kernels import RelativeVelocity
from particles.validation import check_restitution

#: The kernel's name as the command line takes it (the registry's, never typed again here).
KERNEL = RelativeVelocity.name


@pytest.mark.parametrize("option", [["--resolution", "coarse"], ["--dimension", "2"],
                                    ["--q", "1"], ["--angular", "hard"]])
def test_a_fourier_option_with_a_kernel_of_time_t_names_that_kernel(capsys, option):
    err = run_error(capsys, ["solve", "-r", "0.5", "--kernel", KERNEL, "--t", "1",
                             "--no-progress", *option])
    assert f"no --{option[0][2:]} with --kernel {KERNEL}" in err, err


def test_fixed_point_refuses_a_relaxation_of_more_than_a_day_on_its_grid(capsys, monkeypatch):
    from maxwell_kinetics import inelastic_boltzmann

    def no_work(*args, **kwargs):
        raise AssertionError("the relaxation started instead of being refused")

    monkeypatch.setattr(inelastic_boltzmann, "tables_for", no_work)
    # r = 0.99 relaxes to tau' = 1000 by default; on 1601 points that is ~1e5 s, so the grid,
    # the only choice on the command line, is named, with --force
    err = run_error(capsys, ["fixed-point", "-r", "0.99", "--kernel", KERNEL,
                             "--points", "1601", "--half-width", "12"])
    assert "argument points='1601' is invalid" in err and "--force" in err, err


def test_a_negative_zero_restitution_is_zero():
    assert math.copysign(1.0, check_restitution("-0.0")) == 1.0
    assert math.copysign(1.0, check_restitution(-0.0)) == 1.0
