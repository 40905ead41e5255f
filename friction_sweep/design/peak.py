"""The resonance peak: for each friction level beta, the largest response over the frequency ratio r,

    P(beta) = max_r T(r, beta),

located on the exact solver, not on a grid. The spec's frequency_ratio axis is the search grid: every
interior local maximum of T on it (T[i] > T[i-1] and T[i] >= T[i+1]) brackets a maximum of T in
[r[i-1], r[i+1]], which a golden-section search on the per-point solve narrows to `r_tol` (each step keeps
the larger of its two inner points, so the bracket always holds the best value found). The peak reported
is the best point evaluated, never below the grid's value there. A maximum on the grid's first or last
point is not refined (the response may rise beyond the grid) and is flagged `at_edge`.

All brackets of all friction levels are refined together: one vectorised solve per golden-section step
(about 40 steps from a grid spacing of 0.01 down to 1e-10), so a curve of 100 friction levels costs the
grid's points plus some 40 x (number of maxima) points, at a few microseconds each with the event kernel.

The location is exact to `r_tol` as a bracket on the solver's T; since T is flat at a smooth maximum,
(T(r) = P - c (r - r*)^2), the peak VALUE carries only the solver's tolerance, while the location's
meaningful accuracy is about sqrt(steady_tol / c). A point with no bounded steady state (regime
unbounded, as the undamped mass at r = 1 with beta below pi/4) counts as an infinite response; an
unsettled point as none (-inf).

T is any per-point variable of the method (`transmissibility`, the first harmonic, by default;
`peak_transmissibility`, max|x| over the orbit). Methods: event, rk4 (kernels through methods.event, the
first start only), auto (Den Hartog's closed form where methods.auto would use it, event elsewhere).

The search reads the response through one call, `problem.solve(r, beta) -> (T, regime, phase)` (the
Response protocol): Problem is the 1-DoF scenes' response; design.structure's is a structure's chosen
mass against the angular frequency and friction_scale, whose regime has one value per contact (a trailing
axis the search carries along: Peaks.regime is then (levels, size, contacts)).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from friction_sweep import ties
from friction_sweep.codes import Regime
from friction_sweep.kernels import steady
from friction_sweep.kernels.settings import KERNEL_RK4
from friction_sweep.methods import auto, event, theory
from friction_sweep.theory import den_hartog, scenes

#: the methods whose per-point solve the peak is built on
METHODS = ("event", "rk4", "auto")
#: the variables a peak can be taken of (per-point kernel slots of every method above)
PEAK_VARIABLES = ("transmissibility", "peak_transmissibility")
#: default width, in r, of the bracket a maximum is refined to
R_TOL = 1e-10
#: 1 / golden ratio
INV_PHI = (np.sqrt(5.0) - 1.0) / 2.0


class Response(Protocol):
    """What the search reads: T, the regime code(s) and the phase (degrees) at the points (r, beta), 1-D
    arrays of one size (regime may have trailing axes, one value per contact); T +inf where the motion is
    unbounded, -inf where no steady state settled."""

    def solve(self, r: np.ndarray, beta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]: ...


@dataclass(frozen=True)
class Problem:
    """What a response T(r, beta) is: the scene, its effects, the method and its settings."""

    method: str
    excitation: str
    effects: Mapping[str, Any] | None = None
    settings: Mapping[str, Any] | None = None
    variable: str = "transmissibility"

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise ValueError(f"the peak is built on methods {', '.join(METHODS)} (got {self.method!r})")
        if self.variable not in PEAK_VARIABLES:
            raise ValueError(f"the peak is taken of {', '.join(PEAK_VARIABLES)} (got {self.variable!r})")

    def rows(self, r: np.ndarray, beta: np.ndarray) -> np.ndarray:
        """The simulated orbits' raw kernel rows at the points (r, beta) (methods.event.solve_flat, phases
        against the excitation), from the first start only; method rk4's kernel for rk4, event's for
        event and auto."""
        settings = dict(self.settings or {})
        settings.pop("theory_margin", None)
        settings.pop("starts", None)  # one start: the first (kernel_settings' own)
        if self.method == "rk4":
            settings["kernel"] = KERNEL_RK4
        return event.solve_flat(self.excitation, np.ascontiguousarray(r, dtype=float),
                                np.ascontiguousarray(beta, dtype=float), self.effects, **settings)

    def solve(self, r: np.ndarray, beta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(T, regime code, phase in degrees) at the points (r, beta), 1-D arrays of one size; T is +inf
        where the motion is unbounded and -inf where no steady state settled."""
        r = np.ascontiguousarray(r, dtype=float)
        beta = np.ascontiguousarray(beta, dtype=float)
        margin = float((self.settings or {}).get("theory_margin", auto.CATALOGUE.defaults["theory_margin"]))
        value = np.full(r.shape, np.nan)
        regime = np.full(r.shape, float(Regime.UNSETTLED))
        phase = np.full(r.shape, np.nan)
        simulate = np.ones(r.shape, dtype=bool)
        if self.method == "auto" and r.size:
            bstar = den_hartog.continuous_limit(r)
            th = theory.compute_points(self.excitation, r, beta, ("transmissibility", "phase", "regime"), bstar)
            limit = scenes.forcing_amplitude(self.excitation, r) * bstar  # beta*(r) in the scene's convention
            use = ((th["regime"] == Regime.CONTINUOUS) & (beta < (1.0 - margin) * limit)
                   & ~ties.at_resonance(r))
            value[use], regime[use], phase[use] = th[self.variable][use], th["regime"][use], th["phase"][use]
            simulate = ~use
        if simulate.any():
            raw = self.rows(r[simulate], beta[simulate])
            value[simulate] = event.kernel_variable(self.variable, raw, self.excitation, r[simulate])
            regime[simulate] = raw[:, steady.OUT_REGIME]
            phase[simulate] = raw[:, steady.OUT_PHASE]
        value = np.where(regime == Regime.UNBOUNDED, np.inf, value)
        value = np.where(np.isnan(value), -np.inf, value)
        return value, regime, phase


def golden_max(f: Callable[[np.ndarray], np.ndarray], lo: np.ndarray, hi: np.ndarray, tol: float,
               best_x: np.ndarray, best_f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Golden-section search for the maximum of f in every bracket [lo, hi] at once, until each bracket is
    narrower than `tol`; one evaluation of f (on every bracket) per step. `best_x`, `best_f`: a point
    known in each bracket and its value; returned: the best point evaluated and its value (never below
    best_f)."""
    lo, hi = lo.astype(float), hi.astype(float)
    best_x, best_f = best_x.astype(float), best_f.astype(float)
    width = float(np.max(hi - lo, initial=0.0))
    if lo.size == 0 or width <= tol:
        return best_x, best_f
    steps = int(np.ceil(np.log(tol / width) / np.log(INV_PHI)))
    c = hi - INV_PHI * (hi - lo)
    d = lo + INV_PHI * (hi - lo)
    fc, fd = f(c), f(d)
    for _ in range(steps):
        left = fc > fd  # the maximum lies in [lo, d]: d becomes the right inner point of [lo, d]
        hi = np.where(left, d, hi)
        lo = np.where(left, lo, c)
        keep_x, keep_f = np.where(left, c, d), np.where(left, fc, fd)
        new = np.where(left, hi - INV_PHI * (hi - lo), lo + INV_PHI * (hi - lo))
        fnew = f(new)
        c, fc = np.where(left, new, keep_x), np.where(left, fnew, keep_f)
        d, fd = np.where(left, keep_x, new), np.where(left, keep_f, fnew)
        for x, fx in ((c, fc), (d, fd)):
            better = fx > best_f
            best_x, best_f = np.where(better, x, best_x), np.where(better, fx, best_f)
    return best_x, best_f


@dataclass
class Peaks:
    """Every local maximum over r for each friction level, padded with NaN to `size` per level:
    value, frequency ratio, regime, phase (degrees, against the excitation), whether it lies on the
    grid's edge (unrefined) and whether it is the level's largest."""

    value: np.ndarray  # (levels, size)
    frequency_ratio: np.ndarray
    regime: np.ndarray
    phase: np.ndarray
    at_edge: np.ndarray
    largest: np.ndarray
    grid_phase: np.ndarray | None = None  # the phase on the frequency grid (levels x r), for phase_resonance

    def best(self) -> dict[str, np.ndarray]:
        """The largest maximum of each level (NaN where a level has none)."""
        levels = np.arange(self.value.shape[0])
        k = np.argmax(np.where(self.largest, 1, 0), axis=1)
        some = self.largest.any(axis=1)
        out = {}
        for name in ("value", "frequency_ratio", "regime", "phase"):
            picked = getattr(self, name)[levels, k]
            out[name] = np.where(some.reshape(some.shape + (1,) * (picked.ndim - 1)), picked, np.nan)
        out["at_edge"] = np.where(some, self.at_edge[levels, k], False)
        return out


def local_maxima(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(level, index) of every interior local maximum of t (levels x grid): t[i] > t[i-1], t[i] >= t[i+1]
    (a plateau counts once, at its left end)."""
    inner = (t[:, 1:-1] > t[:, :-2]) & (t[:, 1:-1] >= t[:, 2:])
    level, i = np.nonzero(inner)
    return level, i + 1


def peaks(problem: Response, r: np.ndarray, beta: np.ndarray, r_tol: float = R_TOL) -> Peaks:
    """The resonance peaks of T over the increasing grid r (at least 3 values) for each friction level in
    beta (1-D): see the module docstring."""
    r = np.asarray(r, dtype=float)
    beta = np.atleast_1d(np.asarray(beta, dtype=float))
    if r.ndim != 1 or r.size < 3 or np.any(np.diff(r) <= 0):
        raise ValueError("the frequency grid must be at least 3 increasing values")
    R, B = np.meshgrid(r, beta)
    t, reg, ph = (a.reshape(R.shape + a.shape[1:]) for a in problem.solve(R.ravel(), B.ravel()))
    level, i = local_maxima(t)
    x, fx = golden_max(lambda rr: problem.solve(rr, beta[level])[0], r[i - 1], r[i + 1], r_tol, r[i], t[level, i])
    finite = np.isfinite(fx)
    if finite.any():  # the regime and phase where the refined maxima lie
        _, reg_x, ph_x = problem.solve(x, beta[level])
    else:
        reg_x, ph_x = reg[level, i], ph[level, i]
    top = np.argmax(t, axis=1)
    edge_level = np.nonzero((top == 0) | (top == r.size - 1))[0]
    rows: list[list[tuple]] = [[] for _ in beta]  # per level: (value, r, regime, phase, at_edge)
    for k in range(level.size):
        found = rows[level[k]]
        if any(abs(f[1] - x[k]) <= 10 * r_tol for f in found):  # two grid maxima refined to one
            continue
        found.append((fx[k], x[k], reg_x[k], ph_x[k], False))
    for e in edge_level:
        rows[e].append((t[e, top[e]], r[top[e]], reg[e, top[e]], ph[e, top[e]], True))
    size = max(1, max(len(found) for found in rows))
    shape = (beta.size, size)
    out = Peaks(np.full(shape, np.nan), np.full(shape, np.nan), np.full(shape + reg.shape[2:], np.nan),
                np.full(shape, np.nan), np.zeros(shape, dtype=bool), np.zeros(shape, dtype=bool), ph)
    for j, found in enumerate(rows):
        found.sort(key=lambda f: f[1])
        for k, (v, rx, g, p, e) in enumerate(found):
            out.value[j, k], out.frequency_ratio[j, k], out.regime[j, k], out.phase[j, k] = v, rx, g, p
            out.at_edge[j, k] = e
        if found:
            values = np.array([f[0] for f in found])
            out.largest[j, int(np.argmax(values))] = True
    return out


@dataclass(frozen=True)
class Axes:
    """How a Dataset names its axes: the friction level's (`force_ratio` of a 1-DoF scene, `friction_scale` of
    a structure), the frequency's (`frequency_ratio`; a structure's angular `frequency`), and a structure's
    contacts (the regime's trailing axis, dim `contact`)."""

    friction: str = "force_ratio"
    frequency: str = "frequency_ratio"
    contacts: tuple[str, ...] | None = None


ONE_DOF = Axes()


def dataset(curve: Peaks, beta: np.ndarray, attrs: Mapping[str, Any], crossings=None, axes: Axes = ONE_DOF):
    """The peaks as an xarray Dataset over the friction axis (axes.friction: `force_ratio`) and `peak`, the
    local maxima of each level in increasing r, NaN-padded: `resonance_*` the largest, `local_*` every one;
    with `crossings` (phase_resonance.Crossings) the 90-degree points too, `phase_resonance_*` along dim
    `crossing`. The frequency's variables are named after axes.frequency (resonance_frequency_ratio); a
    structure's regimes have dim `contact` last."""
    import xarray as xr

    best = curve.best()
    f, freq = axes.friction, axes.frequency
    contact = () if axes.contacts is None else ("contact",)
    dims, local = (f,), (f, "peak")
    ds = xr.Dataset(
        {"resonance_peak": (dims, best["value"]), f"resonance_{freq}": (dims, best["frequency_ratio"]),
         "resonance_regime": (dims + contact, best["regime"]), "resonance_phase": (dims, best["phase"]),
         "resonance_at_edge": (dims, best["at_edge"].astype(bool)),
         "local_peak": (local, curve.value), f"local_{freq}": (local, curve.frequency_ratio),
         "local_regime": (local + contact, curve.regime), "local_phase": (local, curve.phase),
         "local_at_edge": (local, curve.at_edge), "local_largest": (local, curve.largest)},
        coords={f: np.asarray(beta, dtype=float), "peak": np.arange(curve.value.shape[1]),
                **({} if axes.contacts is None else {"contact": np.array(axes.contacts, dtype=str)})},
        attrs=dict(attrs))
    if crossings is not None:
        cross = (f, "crossing")
        ds = ds.assign({f"phase_resonance_{freq}": (cross, crossings.frequency_ratio),
                        "phase_resonance_value": (cross, crossings.value),
                        "phase_resonance_regime": (cross + contact, crossings.regime)})
        ds = ds.assign_coords(crossing=np.arange(crossings.value.shape[1]))
    return ds
