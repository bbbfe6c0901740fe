"""Comparison 13, hard_spheres, at the small size (d = 2, α = 0.5, the coarse grid, 8 DSMC runs
of N = 2·10⁴): its verdicts, their power against a planted 2 % error of the solver or of the
DSMC, the Maxwell model's exact cooling-state a₂, and the save/load round trip."""

from __future__ import annotations

import math

import numpy as np
import pytest

from maxwell_kinetics import sphere_spectral
from maxwell_kinetics.app.comparisons import VERDICTS, Comparison
from maxwell_kinetics.app.comparisons import _hard_spheres as hard_spheres
from particles import hard_sphere_dsmc, sphere_observables
from particles.sphere_kernels import VariableHardSpheres


@pytest.fixture(scope="module")
def small(comparison):
    return comparison("hard_spheres")


def _status(summary, short_prefix):
    found = [v for v in summary["verdicts"] if v["short"].startswith(short_prefix)]
    assert len(found) == 1, [v["short"] for v in summary["verdicts"]]
    return found[0]


def test_the_small_run_agrees_and_leaves_the_cooling_state_to_the_default_size(small):
    s = small.summary
    statuses = {v["short"]: v["status"] for v in s["verdicts"]}
    assert "disagrees" not in statuses.values(), statuses
    assert _status(s, "d=2: HCS a₂ solver = DSMC")["status"] == "not measured"
    for v in s["verdicts"]:  # every check says where its σ comes from and its dof
        if v["measured"] is None and v["sigma"] is None:  # a tail not measured: no σ at all
            continue
        assert "seeds" in v["sigma_source"] and v["combined_dof"] == 7, v
    row = s["rows"][0]
    # the solver's T and a₂ at the three early times: the grid error (the distance to the
    # R = 6.5 grid) is far below the DSMC's standard error, so the tolerance is the seeds'
    assert max(row["grid_error_T"]) < 0.2 * min(m[1] for m in row["dsmc_T"])
    # Haff's law with the first-order a₂ correction is within 2e-4 of the solver's own T at
    # t ≤ 0.4 (the neglected terms of order a₂², a₃; the DSMC's σ of T is 8e-4)
    assert max(abs(x - 1) for x in row["solver_T_over_corrected_haff"]) < 2e-4


def test_the_maxwell_cooling_state_a2_is_its_moment_equations_fixed_point():
    # The closed moment equations against the kernel's own collision map: d⟨|v|⁴⟩/dt =
    # E[|v′|⁴ − |v|⁴] = k₄M₄ + k₀E² for any isotropic law of zero mean, measured by Monte Carlo
    # for two laws of different kurtosis (Gaussian, and a Gaussian scale mixture), which gives
    # k₄ and k₀; their cooling-state a₂ against maxwell_hcs_a2.  Tolerance: 4 standard errors
    # of the Monte Carlo estimate, propagated by sampling k₄, k₀ from their estimated errors.
    rng = np.random.default_rng(7)
    alpha, m = 0.5, 400_000
    for d in (2, 3):
        kernel = VariableHardSpheres(alpha, exponent=0.0)
        rows, rhs = [], []
        for scale_law in ("gaussian", "mixture"):
            s = (np.ones(m) if scale_law == "gaussian"
                 else np.where(rng.random(m) < 0.5, 0.6, 1.3))
            v = rng.standard_normal((m, d)) * s[:, None]
            w = rng.standard_normal((m, d)) * rng.permutation(s)[:, None]
            sigma = rng.standard_normal((m, d))
            sigma /= np.linalg.norm(sigma, axis=1)[:, None]
            v1, _ = kernel.post_collision(v, w, direction=sigma)
            change = np.sum(v1 * v1, axis=1) ** 2 - np.sum(v * v, axis=1) ** 2
            energy = np.mean(np.sum(v * v, axis=1))
            m4 = np.mean(np.sum(v * v, axis=1) ** 2)
            rows.append((m4, energy**2))
            rhs.append((change.mean(), change.std() / math.sqrt(m)))
        A = np.array(rows)
        k4, k0 = np.linalg.solve(A, [r[0] for r in rhs])
        mu = (1 - alpha**2) / 2
        a2 = d / (d + 2) * (-k0 / (k4 + mu)) - 1
        draws = rng.standard_normal((2000, 2)) * [r[1] for r in rhs] + [r[0] for r in rhs]
        ks = np.linalg.solve(A, draws.T)
        spread = np.std(d / (d + 2) * (-ks[1] / (ks[0] + mu)) - 1)
        assert abs(a2 - sphere_observables.maxwell_hcs_a2(alpha, d)) < 4 * spread, (d, a2, spread)
        assert -(k4 + mu) == pytest.approx(sphere_observables.maxwell_a2_relaxation(alpha, d),
                                           abs=4 * spread)
    assert sphere_observables.maxwell_hcs_a2(alpha, 3) == pytest.approx(2 / 7, rel=1e-12)


def _planted(monkeypatch, solver=1.0, dsmc=1.0):
    """The small run with the solver's or the DSMC's density (its collision rate) × factor."""
    solve, engine = sphere_spectral.solve_spheres, hard_sphere_dsmc.SphereDSMC
    monkeypatch.setattr(sphere_spectral, "solve_spheres",
                        lambda *a, **k: solve(*a, density=solver, **k))
    monkeypatch.setattr(hard_sphere_dsmc, "SphereDSMC",
                        lambda n, r, dimension: engine(n, r, dimension=dimension, density=dsmc))
    # the cooling-state window cut to 4 collisions per particle: the early times alone are
    # judged here, and the window is most of the DSMC's cost
    return hard_spheres.run("small", progress=False, window=(4,))


@pytest.mark.parametrize("plant", [{"solver": 0.98}, {"dsmc": 1.02}], ids=["solver", "dsmc"])
def test_a_two_percent_rate_error_of_either_side_disagrees(monkeypatch, plant):
    # A collision rate 2 % off moves T(0.4) by about 1.6 % (4 standard errors of the 8 seeds'
    # mean of N = 2·10⁴, 8.4e-4); the errors are planted against the sign of the small run's
    # own deviation (solver T 1.3e-3 below the DSMC's), the harder direction.  Both grids move
    # together, so the grid error does not absorb the plant.
    planted = _planted(monkeypatch, **plant)
    verdict = _status(planted.summary, "d=2: solver T(t) = DSMC")
    assert verdict["status"] == "disagrees", verdict


def test_a_wrong_cooling_state_disagrees_and_a_first_sonine_failure_is_refuted(small):
    # The verdicts read only the summary: the solver's cooling state planted 5 standard errors
    # of the DSMC's away from it (two grids computed, grid error 0), and the DSMC's a₂ planted
    # at 6 standard errors from the first Sonine value with a₃ resolved from 0.
    s = {**small.summary, "rows": [dict(r) for r in small.summary["rows"]]}
    row = s["rows"][0]
    hcs, err = row["dsmc_hcs_a2"]
    row.update(hcs_grids=2, hcs_grid_error_a2=0.0, solver_hcs_a2=hcs + 5 * err)
    fs = row["first_sonine_a2"]
    row["dsmc_hcs_a2_vs_first_sonine"] = [-6 * err / fs, err / fs]
    records = {v.short: v.status for v in VERDICTS["hard_spheres"](s)}
    assert records["d=2: HCS a₂ solver = DSMC"] == "disagrees"
    assert records["d=2: HCS a₂ = first Sonine"] == "refuted"
    row["dsmc_hcs_a3"] = [0.0, 1e-3]  # no cause shown: a plain disagreement
    records = {v.short: v.status for v in VERDICTS["hard_spheres"](s)}
    assert records["d=2: HCS a₂ = first Sonine"] == "disagrees"


def test_save_load_round_trip_and_figure(small, tmp_path):
    path = tmp_path / "hard_spheres.npz"
    small.save(path)
    back = Comparison.load(path)
    assert back.name == "hard_spheres" and back.summary == small.summary
    np.testing.assert_array_equal(back.data["curves"][0]["solver_a2"],
                                  small.data["curves"][0]["solver_a2"])
    fig = back.figure()
    assert len(fig.axes) == 3
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert labels == ["d = 2: solver", "d = 2: DSMC ± 1 s.e."]
