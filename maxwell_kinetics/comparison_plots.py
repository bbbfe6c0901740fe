"""Figures of the comparisons in :mod:`maxwell_kinetics.comparisons` (matplotlib, Agg).

``plot(comparison)`` dispatches on ``comparison.name`` and returns a ``Figure``.
"""

from __future__ import annotations

import numpy as np

from .comparisons import block_means, velocity_on_grid
from .exact import f_density, f_hat
from .plotting import _figure

__all__ = ["plot"]


def plot(comparison):
    return _PLOTS[comparison.name](comparison)


def _colors(n):
    import matplotlib

    return matplotlib.colormaps["viridis"](np.linspace(0, 0.9, max(n, 1)))


def _kinetic_theory(c):
    d, s = c.data, c.summary
    sol = d["solution"]
    fig, axes = _figure(4, width=4.2)
    a0, a1, a2, a3 = axes[0]
    q = sol.q
    show = (q > 1e-2) & (q < 20)
    cols = _colors(len(sol.tau))
    for k, tau in enumerate(sol.tau):
        a0.plot(q[show], sol.G[k, show].real, color=cols[k], label=f"τ={tau:g}")
    a0.plot(q[show], f_hat(q[show]), "k--", label="f̂")
    a0.set(xscale="log", xlabel="q", ylabel="G(q, τ)", title="G → f̂")
    a0.legend(fontsize=6)
    tau = np.asarray(s["tau"])
    pos = tau > 0
    a1.semilogy(tau[pos], np.asarray(s["sup_error"])[pos], "k-o", ms=3, label="sup|G − f̂|")
    for i, (sv, dist) in enumerate(d["distances"].items()):
        a1.semilogy(tau[pos], dist[pos], "-", color=f"C{i}", label=f"d_{sv}")
        a1.semilogy(tau[pos], d["bounds"][sv][pos], ":", color=f"C{i}",
                    label=f"bound e^(−γτ) d_{sv}(0)")
    a1.set(xscale="log", xlabel="τ", ylabel="distance to f̂",
           title="distances and contraction bounds")
    a1.legend(fontsize=6)
    for n in (4, 6, 8):
        a2.semilogy(d["moment_tau"], d["moments"][:, n], label=f"M_{n}/M_2^{n // 2}")
    a2.set(xlabel="τ", ylabel="M_n / M_2^(n/2)", title="multiscaling of the moments")
    a2.legend(fontsize=7)
    x = d["x"]
    for k in range(len(sol.tau)):
        pk = d["density"][k]
        ok = pk > 1e-14
        a3.loglog(x[ok], pk[ok], color=cols[k])
    a3.loglog(x, f_density(x), "k--", label="f = 2/(π(1+x²)²)")
    a3.loglog(x, 0.05 * x**-4.0, "k:", label="x⁻⁴")
    a3.set(ylim=(1e-10, 1), xlabel="x = v/v0", ylabel="P(x, τ)", title="the x⁻⁴ tail")
    a3.legend(fontsize=7)
    fig.tight_layout()
    return fig


def _kinetic_vs_ulam(c):
    """One panel per case: the solver's inverse-FFT P(x, τ) as lines, the pooled Ulam histogram
    as open markers with ±1 standard error (seed scatter); per-τ χ²/(dof·φ) in a legend below
    the panel.  Last panel: the KS distance against N."""
    from matplotlib.lines import Line2D

    d = c.data
    cases = d["cases"]
    fig, axes = _figure(len(cases) + 1, width=4.0, height=5.2)
    for ax, case in zip(axes[0], cases, strict=False):
        cols = _colors(len(case["rows"]))
        handles = []
        for i, row in enumerate(case["rows"]):
            h = row["comparison"]
            ax.plot(row["fft"]["x"], row["fft"]["density"], "-", color=cols[i], lw=1.2, zorder=2)
            ax.errorbar(h.centres, h.density, yerr=h.error, fmt="o", ms=3.5, mfc="white",
                        mew=0.8, elinewidth=0.8, capsize=1.5, color=cols[i], zorder=3)
            handles.append(Line2D([], [], color=cols[i], marker="o", mfc="white", lw=1.2,
                                  label=f"τ = {row['tau']:g}:  χ²/(dof·φ) "
                                  f"{row['chi2_over_overdispersion']:.2f}, smoothed "
                                  f"{row['smoothed']['chi2_over_overdispersion']:.2f}"))
        handles += [Line2D([], [], color="k", lw=1.2, label="solver, inverse FFT of G"),
                    Line2D([], [], color="k", marker="o", mfc="white", ls="none",
                           label="Ulam particles ± 1 s.e.")]
        ax.set(xlabel="x = v/v0", ylabel="P(x, τ)",
               title=f"r = {case['restitution']:g}, {case['initial']} initial law")
        ax.legend(handles=handles, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.13),
                  frameon=False)
    ax = axes[0][-1]
    n = d["scan_n"]
    ax.errorbar(n, d["scan_ks"], yerr=d["scan_ks_error"], fmt="o", label="mean KS distance")
    slope, icpt = d["scan_fit"]
    ax.loglog(n, np.exp(icpt) * n**slope, "k-", label=f"fit slope {slope:.3f}")
    ax.loglog(n, 0.8687 / np.sqrt(n), "k:", label="0.87/√N (iid)")
    ax.set(xscale="log", yscale="log", xlabel="N", ylabel="D_KS", title="distance against N")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.13), frameon=False)
    fig.tight_layout()
    return fig


def _ulam_collapse(c):
    """Left: the median-rescaled histograms (the ones the χ² check uses) against f.  Middle: their
    tail, |x| in log bins with at least 5 pooled counts, against f and x⁻⁴.  Right: the
    deviation from f per bin in standard errors, median-rescaled (filled) and rescaled by the
    run's own v0 (open, the paper's v/v0, which a finite sample of an x⁻⁴ law biases)."""
    d = c.data
    fig, axes = _figure(3, width=4.8, height=5.0)
    lin, lg, dev = axes[0]
    x = np.linspace(d["edges"][0], d["edges"][-1], 400)
    for i, (row, h, hs, tail) in enumerate(zip(d["rows"], d["histograms"],
                                               d["shape_histograms"], d["tails"], strict=True)):
        lab = f"r={row['restitution']:g}, τ={row['tau']:g}"
        chi_m = row["median_scaled"]["chi2_over_overdispersion"]
        chi_v = row["v0_scaled"]["chi2_over_overdispersion"]
        lin.errorbar(hs.centres, hs.density, yerr=hs.error, fmt="o", ms=3, mfc="white",
                     color=f"C{i}", label=f"{lab}: χ²/(dof·φ) {chi_m:.2f}")
        ok = tail["counts"] >= 5
        lg.errorbar(tail["centres"][ok], tail["density"][ok], yerr=tail["error"][ok], fmt="o",
                    ms=3, mfc="white", color=f"C{i}", label=lab)
        for hh, style, name, chi in ((hs, "o", "median", chi_m), (h, "s", "v/v0", chi_v)):
            good = hh.error > 0
            dev.plot(hh.centres[good], (hh.density - hh.predicted)[good] / hh.error[good], style,
                     ms=3.5, color=f"C{i}", mfc=f"C{i}" if name == "median" else "white",
                     label=f"{lab}, {name}: {chi:.2f}")
    lin.plot(x, f_density(x), "k-", lw=1, label="f(x) = 2/(π(1+x²)²)")
    xmax = max(float(t["centres"][t["counts"] >= 5].max()) for t in d["tails"])
    xp = np.geomspace(0.05, 1.5 * xmax, 200)
    lg.loglog(xp, f_density(xp), "k-", lw=1, label="f(x)")
    lg.loglog(xp[xp > 3], 2.0 / np.pi * xp[xp > 3] ** -4.0, "k:", label="2/(π x⁴)")
    dev.axhline(0.0, color="k", lw=0.8)
    for y in (-2.0, 2.0):
        dev.axhline(y, color="k", lw=0.5, ls=":")
    lin.set(xlabel="x (median |x| set to f's)", ylabel="P(x)",
            title="Ulam collapse onto f (paper Fig. 2)")
    lg.set(xlabel="|x| (median-rescaled)", ylabel="P(x)", title="log-log: the x⁻⁴ tail",
           xlim=(0.04, 1.5 * xmax))
    dev.set(xlabel="x", ylabel="(P − f) / standard error",
            title="deviation from f: median (filled), v/v0 (open)")
    lin.legend(fontsize=7)
    lg.legend(fontsize=7, loc="lower left")
    dev.legend(fontsize=6.5, ncol=2, loc="upper center", bbox_to_anchor=(0.5, -0.13),
               frameon=False, title="χ²/(dof·φ)", title_fontsize=7)
    fig.tight_layout()
    return fig


def _energy_decay(c):
    """E(t) of each MD run and E(τ) of each lattice run with the theory curves, and every fit
    drawn over its window (shaded): the line of the seeds' mean ln E, whose slope is the
    reported mean of the per-seed slopes."""
    d, s = c.data, c.summary
    fig, axes = _figure(2, width=5.5, height=4.4)
    a, b = axes[0]
    r = d["restitution"]
    t, e = d["md_t"], d["md_energy"]
    t0 = d["t0"]
    fits = d["fits"]

    def label(name, key, expected):
        res = s[key]
        return (f"{name} fit on [{res['window'][0]:g}, {res['window'][1]:g}]: "
                f"{res['slope'][0]:.3f} ± {res['uncertainty']:.3f} ({expected})")

    def shade(ax, fit, color):  # the recorded times inside the window (τ = 0 is off the axis)
        clock = fit["clock"][fit["clock"] > 0]
        ax.axvspan(clock[0], clock[-1], color=color, alpha=0.12, lw=0)

    for i in range(e.shape[0]):
        a.loglog(t, e[i], color="C0", alpha=0.6, lw=1, label="MD runs" if i == 0 else None)
    a.loglog(t, 1.0 / (1.0 + t / t0) ** 2, "k--", lw=1, label="Haff (1 + t/t₀)⁻²")
    f = fits["md_haff"]
    a.loglog(f["clock"], np.exp(f["intercept"]) * (1.0 + f["clock"] / t0) ** f["slope"], "-",
             color="C3", lw=2.5, label=label("Haff", "md_haff_exponent", "−2"))
    shade(a, f, "C3")
    f = fits["md_late"]
    a.loglog(f["clock"], np.exp(f["intercept"]) * f["clock"] ** f["slope"], "-", color="C2",
             lw=2.5, label=label("late", "md_late_exponent", "−2/3"))
    shade(a, f, "C2")
    a.set(xlabel="t", ylabel="E(t)", title=f"MD, r = {r:g}")
    a.legend(fontsize=7, loc="lower left")
    tau, el = d["lattice_tau"], d["lattice_energy"]
    for i in range(el.shape[0]):
        b.loglog(tau, el[i], color="C1", alpha=0.6, lw=1, label="lattice runs" if i == 0 else None)
    b.loglog(tau, np.exp(-(1 - r**2) / 2 * tau), "k--", lw=1, label="exp(−(1−r²)τ/2)")
    f = fits["lattice_early"]
    ce = f["clock"][f["clock"] > 0]
    b.loglog(ce, np.exp(f["intercept"] + f["slope"] * ce + f.get("curvature", 0.0) * ce**2),
             "-", color="C3", lw=2.5,
             label=label("initial rate", "lattice_initial_rate", f"{-(1 - r**2) / 2:g}"))
    shade(b, f, "C3")
    f = fits["lattice_late"]
    b.loglog(f["clock"], np.exp(f["intercept"]) * f["clock"] ** f["slope"], "-", color="C2",
             lw=2.5, label=label("late", "lattice_late_exponent", "−1/2"))
    shade(b, f, "C2")
    b.set(ylim=(el.min() / 2, 1.5), xlabel="τ", ylabel="E(τ)", title=f"lattice, r = {r:g}")
    b.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    return fig


def _structure_factors(c):
    """S(k) of the seed mean against scaled k per time; the fitted Porod line (seed-mean
    spectrum at the last time, over the log bins of the fit window) drawn on its window with
    its slope, and a k⁻² reference below it."""
    from particles.observables import log_bin

    from .comparisons import porod_fit

    d = c.data
    labels = ("md", "lattice", "lattice_no_constraint")
    titles = ("MD: S vs k t^(2/3)", "lattice: S vs k τ^(1/2)", "lattice, no constraint")
    clock = {"md": "t", "lattice": "τ", "lattice_no_constraint": "τ"}
    fig, axes = _figure(3, width=4.2, height=4.4)
    for ax, lab, title in zip(axes[0], labels, titles, strict=True):
        dd = d[lab]
        z = dd["z"]
        cols = _colors(len(dd["times"]))
        for i, t in enumerate(dd["times"]):
            kb, sb, _ = log_bin(dd["k"], dd["S"][i], 10)
            ax.loglog(kb * t**z, sb, "o-", ms=2, lw=0.8, color=cols[i],
                      label=f"{clock[lab]} = {t:.0f}")
        s = c.summary[lab]
        window, k_max = s["porod_window"]["x"], s["porod_window"]["k_max"]
        t_last = dd["times"][-1]
        fit = porod_fit(dd["k"], dd["S"][-1], t_last, z, window, k_max)
        if fit is not None:
            slope, icpt, kf = fit
            kl = np.array([kf[0], kf[-1]])
            err = (s["porod_slope_per_time"][-1] or [None, None])[1]
            pm = f" ± {err:.2f}" if err is not None else ""
            ax.loglog(kl * t_last**z, np.exp(icpt) * kl**slope, "r-", lw=2.5, alpha=0.8,
                      label=f"fit at {clock[lab]} = {t_last:.0f}: slope {slope:.2f}{pm}")
            ax.loglog(kl * t_last**z, 0.3 * np.exp(icpt) * kl[0] ** (slope + 2.0) * kl**-2.0,
                      "k:", lw=1, label="k⁻² (reference)")
        ax.axvspan(*window, color="0.9", zorder=0, label="Porod fit window")
        ax.set(xlabel=f"k {clock[lab]}^{z:.3g}" if lab != "md" else "k t^(2/3)",
               ylabel="S(k)",
               title=f"{title}\nspread {s['collapse_spread_at_z_theory'][0]:.2f}"
               f" (unscaled {s['collapse_spread_unscaled'][0]:.2f})")
        ax.legend(fontsize=6, loc="lower left")
    fig.tight_layout()
    return fig


def _velocity_distributions(c):
    d = c.data
    edges = d["edges"]
    centres = 0.5 * (edges[1:] + edges[:-1])
    fig, axes = _figure(2, width=5.0)
    xf = np.linspace(edges[0], edges[-1], 400)
    for ax, stage in zip(axes[0], ("early", "late"), strict=True):
        st = d["stages"][stage]
        for i, (name, m) in enumerate(st["models"].items()):
            k, ke = m["kurtosis"]
            ax.errorbar(centres, m["_density"], yerr=m["_density_error"], fmt=".-", ms=3, lw=0.8,
                        color=f"C{i}", label=f"{name}: ⟨x⁴⟩={k:.2f}±{ke or 0:.2f}")
        ax.plot(xf, f_density(xf), "k--", lw=1, label="Ulam τ→∞: f(x)")
        ax.plot(xf, np.exp(-xf**2 / 2) / np.sqrt(2 * np.pi), "k:", lw=1, label="Gaussian")
        info = st["info"]
        ax.set(xlabel="x = (v − ⟨v⟩)/v0", ylabel="P(x)",
               title=f"{stage}: MD t={info['md_time']:g}, equal energy E={info['energy']:.3g}")
        ax.legend(fontsize=6)
    fig.tight_layout()
    return fig


def _velocity_profiles(c):
    d, s = c.data, c.summary
    fig, axes = _figure(4, width=4.5)
    a, b, e, f = axes[0]
    n = d["md_v"].size
    n_show = min(5000, n)
    coarse = s.get("coarse_skewness")
    m = 64 if n >= 64 * 64 else 1  # the overlaid block means
    grid = np.arange(n) * (d["length"] / n)
    vx = velocity_on_grid(d["md_x"], d["md_v"], d["length"])
    curves = ((a, grid, vx, "C0"), (b, np.arange(n), d["md_v"], "C0"),
              (e, np.arange(d["lattice_v"].size), d["lattice_v"], "C1"))
    for ax, xs, vs, color in curves:
        ax.plot(xs[:n_show], vs[:n_show], ".-", ms=1, lw=0.3, color=color, alpha=0.6)
        if m > 1:
            ax.plot(block_means(xs[:n_show], m), block_means(vs[:n_show], m), "k-", lw=1.2,
                    label=f"means of {m}")
            ax.legend(fontsize=7, loc="lower right")
    sk = s["increment_skewness"]

    def title(key):
        raw = f"raw skewness {sk[key]['skewness'][0]:.2f}"
        if coarse is None or len(coarse[key]["scales"]) < 2:
            return raw
        top = coarse[key]
        return f"{raw}, m={top['scales'][-1]}: {top['skewness'][-1][0]:+.2f}"

    a.set(xlabel="x (grid of spacing L/N)", ylabel="v",
          title=f"MD v(x, t={d['md_time']:g})\n{title('md_vx')}")
    b.set(xlabel="label i", ylabel="v", title=f"MD v(i, t)\n{title('md_vi')}")
    e.set(xlabel="site i", ylabel="v",
          title=f"lattice v(i, τ={d['lattice_tau']:.0f})\n{title('lattice_vi')}")
    if coarse is not None:
        labels = {"md_vx": ("MD v(x)", "C0", "s"), "md_vi": ("MD v(i)", "C2", "o"),
                  "lattice_vi": ("lattice v(i)", "C1", "^")}
        for key, (label, color, marker) in labels.items():
            ms_ = np.asarray(coarse[key]["scales"], dtype=float)
            val = np.array([v for v, _ in coarse[key]["skewness"]])
            err = np.array([0.0 if e_ is None else e_ for _, e_ in coarse[key]["skewness"]])
            f.errorbar(ms_, val, yerr=err, color=color, marker=marker, ms=4, capsize=2,
                       label=label)
        f.axhline(0.0, color="k", lw=0.5)
        f.set(xscale="log", xlabel="coarse-graining m (labels, sites, L/N)",
              ylabel="skewness of increments",
              title="sign of the large gradients\n(mean ± s.e. over seeds)")
        f.legend(fontsize=7)
    else:
        f.set_axis_off()
    fig.tight_layout()
    return fig


_PLOTS = {
    "kinetic_theory": _kinetic_theory,
    "kinetic_vs_ulam": _kinetic_vs_ulam,
    "ulam_collapse": _ulam_collapse,
    "energy_decay": _energy_decay,
    "structure_factors": _structure_factors,
    "velocity_distributions": _velocity_distributions,
    "velocity_profiles": _velocity_profiles,
}
