"""The explanation checks of two comparisons, on synthetic summaries and spectra (no runs, no
solves): Haff's law of MD explained by its departure from the hard-rod Boltzmann equation
(``energy_decay``), and the measured drift of the MD collapse exponent within one run
(``structure_factors``).  The verdict tests are exact arithmetic on made-up numbers; the drift
test builds spectra that collapse exactly with a known z on each pair of times."""

from __future__ import annotations

import numpy as np
import pytest

from maxwell_kinetics.app.comparisons import VERDICTS, z_drift


def _energy_summary(md_slope, md_sigma, boltzmann_slope=-2.025, ratio=(1.0, 0.01)):
    """An energy_decay summary with only what its verdicts read; the other three fits agree
    exactly with their expected values."""
    def fit(slope, sigma, expected, window):
        return {"slope": [slope, sigma], "uncertainty": sigma, "expected": expected,
                "window": list(window)}

    s = {"parameters": {"restitution": 0.5},
         "md_haff_exponent": fit(md_slope, md_sigma, -2.0, (0.3, 2.0)),
         "md_late_exponent": fit(-2 / 3, 0.1, -2 / 3, (25.0, 100.0)),
         "lattice_initial_rate": fit(-0.375, 0.01, -0.375, (0.0, 0.25)),
         "lattice_late_exponent": fit(-0.5, 0.005, -0.5, (100.0, 2000.0))}
    if boltzmann_slope is not None:
        s["boltzmann_haff_exponent"] = {"slope": boltzmann_slope, "expected": -2.0,
                                        "window": [0.3, 2.0]}
    if ratio is not None:  # E of MD over E of the Boltzmann equation, at the window's ends
        s["md_energy_over_boltzmann"] = {"times": [0.35, 1.6],
                                         "ratio": [[1.0, 0.01], list(ratio)]}
    return s


def _haff_verdict(summary):
    return VERDICTS["energy_decay"](summary)[0].to_dict()


def test_haff_is_explained_when_md_has_left_molecular_chaos_in_the_window():
    """MD slope −1.775 ± 0.0625 (3σ = 0.1875) is 0.225 from −2 (fails); MD's E over the
    Boltzmann E at the window's end, 1.125 ± 0.0078125, is 16σ above 1 (the explanation
    holds); the Boltzmann slope is shown in the words."""
    v = _haff_verdict(_energy_summary(-1.775, 0.0625, ratio=(1.125, 0.0078125)))
    assert v["status"] == "explained"
    assert v["explanation"]["holds"] and v["explanation"]["measured"] == 1.125
    assert v["explanation"]["source"].startswith("model:") and "-2.025" in v["why"]


@pytest.mark.parametrize("ratio", [(1.0, 0.01), (1.0234375, 0.0078125)])
def test_haff_explanation_needs_a_departure_from_molecular_chaos_of_3_sigma(ratio):
    """The ratio at 1 (MD still follows molecular chaos: nothing explains the failed slope, it
    disagrees) and exactly 3σ = 0.0234375 away (binary-exact numbers: the edge explains)."""
    v = _haff_verdict(_energy_summary(-1.5, 0.0625, ratio=ratio))
    assert v["status"] == ("disagrees" if ratio[0] == 1.0 else "explained")
    assert v["explanation"]["holds"] is (ratio[0] != 1.0)


def test_haff_agrees_whatever_the_ratio():
    v = _haff_verdict(_energy_summary(-1.9375, 0.0625, ratio=(1.5, 0.01)))
    assert v["status"] == "agrees"


def test_a_summary_without_the_ratio_has_no_explanation():
    v = _haff_verdict(_energy_summary(-1.5, 0.0625, ratio=None))
    assert v["status"] == "disagrees" and v["explanation"] is None


def test_the_drift_measures_the_exponent_of_each_pair_of_times():
    """S(k, t_i) = f(k a_i) with a₁/a₀ = (t₁/t₀)^0.9 and a₂/a₁ = (t₂/t₁)^0.6 collapses exactly
    with z = 0.9 on the early pair and 0.6 on the late one; each of 3 seeds multiplies S by
    its own constant (1, 1.5, 2), the same at every time, so that the collapse stays exact for
    every jackknife replica: the z are those to the Brent search's 1e-5 (tolerance 1e-3), and
    their jackknife errors small."""
    times = np.array([10.0, 20.0, 40.0])
    a = np.array([1.0, 2.0**0.9, 2.0**0.9 * 2.0**0.6])
    k = np.geomspace(1e-3, 3.0, 600)

    def f(x):
        return 1.0 / (1.0 + x**2)

    spec = np.array([[c * f(k * ai) for ai in a] for c in (1.0, 1.5, 2.0)])
    zs = np.round(np.arange(0.0, 1.0001, 0.01), 2)
    out = z_drift(k, spec, times, zs, (0.5, 15.0))
    assert out["pair_times"] == [[10.0, 20.0], [20.0, 40.0]]
    assert out["z_best_early_pair"][0] == pytest.approx(0.9, abs=1e-3)
    assert out["z_best_late_pair"][0] == pytest.approx(0.6, abs=1e-3)
    assert out["z_drift"][0] == pytest.approx(-0.3, abs=2e-3)
    assert all(out[key][1] < 1e-3 for key in ("z_best_early_pair", "z_best_late_pair",
                                              "z_drift"))
