"""Whole-plane consistency rules for a structure cube (`fsweep check` on a cube of several masses and
contacts, issue 31; DESIGN §7), each a statement the exact steady state satisfies, judged from the cube's
own variables and the structure it records (structures.recorded), with no kernel loaded:

    unsettled     every point settled: each contact has a regime (as the 1-DoF rule)
    free_limit    at friction_scale 0 the structure is linear: the first harmonic of every mass is
                  X = (K - w^2 M + i w C)^-1 f, f = F (force) or Y (K_b + i w C_b) (base), to FREE_RTOL
    stuck_limit   where every contact is stuck the whole period the structure is linear with the contacts
                  stuck (rigid ones as constraints, Jenkins ones as their springs; structures.linear), to
                  STUCK_RTOL
    bound         each contact's force is at most its static friction s mu_s_j, so its first harmonic at most
                  (4/pi) s mu_s_j, and with H = (K - w^2 M + i w C)^-1:
                  |X_i| <= |(H f)_i| + sum_j |(H w_j)_i| (4/pi) s mu_s_j   (BOUND_RTOL slack)
    energy        per forcing period, the forcing's work pi F.Xs (force excitation, Xs the sine part of the
                  first harmonic) equals the contacts' friction energy plus the viscous dissipation
                  oint x'^T C x' dt, which is at least its first harmonic's share pi w (Xc^T C Xc + Xs^T C Xs)
                  (Parseval; C >= 0): an equality without dashpots, an inequality with them (ENERGY_RTOL).
                  Under base excitation a contact to the moving base does work the cube does not record:
                  those cubes are skipped; without one the forcing's work is pi Y (K_b.Xs + w C_b.Xc)
    harmonics     (outputs: harmonics) the exact harmonics' X_1 is the first harmonic that amplitude and phase
                  give (two integrations of one orbit: closed form, Gauss-Legendre; HARMONICS_RTOL), and
                  each contact's force, at most s mu_s_j in size, has |F_0| <= s mu_s_j and
                  |F_k| <= (4/pi) s mu_s_j for k >= 1 (the square wave's, the largest a bounded force has)
    history       (outputs: time_history) every stored orbit's contact forces stay within their static band,
                  |lambda_j| <= s mu_s_j at the history point's friction_scale s (HARMONICS_RTOL slack)

Each rule holds at any steady state, so where static friction gave the cube the states from a moving start
too (`*_moving` variables) every rule runs on those again (its name with the suffix `_moving`).

Amplitudes in the cube are over `amplitude_unit` (Y for base excitation); phases are lags behind the
excitation, so the complex first harmonic is X = |X| (cos phi - i sin phi) for x = Re(X e^{i w t}).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from friction_sweep import codes
from friction_sweep.codes import Regime, SteadyState
from friction_sweep.consistency import (
    FAILED,
    MAX_EXAMPLES,
    OK,
    PARTIAL,
    SKIPPED,
    CubeError,
    Finding,
    _value,
    moving_twin,
)
from friction_sweep.storage.schema import MOVING_SUFFIX
from friction_sweep.structures.linear import compliances, forcing, free_response, stuck_response
from friction_sweep.structures.model import Assembled
from friction_sweep.theory.phase import complex_amplitude

#: rule `free_limit`: |X_cube - X_linear| <= FREE_RTOL max_i |X_linear_i| (the engine is exact to rounding;
#: its tests hold it to 1e-12)
FREE_RTOL = 1e-8
#: rule `stuck_limit`: the same against the stuck structure
STUCK_RTOL = 1e-8
#: rule `bound`: slack on the proven bound, relative to its largest mass's (rounding of the measured first
#: harmonic)
BOUND_RTOL = 1e-6
#: rule `energy`: relative slack on the balance (the engine measures its work integrals by quadrature)
ENERGY_RTOL = 1e-6
#: rule `harmonics`: X_1 against amplitude and phase, relative to the point's largest |X| (both exact to rounding;
#: their tests hold them to 1e-12), and the slack on the force bound
HARMONICS_RTOL = 1e-9
PLANE = ("friction_scale", "frequency")


class _Tally:
    """Counts violations and keeps the first examples, in order of frequency then friction scale."""

    def __init__(self, ds: xr.Dataset):
        self.s = ds["friction_scale"].values.astype(float)
        self.w = ds["frequency"].values.astype(float)
        self.count = 0
        self.found: list[tuple[int, int, str, object, object]] = []

    def add(self, i: int, k: int, where: str, found, expected) -> None:
        self.count += 1
        self.found.append((k, i, where, found, expected))

    def finding(self, rule: str, checked: int, note: str = "", partial: bool = False) -> Finding:
        examples = [{"frequency": float(self.w[k]), "friction_scale": float(self.s[i]), **({"at": at} if at else {}),
                     "found": _value(f), "expected": _value(e)}
                    for k, i, at, f, e in sorted(self.found, key=lambda x: (x[0], x[1]))[:MAX_EXAMPLES]]
        status = FAILED if self.count else PARTIAL if partial else OK
        return Finding(rule, status, int(checked), self.count, examples, note)


def _plane(ds: xr.Dataset, name: str) -> np.ndarray | None:
    """A variable on (friction_scale, frequency[, dof or contact]), or None where the cube lacks it."""
    if name not in ds.data_vars:
        return None
    da = ds[name]
    return np.asarray(da.transpose(*PLANE, *[d for d in da.dims if d not in PLANE]).values)


def _settled(ds: xr.Dataset) -> np.ndarray:
    """(n_s, n_w): the points whose steady-state search converged (all points where the cube does not say)."""
    steady = _plane(ds, "steady_state")
    shape = (ds.sizes["friction_scale"], ds.sizes["frequency"])
    return np.ones(shape, bool) if steady is None else steady == SteadyState.CONVERGED


def harmonics(ds: xr.Dataset, a: Assembled) -> np.ndarray | None:
    """(n_s, n_w, n) complex first harmonics X (x = Re(X e^{iwt})) in the structure's length unit, from
    amplitude and phase; None without amplitude. Without phase: |X| only (real)."""
    amp = _plane(ds, "amplitude")
    if amp is None:
        return None
    amp = amp.astype(float) * a.amplitude_unit
    phase = _plane(ds, "phase")
    if phase is None:
        return amp.astype(complex)
    return complex_amplitude(amp, phase)


def check_unsettled(ds: xr.Dataset, a: Assembled) -> Finding:
    """Rule `unsettled`: every point has a settled regime at every contact (why it stopped, where not)."""
    regime = _plane(ds, "regime")
    if regime is None:
        return Finding("unsettled", SKIPPED, note="no regime")
    steady = _plane(ds, "steady_state")
    tally = _Tally(ds)
    for i, k in np.argwhere((regime == Regime.UNSETTLED).any(axis=-1)):
        names = [a.contact_names[j] for j in np.flatnonzero(regime[i, k] == Regime.UNSETTLED)]
        why = "" if steady is None else f" ({codes.name_of(SteadyState, steady[i, k])})"
        tally.add(i, k, ", ".join(names), f"unsettled{why}", "a settled regime")
    return tally.finding("unsettled", regime[..., 0].size)


def _compare(ds: xr.Dataset, a: Assembled, rule: str, points, linear, rtol: float, missing: str) -> Finding:
    """X of the cube against `linear(w)` at `points` ((i, k) indices), to rtol of max |X_linear|."""
    X = harmonics(ds, a)
    if X is None:
        return Finding(rule, SKIPPED, note="no amplitude")
    points = list(points)
    if not points:
        return Finding(rule, SKIPPED, note=missing)
    w = ds["frequency"].values.astype(float)
    phase = "phase" in ds
    tally = _Tally(ds)
    checked = singular = 0
    for i, k in points:
        expected = linear(float(w[k]))
        if expected is None:
            singular += 1
            continue
        checked += 1
        found = X[i, k]
        if not phase:
            found, expected = np.abs(found), np.abs(expected)
        error = np.abs(found - expected)
        scale = max(float(np.abs(expected).max(initial=0.0)), np.finfo(float).tiny)
        bad = ~(error <= rtol * scale)
        if bad.any():
            d = int(np.flatnonzero(bad)[0])
            tally.add(i, k, a.dof_names[d], f"|X| {abs(found[d]):.10g}", f"{abs(expected[d]):.10g} (error "
                      f"{error[d]:.3g} > {rtol:g} x {scale:.6g}{'' if phase else ', amplitude only'})")
    note = f"{singular} points at a natural frequency of the undamped linear structure not judged" if singular else ""
    return tally.finding(rule, checked, note, partial=bool(singular))


def check_free_limit(ds: xr.Dataset, a: Assembled) -> Finding:
    """Rule `free_limit`: at friction_scale 0, X = (K - w^2 M + i w C)^-1 f at every settled point."""
    zero = np.flatnonzero(ds["friction_scale"].values == 0.0)
    settled = _settled(ds)
    points = [(int(i), int(k)) for i in zero for k in np.flatnonzero(settled[i])]

    return _compare(ds, a, "free_limit", points, lambda w: free_response(a, w), FREE_RTOL,
                    "no friction_scale 0 on the grid")


def check_stuck_limit(ds: xr.Dataset, a: Assembled) -> Finding:
    """Rule `stuck_limit`: where every contact is stuck at a settled point, X is the stuck structure's."""
    regime = _plane(ds, "regime")
    if regime is None:
        return Finding("stuck_limit", SKIPPED, note="no regime")
    stuck = (regime == Regime.STUCK).all(axis=-1) & _settled(ds)
    return _compare(ds, a, "stuck_limit", map(tuple, np.argwhere(stuck)), lambda w: stuck_response(a, w),
                    STUCK_RTOL, "no point where every contact is stuck")


def check_bound(ds: xr.Dataset, a: Assembled) -> Finding:
    """Rule `bound`: |X_i| <= |(H f)_i| + sum_j |(H w_j)_i| (4/pi) s mu_s_j at every settled point."""
    X = harmonics(ds, a)
    if X is None:
        return Finding("bound", SKIPPED, note="no amplitude")
    s, w = ds["friction_scale"].values.astype(float), ds["frequency"].values.astype(float)
    settled = _settled(ds)
    tally = _Tally(ds)
    checked = unbounded = 0
    for k, wk in enumerate(w):
        H = compliances(a, float(wk))
        if H is None:
            unbounded += int(settled[:, k].sum())
            continue
        direct, per_contact = np.abs(H[0]), np.abs(H[1]) * (4.0 / np.pi) * a.mu_s
        for i in np.flatnonzero(settled[:, k]):
            bound = direct + per_contact.sum(axis=1) * s[i]
            bound = bound + BOUND_RTOL * bound.max(initial=0.0)  # a mass the bound holds at 0 moves by rounding
            found = np.abs(X[i, k])
            checked += 1
            bad = ~(found <= bound)
            if bad.any():
                d = int(np.flatnonzero(bad)[0])
                tally.add(int(i), k, a.dof_names[d], float(found[d]), f"at most {bound[d]:.10g}")
    note = f"{unbounded} points at an undamped natural frequency not judged (no finite bound)" if unbounded else ""
    return tally.finding("bound", checked, note, partial=bool(unbounded))


def check_energy(ds: xr.Dataset, a: Assembled) -> Finding:
    """Rule `energy`: forcing work = friction energy + viscous dissipation per period (module docstring)."""
    rule = "energy"
    X = harmonics(ds, a)
    energy = _plane(ds, "friction_energy")
    if X is None or energy is None or "phase" not in ds:
        lacking = [n for n in ("amplitude", "phase", "friction_energy") if n not in ds]
        return Finding(rule, SKIPPED, note=f"no {', '.join(lacking)}")
    if a.excitation == "base" and (a.e > 0).any():
        return Finding(rule, SKIPPED, note="a contact to the moving base does work the cube does not record")
    damped = bool(np.abs(a.C).max(initial=0.0) > 0.0)
    w = ds["frequency"].values.astype(float)
    settled = _settled(ds)
    tally = _Tally(ds)
    checked = 0
    Xc, Xs = X.real, -X.imag
    Y = a.base_amplitude
    for i, k in np.argwhere(settled):
        wk = float(w[k])
        if a.excitation == "force":
            work = np.pi * float(a.F_cos @ Xs[i, k])
        else:
            work = np.pi * Y * float(a.K_base @ Xs[i, k] + wk * a.C_base @ Xc[i, k])
        friction = float(np.sum(energy[i, k]))
        viscous = np.pi * wk * float(Xc[i, k] @ a.C @ Xc[i, k] + Xs[i, k] @ a.C @ Xs[i, k])
        if not np.isfinite(work + friction + viscous):
            continue
        checked += 1
        # the scale of the work's terms, not of their sum (which cancels where the motion is in phase)
        size = np.pi * float(np.abs(forcing(a, wk)) @ np.abs(X[i, k]))
        slack = ENERGY_RTOL * (size + friction + viscous)
        surplus = work - friction - viscous
        if surplus < -slack or (not damped and surplus > slack):
            sign = ">=" if damped else "="
            tally.add(int(i), int(k), "", f"work {work:.10g}, friction {friction:.10g}",
                      f"work {sign} friction + viscous ({viscous:.10g}{', first harmonic' if damped else ''})")
    note = ("with dashpots: an inequality (the viscous dissipation beyond the first harmonic is not in the cube)"
            if damped else "")
    return tally.finding(rule, checked, note)


def check_harmonics(ds: xr.Dataset, a: Assembled) -> Finding:
    """Rule `harmonics`: X_1 of the harmonics is amplitude and phase's; each contact force's coefficients within
    its bound (module docstring), at every settled point."""
    rule = "harmonics"
    parts = [_plane(ds, f"{row}_harmonic_{part}") for row in ("response", "friction") for part in ("real", "imag")]
    xr_, xi, fr, fi = parts
    if xr_ is None or xi is None or fr is None or fi is None:
        return Finding(rule, SKIPPED, note="no harmonics")
    X = (xr_ + 1j * xi) * a.amplitude_unit  # (n_s, n_w, n, H + 1)
    F = fr + 1j * fi  # (n_s, n_w, m, H + 1)
    first = harmonics(ds, a)
    s = ds["friction_scale"].values.astype(float)
    limit = np.full(F.shape[-1], 4.0 / np.pi)
    limit[0] = 1.0
    tally = _Tally(ds)
    checked = 0
    for i, k in np.argwhere(_settled(ds)):
        checked += 1
        size = float(np.abs(X[i, k]).max(initial=0.0))
        if first is not None:
            found = X[i, k, :, 1] if "phase" in ds else np.abs(X[i, k, :, 1])
            bad = ~(np.abs(found - first[i, k]) <= HARMONICS_RTOL * size)
            if bad.any():
                d = int(np.flatnonzero(bad)[0])
                tally.add(int(i), int(k), a.dof_names[d], f"X_1 {complex(found[d]):.10g}",
                          f"{complex(first[i, k, d]):.10g} (amplitude and phase)")
                continue
        bound = s[i] * a.mu_s[:, None] * limit[None, :]
        over = ~(np.abs(F[i, k]) <= bound * (1.0 + HARMONICS_RTOL))
        if over.any():
            j, h = (int(v) for v in np.argwhere(over)[0])
            tally.add(int(i), int(k), f"{a.contact_names[j]}, harmonic {h}", f"|F| {abs(F[i, k, j, h]):.10g}",
                      f"at most {bound[j, h]:.10g}")
    return tally.finding(rule, checked)


def check_history(ds: xr.Dataset, a: Assembled) -> Finding:
    """Rule `history`: each stored orbit's contact forces within their static band (module docstring); its
    examples name the history point, the contact and the sample."""
    from friction_sweep.storage.schema import HISTORY_DIM

    rule = "history"
    if "history_contact_force" not in ds or "history_friction_scale" not in ds.coords:
        return Finding(rule, SKIPPED, note="no time history")
    force = np.asarray(ds["history_contact_force"].transpose(HISTORY_DIM, "sample", "contact").values, dtype=float)
    scale = ds["history_friction_scale"].values.astype(float)
    frequency = ds["history_frequency"].values.astype(float)
    stored = np.isfinite(force).any(axis=(1, 2))
    examples: list[dict] = []
    violations = 0
    for k in np.flatnonzero(stored):
        band = scale[k] * np.asarray(a.mu_s, dtype=float)
        over = np.abs(force[k]) > band[None, :] * (1.0 + HARMONICS_RTOL)  # NaN (past a shorter orbit) never is
        if over.any():
            violations += 1
            i, j = (int(v) for v in np.argwhere(over)[0])
            if len(examples) < MAX_EXAMPLES:
                examples.append({HISTORY_DIM: int(k), "frequency": float(frequency[k]),
                                 "friction_scale": float(scale[k]), "at": f"{a.contact_names[j]}, sample {i}",
                                 "found": float(force[k, i, j]), "expected": f"within +-{band[j]:.10g}"})
    return Finding(rule, FAILED if violations else OK, int(stored.sum()), violations, examples)


RULES = (check_unsettled, check_free_limit, check_stuck_limit, check_bound, check_energy, check_harmonics,
         check_history)


def check(ds: xr.Dataset) -> list[Finding]:
    """Run every rule on a structure cube; CubeError where the Dataset holds no structure they can read."""
    from friction_sweep.structures import recorded

    for dim in (*PLANE, "dof", "contact"):
        if dim not in ds.dims:
            raise CubeError(f"no dimension {dim}")
    try:
        a = recorded.assembled(ds)
    except recorded.UnreadableStructure as err:
        raise CubeError(str(err)) from None
    findings = [rule(ds, a) for rule in RULES]
    twin = moving_twin(ds)
    if twin is not None:  # (the time histories are the rest start's: no twin of theirs to check)
        for rule in (r for r in RULES if r is not check_history):
            finding = rule(twin, a)
            finding.rule += MOVING_SUFFIX
            findings.append(finding)
    return findings
