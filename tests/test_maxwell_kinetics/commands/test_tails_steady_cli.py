"""The d-dimensional and driven CLI: ``tail-exponent``, ``steady`` and ``simulate ulam --dimension
--angular --driving`` (numbers against the library and exact values, bad input)."""

import math

import numpy as np
import pytest
from helpers import run_error, run_json

from maxwell_kinetics.driven import steady_kurtosis


@pytest.mark.parametrize("d, angular, s", [(1, "uniform", 1.5), (2, "hard", 2.0)])
def test_tail_exponent_exact_values(capsys, d, angular, s):
    # d = 1: s* = 3/2 for every r (1 − p³ − q³ = 3pq); d = 2, hard model, r = 0: s* = 2 exactly
    angular_option = ["--angular", angular] if d > 1 else []  # refused in d = 1
    out = run_json(capsys, ["tail-exponent", "--dimension", str(d), "-r", "0", *angular_option,
                            "--json"])
    assert out["s"] == pytest.approx(s, abs=1e-9)
    e = out["exponents"]
    assert e["density"] == pytest.approx(d + 2 * s) and e["speed"] == pytest.approx(1 + 2 * s)
    assert e["component"] == e["speed"] and e["density"] - e["speed"] == pytest.approx(d - 1)


def test_steady_json_matches_the_exact_moments(capsys):
    r, D = 0.5, 2.0
    p = (1 + r) / 2
    out = run_json(capsys, ["steady", "-r", str(r), "-D", str(D), "--json"])
    assert out["variance"] == pytest.approx(D / (p * (1 - p)), rel=1e-14)
    assert out["kurtosis"] == pytest.approx(steady_kurtosis(r), rel=1e-14)
    x, P = np.array(out["density"]["x"]), np.array(out["density"]["P"])
    dx = x[1] - x[0]
    assert np.sum(P) * dx == pytest.approx(1.0, abs=1e-9)
    assert np.sum(x * x * P) * dx == pytest.approx(out["variance"], rel=1e-8)


@pytest.mark.parametrize(
    "argv, named",
    [
        (["tail-exponent", "--dimension", "4", "-r", "0.5"], "dimension=4"),
        (["tail-exponent", "--dimension", "0", "-r", "0.5"], "dimension=0"),
        (["tail-exponent", "--dimension", "2", "-r", "0.5", "--angular", "soft"], "angular="),
        (["tail-exponent", "--dimension", "2", "-r", "1.2"], "restitution="),
        (["steady", "-r", "0.5", "-D", "-1"], "driving="),
        (["steady", "-r", "0.5", "-D", "inf"], "driving="),
        (["steady", "-r", "0.5", "-D", "0"], "driving="),
        (["steady", "-r", "1", "-D", "1"], "restitution="),
        (["steady", "-r", "-0.1", "-D", "1"], "restitution="),
        (["simulate", "ulam", "--n", "100", "--restitution", "0.5", "--tau", "1",
          "--dimension", "4"], "dimension="),
        (["simulate", "ulam", "--n", "100", "--restitution", "0.5", "--tau", "1",
          "--dimension", "2", "--angular", "soft"], "angular="),
        (["simulate", "ulam", "--n", "100", "--restitution", "0.5", "--tau", "1",
          "--driving", "-1"], "driving="),
    ],
)
def test_bad_input_exits_2(capsys, tmp_path, argv, named):
    err = run_error(capsys, argv)
    assert named in err


def test_simulate_ulam_in_2d_decays_at_the_rate_of_the_theory(capsys):
    # ⟨|v|²⟩ = d e^{−Λτ N/(N−1)} in expectation (unit variance per component at τ = 0); one run
    # of N = 2e4 has a relative sampling error ≈ sqrt(2 · kurtosis_factor / N) ≲ 2 %: 5 % bound
    from maxwell_kinetics.tails import decay_rate

    out = run_json(capsys, ["simulate", "ulam", "--n", "20000", "--restitution", "0.5",
                            "--tau", "2", "--dimension", "2", "--angular", "hard", "--json"])
    expected = 2 * math.exp(-decay_rate(2, 0.5, "hard") * 2 * 20000 / 19999)
    assert out["energy"][0] == pytest.approx(expected, rel=0.05)
    assert out["params"]["dimension"] == 2 and out["params"]["angular"] == "hard"


def test_solve_in_two_dimensions(capsys):
    # the isotropic solver through the CLI: G(0) = 1 and G''(0) = -1 are kept, so at small q
    # G ≈ 1 - q²/2 (to O(q⁴): 1e-4 at q = 0.1)
    out = run_json(capsys, ["solve", "-r", "0.5", "--tau", "0,2", "--q", "0.1,1",
                            "--resolution", "coarse", "--dimension", "2", "--angular", "hard",
                            "--json", "--no-progress"])
    assert out["dimension"] == 2 and out["angular"] == "hard"
    g_small = out["G_real"][-1][0]
    assert g_small == pytest.approx(1 - 0.005, abs=1e-4)


@pytest.mark.parametrize("extra, named", [(["--dimension", "4"], "dimension="),
                                          (["--dimension", "2", "--angular", "soft"],
                                           "angular=")])
def test_solve_refuses_bad_dimension_or_angular(capsys, extra, named):
    err = run_error(capsys, ["solve", "-r", "0.5", "--tau", "1"] + extra)
    assert named in err
