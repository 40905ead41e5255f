"""A blade with an under-platform damper (issue 31, configs/blade_damper.yaml; the README's worked example):
the response of the blade's tip (the cube's first mass) against the excitation's angular frequency at
several normal loads on the damper (friction_scale: the load over its nominal one), with the linear limits
dashed: no damper (every contact free) and the damper stuck to the platform (every contact stuck), both
exact (friction_sweep.structures.linear); each contact's regime over the (frequency, normal load) plane,
with the frequency of the tip's peak at each load; and the resonance peak against the normal load, each
located exactly between the grid's frequencies, with the load that minimises it found to 1e-8 (fs.optimize
on the spec the cube recorded).

    python figures/blade_damper.py results/blade_damper.nc figures/out/blade_damper.png
"""

import common as C
import numpy as np

from friction_sweep import quicklook
from friction_sweep.structures import linear, recorded

#: normal loads drawn as curves: the lightest, the heaviest, the optimum and these shares of the range
CURVES = 6


def optimum(ds, dof: str):
    """fs.optimize on the spec the cube recorded, its peak taken of `dof`: the exact performance curve over the
    cube's friction scales and the optimum (friction_sweep.design.structure)."""
    from ruamel.yaml import YAML

    import friction_sweep as fs

    spec = YAML(typ="safe").load(ds.attrs["spec"])
    spec["settings"] = {**(spec.get("settings") or {}), "peak_dof": dof}
    return fs.optimize(spec)


def chosen(n: int, best: int) -> list[int]:
    """CURVES friction-scale indices spread over the range, the optimum among them."""
    picks = {int(i) for i in np.rint(np.linspace(0, n - 1, CURVES - 1))} | {best}
    return sorted(picks)


def main(argv=None):
    (path,), out = C.parse_args(argv, "python figures/blade_damper.py CUBE.nc OUT.png", n_inputs=1)
    ds = C.open_cube(path)
    C.require(ds, path, "amplitude", "regime")
    if "structure" not in ds.attrs:
        raise SystemExit(f"{path}: not a structure cube (no structure attribute)")
    a = recorded.assembled(ds)
    tip = str(ds["dof"].values[0])
    w, s = ds["frequency"].values.astype(float), ds["friction_scale"].values.astype(float)
    opt = optimum(ds, tip)
    peak, where = opt.resonance_peak.values, opt.resonance_frequency.values
    s_opt, p_opt, w_opt = (float(opt[f"optimum_{k}"]) for k in ("friction_scale", "peak", "frequency"))
    best = int(np.argmin(np.abs(s - s_opt)))  # the grid's load nearest the optimum, drawn as a curve
    fine = np.linspace(w[0], w[-1], 20 * w.size)  # the linear limits are closed forms: drawn smooth
    i_tip = a.dof_names.index(tip)
    limits = {}
    for name, solve in (("no damper (contact free)", linear.free_response),
                        ("damper stuck", linear.stuck_response)):
        values = [solve(a, float(x)) for x in fine]
        limits[name] = np.array([np.nan if v is None else abs(v[i_tip]) for v in values])

    contacts = [str(c) for c in ds["contact"].values]
    fig, axes = C.new_figure(2 + len(contacts), 1, size=(7.4, 4.2 + 2.6 * (1 + len(contacts))),
                             gridspec_kw={"height_ratios": [3.2, *[2.2] * len(contacts), 2.2]})
    ax = axes[0, 0]
    rows = chosen(s.size, best)
    palette = C.colors(len(rows))
    amp = ds["amplitude"].sel(dof=tip).transpose("friction_scale", "frequency").values
    for i, colour in zip(rows, palette, strict=True):
        label = f"load {s[i]:g}" + (" (nearest the optimum)" if i == best else "")
        ax.plot(w, amp[i], "-", color=colour, lw=2.2 if i == best else 1.3, label=label)
    for (name, values), style in zip(limits.items(), ("--", ":"), strict=True):
        ax.plot(fine, values, style, color="k", lw=1.0, label=f"linear: {name}")
    ax.set_yscale(quicklook.choose_yscale(amp[rows]))
    ax.set(xlabel=r"angular frequency $\omega$", ylabel=f"first-harmonic amplitude of the {tip}",
           xlim=(w[0], w[-1]), title=f"the {tip}'s response at several normal loads")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))

    for k, name in enumerate(contacts):
        mesh = axes[1 + k, 0]
        patches = quicklook.regime_mesh(mesh, w, s, ds["regime"].sel(contact=name).transpose("friction_scale",
                                                                                               "frequency"),
                                        f"regime {name}")
        (line,) = mesh.plot(where, s, "k.-", ms=4, lw=0.9, label=f"the {tip}'s peak")
        mesh.axhline(s_opt, color="k", lw=0.8, ls="--")
        mesh.set(xlabel=r"angular frequency $\omega$", ylabel="normal load / nominal",
                 title=f"regime of contact {name!r}")
        mesh.legend(handles=[*patches, line], loc="upper left", bbox_to_anchor=(1.01, 1.0))

    ax = axes[-1, 0]
    ax.plot(s, peak, "o-", color="C0", ms=3, label=f"peak amplitude of the {tip} (exact)")
    ax.plot([s_opt], [p_opt], "*", color="C3", ms=12,
            label=f"optimum: {p_opt:.4g} at load {s_opt:.6g}, $\\omega$ = {w_opt:.4g}")
    for (name, values), style in zip(limits.items(), ("--", ":"), strict=True):
        ax.axhline(np.nanmax(values), color="k", ls=style, lw=1.0, label=f"linear peak: {name}")
    ax.set_yscale(quicklook.choose_yscale(peak))
    ax.set(xlabel="normal load / nominal (friction_scale)", ylabel="resonance peak",
           title="where the peak is smallest")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.suptitle("A blade with an under-platform damper (configs/blade_damper.yaml)")
    C.save(fig, out)


if __name__ == "__main__":
    main()
