"""compare_histograms on samples of a known law: its χ² (Histogram.distance with Pearson's
variance) has mean 1 per degree of freedom under the null hypothesis, and φ is 1 for
independent samples."""

import math

import numpy as np
from scipy.special import ndtr

from maxwell_kinetics import statistics as st


def test_chi2_dof_and_overdispersion_are_1_for_independent_samples_of_the_law():
    # 200 repetitions of R = 4 runs of M = 2000 N(0, 1) samples on 24 bins (every bin ≥ 13
    # expected pooled counts, so dof = 24).  The mean of 200 χ²/dof is 1 within
    # 4 · √(2/24) / √200 = 0.082 (4 standard errors); φ's mean over 200 repetitions is 1 within
    # 4 · (its own standard error √(2/(3·25)) / √200) = 0.046 (25 bins with ≥ 5 expected per
    # run: 24 and the mass outside).
    rng = np.random.default_rng(2024)
    edges = np.linspace(-3.0, 3.0, 25)
    prob = np.diff(ndtr(edges))
    chi2, phi = [], []
    for _ in range(200):
        cmp = st.compare_histograms(rng.standard_normal((4, 2000)), edges, prob)
        chi2.append(cmp.chi2_dof)
        phi.append(cmp.overdispersion)
    assert cmp.dof == 24 and cmp.runs == 4 and cmp.samples == 2000
    assert abs(np.mean(chi2) - 1.0) < 4 * math.sqrt(2 / 24) / math.sqrt(200)
    assert abs(np.mean(phi) - 1.0) < 4 * math.sqrt(2 / (3 * 25)) / math.sqrt(200)


def test_a_wrong_law_is_far_outside():
    # N(0, 1.1²) samples against N(0, 1): 8000 samples resolve the 10 % width easily
    rng = np.random.default_rng(7)
    edges = np.linspace(-3.0, 3.0, 25)
    cmp = st.compare_histograms(1.1 * rng.standard_normal((4, 2000)), edges,
                                np.diff(ndtr(edges)))
    assert cmp.chi2_dof > 1 + 10 * math.sqrt(2 / cmp.dof)
