"""What a calibration writes: the samples as ArviZ InferenceData (netCDF), the MAP's residual table, a
markdown report with the diagnostics and what the data identify, and two figures (the data against the
posterior predictive band; a corner plot).

Identification is read off the posterior's contraction against the prior, 1 - var_post / var_prior
(Betancourt's posterior contraction): a parameter the data pin down contracts towards 1, one they say
nothing about stays at 0 (its posterior is its prior).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pandas as pd

from friction_sweep.storage import outputs
from friction_sweep.storage.atomic import save_figure, write_text

from .fit import MapFit
from .inference import import_arviz
from .model import ForwardModel
from .posterior import Posterior
from .sampler import Chains

OUTPUT_FILES = ("posterior.nc", "map.csv", "report.md", "predictive.png", "corner.png")
#: contraction thresholds: at least IDENTIFIED is identified, below NOT_IDENTIFIED is not
IDENTIFIED = 0.5
NOT_IDENTIFIED = 0.1
FIGURE_DPI = 130
#: the report's section on the sampler (benchmarks/calibration_report.py copies it into the README)
SAMPLER_TITLE = "Sampler diagnostics (emcee, differential-evolution moves, walkers started from the prior)"
#: points along r of the predictive band's curves
CURVE_POINTS = 80
#: draws from the priors in the InferenceData's `prior` group (no model evaluations: cheap)
PRIOR_DRAWS = 1000


def unit_of(model: ForwardModel, kind: str) -> str:
    """The unit a parameter is reported in (as the spec's priors are read: SI, degrees)."""
    if kind == "natural_frequency":
        return "Hz" if model.spec.reference_frequency is not None else "1"
    if kind == "friction_force":
        return "N"
    return "degree" if kind in ("noise_phase", "discrepancy_phase") else "1"


def verdict(contraction: float) -> str:
    if contraction >= IDENTIFIED:
        return "identified"
    return "weakly identified" if contraction >= NOT_IDENTIFIED else "not identified"


def summary(model: ForwardModel, fit: MapFit, chains: Chains) -> pd.DataFrame:
    """One row per parameter: MAP, posterior median and 95 % interval, prior, contraction, verdict, tau, ESS."""
    flat = chains.samples.reshape(-1, model.ndim)
    rows = []
    for i, p in enumerate(model.parameters):
        lo, med, hi = np.percentile(flat[:, i], [2.5, 50.0, 97.5])
        prior_sd = p.prior.std()
        contraction = 1.0 - float(np.var(flat[:, i])) / prior_sd**2 if prior_sd > 0 else math.nan
        rows.append({"parameter": p.name, "unit": unit_of(model, p.kind), "map": fit.theta[i], "median": med,
                     "ci95_low": lo, "ci95_high": hi, "prior": p.prior.describe(), "prior_sd": prior_sd,
                     "posterior_sd": float(np.std(flat[:, i])), "contraction": contraction,
                     "identification": verdict(contraction), "tau": chains.tau[i], "ess": chains.ess[i],
                     "walker_rhat": chains.rhat[i]})
    return pd.DataFrame(rows)


def residual_stats(table: pd.DataFrame, fitted: bool) -> dict[str, float]:
    """RMS and max |phase residual| (degrees) over the fitted rows (or the held-out ones)."""
    if "phase_residual_deg" not in table:
        return {}
    d = table.loc[table["fitted"] == fitted, "phase_residual_deg"].to_numpy(float)
    d = d[np.isfinite(d)]
    if not d.size:
        return {}
    return {"rms_deg": float(np.sqrt(np.mean(d**2))), "max_deg": float(np.max(np.abs(d))), "rows": int(d.size)}


def predictive(post: Posterior, chains: Chains, draws: int, seed: int) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """`draws` posterior vectors and, at every row, the model's values there (phase with the offset) and
    replicated data (with the noise): {'phase_model', 'phase', 'transmissibility_model', 'transmissibility'}."""
    rng = np.random.default_rng(seed + 1)
    flat = chains.samples.reshape(-1, post.model.ndim)
    theta = flat[rng.choice(flat.shape[0], size=min(draws, flat.shape[0]), replace=False)]
    predicted = post.model.predict(theta)
    out = {}
    obs = post.model.obs
    if obs.phase is not None:
        model_phase = predicted["phase"] + post.offset(theta)[:, None]
        kappa = 1.0 / np.radians(post.phase_sd(theta)) ** 2
        noise = np.degrees(rng.vonmises(0.0, kappa))
        out["phase_model"] = model_phase
        out["phase"] = np.mod(model_phase + noise + 90.0, 360.0) - 90.0
    if obs.transmissibility is not None:
        sd = post.sd(theta, "transmissibility")
        out["transmissibility_model"] = predicted["transmissibility"]
        out["transmissibility"] = predicted["transmissibility"] * np.exp(sd * rng.standard_normal(sd.shape))
    return theta, out


def inference_data(post: Posterior, chains: Chains, replicated, map_theta: np.ndarray, *, seed: int, run: dict,
                   provenance: dict):
    """ArviZ InferenceData in ArviZ's conventions, walkers as chains:

    * posterior, prior (PRIOR_DRAWS draws from the priors, one chain): per-series parameters on dim
      `series`; each posterior variable carries its units, prior and diagnostics (emcee's autocorrelation
      time, the ensemble's effective sample size, the walkers' R-hat, the MAP) as attributes, once;
    * log_likelihood: each sample's log likelihood of every fitted row, per measured quantity (what
      az.loo, az.waic and az.compare read), on dim `row` (the fitted rows' lines);
    * sample_stats: `lp` (the log posterior) and `acceptance_rate` (1 where the step's proposal was
      accepted, else 0: an ensemble move's acceptance, one draw at a time); the run's settings and
      convergence (`run`) as the group's attributes;
    * observed_data, posterior_predictive (replicated data) and constant_data (each row's frequency and
      force ratio as the data give them, its series and whether it was fitted) on dim `row` = the data
      file's line;
    * the file's own attributes (`provenance`): title, history, Conventions, the spec.
    """
    import xarray as xr

    az = import_arviz()
    model = post.model
    obs = model.obs

    def grouped(values: np.ndarray) -> tuple[dict[str, np.ndarray], dict[str, list[str]]]:
        """(chain, draw, parameter) values as one array per parameter kind, per-series ones on `series`."""
        out: dict[str, np.ndarray] = {}
        dims: dict[str, list[str]] = {}
        for kind in dict.fromkeys(p.kind for p in model.parameters):
            idx = [i for i, p in enumerate(model.parameters) if p.kind == kind]
            if model.parameters[idx[0]].series >= 0:
                out[kind], dims[kind] = values[:, :, idx], ["series"]
            else:
                out[kind] = values[:, :, idx[0]]
        return out, dims

    posterior, dims = grouped(chains.samples)
    rng = np.random.default_rng(seed + 2)  # predictive() draws from seed + 1
    prior, _ = grouped(np.column_stack([p.prior.sample(rng, PRIOR_DRAWS) for p in model.parameters])[None])
    observed = {name: getattr(obs, name) for name in obs.measured}
    constant = {"frequency_ratio": obs.frequency_ratio, "force_ratio": obs.force_ratio,
                "series_index": obs.series.astype(np.int64), "fitted": obs.fitted.astype(np.int8)}
    for name in (*replicated, *observed, *constant):
        dims[name] = ["row"]
    idata = az.from_dict(
        posterior=posterior,
        prior=prior,
        posterior_predictive={name: values[None, :, :] for name, values in replicated.items()},
        observed_data=observed,
        constant_data=constant,
        sample_stats={"lp": chains.log_posterior, "acceptance_rate": chains.accepted.astype(np.float64)},
        coords={"series": list(obs.series_labels), "row": obs.lines.tolist()},
        dims=dims,
    )
    fitted_rows = obs.lines[obs.fitted].tolist()  # the likelihood's rows: held-out rows are predicted only
    idata.add_groups(log_likelihood=xr.Dataset(
        {name: (("chain", "draw", "row"), chains.pointwise[:, :, q, :]) for q, name in enumerate(obs.measured)},
        coords={"chain": idata.posterior["chain"].values, "draw": idata.posterior["draw"].values,
                "row": fitted_rows}))
    diagnostics = {"autocorr_time": chains.tau, "effective_sample_size": chains.ess, "walker_rhat": chains.rhat,
                   "map": np.asarray(map_theta, dtype=np.float64)}
    for kind in posterior:
        idx = [i for i, p in enumerate(model.parameters) if p.kind == kind]
        unit = unit_of(model, kind)
        for group in (idata.posterior, idata.prior):
            group[kind].attrs.update(units=unit, prior=model.parameters[idx[0]].prior.describe(unit))
        for key, values in diagnostics.items():
            idata.posterior[kind].attrs[key] = values[idx] if len(idx) > 1 or kind in dims else float(values[idx[0]])
    constant_meaning = {
        "frequency_ratio": "frequency ratio of the row as the data give it (the model's: this x f_ref / f_n, f_n "
                           "the natural_frequency parameter where it is one)",
        "force_ratio": "force ratio of the row as the data give it (the model's: scaled or per series by the "
                       "friction parameter)",
        "series_index": "the row's series, an index into the coordinate `series`",
        "fitted": "1: the row enters the likelihood; 0: held out (predicted only)",
    }
    for name, meaning in constant_meaning.items():
        idata.constant_data[name].attrs.update(long_name=meaning, units="1")
    idata.sample_stats.attrs.update(run)
    idata.attrs = provenance
    return idata


def markdown(model: ForwardModel, chains: Chains, params: pd.DataFrame, table: pd.DataFrame,
             timing: dict[str, float], data_path: str) -> str:
    fitted, held = residual_stats(table, True), residual_stats(table, False)
    lines = [
        "# Calibration",
        "",
        f"Data: `{data_path}` ({model.obs.size} rows, {int(model.obs.fitted.sum())} fitted), scene "
        f"`{model.excitation}`, method `{model.method}`.",
        "",
        "## Parameters",
        "",
        "| parameter | unit | MAP | median | 95 % interval | prior | contraction | data say | tau | ESS |",
        "|---|---|---:|---:|---|---|---:|---|---:|---:|",
    ]
    for _, p in params.iterrows():
        lines.append(f"| {p['parameter']} | {p['unit']} | {p['map']:.5g} | {p['median']:.5g} | "
                     f"[{p['ci95_low']:.5g}, {p['ci95_high']:.5g}] | {p['prior']} | {p['contraction']:.2f} | "
                     f"{p['identification']} | {p['tau']:.1f} | {p['ess']:.0f} |")
    lines += [
        "",
        f"Contraction 1 − var(posterior)/var(prior): {IDENTIFIED} and above identified, below "
        f"{NOT_IDENTIFIED} not identified (the posterior is the prior).",
        "",
        f"## {SAMPLER_TITLE}",
        "",
        "| walkers | steps | burn-in | largest tau | kept run / tau | smallest ESS | walkers' R-hat | acceptance "
        "| converged |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---|",
        f"| {chains.samples.shape[0]} | {chains.steps} | {chains.burn} | {np.max(chains.tau):.1f} | "
        f"{chains.length_in_tau:.0f} | {np.min(chains.ess):.0f} | {np.max(chains.rhat):.3f} | "
        f"{chains.acceptance:.2f} | "
        f"{'yes' if chains.converged else 'NO: max_steps reached'} |",
        "",
        "## Fit",
        "",
    ]
    if fitted:
        lines.append(f"MAP phase residuals, fitted rows: RMS {fitted['rms_deg']:.2f}°, max {fitted['max_deg']:.2f}° "
                     f"({fitted['rows']} rows).")
    if held:
        lines.append(f"Held-out rows (predicted, not fitted): RMS {held['rms_deg']:.2f}°, max {held['max_deg']:.2f}° "
                     f"({held['rows']} rows).")
    lines += [
        "",
        f"Time: MAP {timing['map']:.1f} s, sampling {timing['sampling']:.1f} s, whole run {timing['total']:.1f} s; "
        f"{timing['rate']:.0f} model evaluations (parameter vectors, {model.obs.size} rows each) per second "
        "while sampling.",
        "",
        "## MAP residuals",
        "",
        _table_md(table),
        "",
    ]
    return "\n".join(lines)


def _table_md(table: pd.DataFrame) -> str:
    cols = list(table.columns)
    out = ["| " + " | ".join(cols) + " |", "|" + "|".join("---" for _ in cols) + "|"]
    for _, row in table.iterrows():
        out.append("| " + " | ".join(f"{v:.4g}" if isinstance(v, float) else str(v) for v in row) + " |")
    return "\n".join(out)


def predictive_figure(post: Posterior, theta: np.ndarray):
    """Measured phases (or transmissibilities) against r at the reference natural frequency, one colour per
    series, over the posterior's 95 % band of the model curve (noise-free) and its median."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    model = post.model
    obs = model.obs
    quantity = "phase" if obs.phase is not None else "transmissibility"
    fig, ax = plt.subplots(figsize=(8, 5), constrained_layout=True)
    colours = plt.get_cmap("viridis")(np.linspace(0.0, 0.85, len(obs.series_labels)))
    lo, hi = float(obs.frequency_ratio.min()), float(obs.frequency_ratio.max())
    grid = np.linspace(lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo), CURVE_POINTS)
    for s, (label, colour) in enumerate(zip(obs.series_labels, colours, strict=True)):
        rows = obs.series == s
        beta0 = float(obs.force_ratio[rows][0])
        dense = dataclasses.replace(obs, frequency_ratio=grid, force_ratio=np.full(grid.size, beta0),
                                    series=np.full(grid.size, s), lines=np.zeros(grid.size, dtype=int),
                                    phase=np.zeros(grid.size) if obs.phase is not None else None,
                                    transmissibility=np.ones(grid.size) if obs.transmissibility is not None else None,
                                    phase_sd=None, transmissibility_sd=None, fitted=np.ones(grid.size, dtype=bool))
        curves = ForwardModel(model.spec, dense, jobs=model.jobs)
        values = curves.predict(theta)[quantity]
        if quantity == "phase":
            values = values + post.offset(theta)[:, None]
        # where no draw has a value (theory off continuous motion) the band has none: no curve drawn there
        band = np.full((3, grid.size), np.nan)
        some = np.isfinite(values).any(axis=0)
        band[:, some] = np.nanpercentile(values[:, some], [2.5, 50.0, 97.5], axis=0)
        ax.fill_between(grid, band[0], band[2], color=colour, alpha=0.25, lw=0)
        ax.plot(grid, band[1], color=colour, lw=1.2)
        marker = np.where(obs.fitted[rows], "o", "s")
        for m in ("o", "s"):
            sel = marker == m
            if sel.any():
                ax.plot(obs.frequency_ratio[rows][sel], getattr(obs, quantity)[rows][sel], m, color=colour, ms=6,
                        mfc=colour if m == "o" else "none",
                        label=f"series {label}" + ("" if m == "o" else " (held out)"))
    reference = "f_n as the spec states it" if model.spec.reference_frequency is not None else "the data's own"
    ax.set(xlabel=f"frequency ratio r (at {reference})",
           ylabel="first-harmonic phase lag (degree)" if quantity == "phase" else "transmissibility",
           title=f"Data against the posterior's 95 % band ({model.method} model)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return fig


def corner_figure(model: ForwardModel, chains: Chains, fit: MapFit):
    """A corner plot: each parameter's marginal histogram on the diagonal (prior density dashed), each pair's
    2-D histogram below it, the MAP marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    flat = chains.samples.reshape(-1, model.ndim)
    n = model.ndim
    fig, axes = plt.subplots(n, n, figsize=(1.7 * n + 1, 1.7 * n + 1), squeeze=False)
    labels = [f"{p.name}\n[{unit_of(model, p.kind)}]" for p in model.parameters]
    for i in range(n):
        for j in range(n):
            ax = axes[i, j]
            if j > i:
                ax.set_visible(False)
                continue
            if i == j:
                ax.hist(flat[:, i], bins=40, density=True, color="tab:blue", alpha=0.6)
                lo, hi = ax.get_xlim()
                x = np.linspace(lo, hi, 200)
                ax.plot(x, np.exp(model.parameters[i].prior.logpdf(x)), "k--", lw=0.8)
                ax.axvline(fit.theta[i], color="tab:red", lw=0.8)
                ax.set_yticks([])
            else:
                ax.hist2d(flat[:, j], flat[:, i], bins=40, cmap="Blues")
                ax.plot(fit.theta[j], fit.theta[i], "+", color="tab:red", ms=8)
            if i == n - 1:
                ax.set_xlabel(labels[j], fontsize=7)
            else:
                ax.set_xticklabels([])
            if j == 0 and i > 0:
                ax.set_ylabel(labels[i], fontsize=7)
            elif j > 0:
                ax.set_yticklabels([])
            ax.tick_params(labelsize=6)
    fig.suptitle("Posterior: marginals (prior dashed), pairs; MAP in red")
    fig.tight_layout()
    return fig


def write(folder: Path, idata, table: pd.DataFrame, md: str, figures, *, overwrite: bool = True) -> list[Path]:
    """Every output file into `folder`, all or none (outputs.write_all); without `overwrite`, none
    replaces a file."""
    paths = [folder / name for name in OUTPUT_FILES]
    predictive_fig, corner_fig = figures
    return outputs.write_all([
        (paths[0], lambda tmp: idata.to_netcdf(str(tmp), engine="h5netcdf")),
        (paths[1], lambda tmp: write_text(tmp, table.to_csv(index=False, float_format="%.10g"))),
        (paths[2], lambda tmp: write_text(tmp, md)),
        (paths[3], lambda tmp: save_figure(predictive_fig, tmp, dpi=FIGURE_DPI)),
        (paths[4], lambda tmp: save_figure(corner_fig, tmp, dpi=FIGURE_DPI)),
    ], overwrite=overwrite)
