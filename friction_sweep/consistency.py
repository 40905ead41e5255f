"""Whole-plane consistency rules for a result cube of any method (`fsweep check`).

Each rule is a statement about the (r, beta) plane that holds for the exact steady state of the model,
whatever the method and however fine or close to r = 1 the grid: a correct cube passes them all. The
rules work on an xarray Dataset (dims force_ratio, frequency_ratio) and return a `Finding` each; they
print nothing.

Notation. The relative coordinate q obeys

    q'' + 2 zeta q' + q + f = A cos(r t),     |f| <= max(beta, bs),

with A = 1 for force/base and A = r^2 for joined (where q = z and x = z + cos(r t)), and
A = sqrt(1 + (2 zeta r)^2) for base with the dashpot in parallel with the spring (`to: base`, whose
forcing cos(r t) - 2 zeta r sin(r t) has that amplitude; theory.scenes); beta is the force ratio (kinetic
friction), bs = mu beta the static friction (mu = static_friction_ratio, default 1) and zeta =
viscous_damping (default 0) with its place, all read from the `effects` in the cube's `method_settings`
(a number, or {ratio, to} for an effect with places).
b = beta (force/base) or beta / r^2 (joined) is the friction against the forcing amplitude. Every tie
(r = 1, no motion from rest) is decided by friction_sweep.ties, as the methods decide it.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np
import xarray as xr

from friction_sweep import catalogue, codes, ties
from friction_sweep.catalogue import EFFECTS, EXCITATIONS, PLACED_KEYS, effect_place, effect_value
from friction_sweep.codes import Regime, SteadyState
from friction_sweep.storage import attributes, schema
from friction_sweep.storage.schema import ACCELERATION_DIMS, cube_dims
from friction_sweep.theory import den_hartog as dh
from friction_sweep.theory import energy, scenes

#: effects that Den Hartog's closed form lacks even at their plain-looking values (rule `theory`). Rules
#: `resonance` and `bound` hold for them: a contact spring passes on a force bounded by the static friction
#: (first harmonic at most 4 beta_s / pi), and dissipates 4 beta (a - beta / kappa) ~ 4 beta a at large a
NO_CLOSED_FORM = ("contact_stiffness",)
#: relative slack on the proven bound of rule `bound` (rounding of the measured first harmonic)
BOUND_RTOL = 1e-6
#: rule `theory`: points compared lie at b <= THEORY_MARGIN * beta*(r) ...
THEORY_MARGIN = 0.98
#: ... and at least this far from r = 1 (the stroboscopic map's conditioning ~1e-14 / |1 - r|) ...
THEORY_MIN_DETUNING = 1e-4
#: ... where the transmissibility must agree with the closed form to this relative error
THEORY_RTOL = 1e-8
#: rule `theory` computes the closed form on this many frequency ratios at a time (bounded memory)
THEORY_CHUNK = 32
#: methods whose cubes rule `energy` (friction_sweep.theory.energy) reads: the simulations, whose accuracy
#: the settings state (`paper` reproduces ode45's errors, with no bound to test; `theory` is a closed form,
#: not a simulated orbit)
ENERGY_METHODS = ("event", "rk4", "auto")
#: the relative error of one period of the event map (kernels.period_map.MAP_ROUNDING, restated here so
#: that `fsweep check` loads no kernel; tests/test_energy_balance.py keeps the two equal)
MAP_ROUNDING = 32.0 * 2.220446049250313e-16
#: examples kept per rule
MAX_EXAMPLES = 5

DIMS = ("force_ratio", "frequency_ratio")

OK, FAILED, SKIPPED, INFO = "ok", "failed", "skipped", "info"
#: no violation among the points checked, but points the rule could only partly judge (note says which, why)
PARTIAL = "partial"


class CubeError(ValueError):
    """The Dataset is not a friction_sweep result cube these rules can read."""


@dataclass
class Finding:
    """The outcome of one rule.

    status: "ok", "failed" (violations > 0), "partial" (no violation, but `note` names points the rule could
    not judge in full), "skipped" (note says why) or "info" (never a failure).
    examples: up to MAX_EXAMPLES dicts {r, beta, found, expected}, in order of r then beta.
    """

    rule: str
    status: str
    checked: int = 0
    violations: int = 0
    examples: list = field(default_factory=list)
    note: str = ""

    def to_dict(self) -> dict:
        return asdict(self)


@dataclass
class _Cube:
    excitation: str
    method: str
    effects: dict
    settings: dict  # the cube's method_settings
    zeta: float
    place: str  # where the dashpot sits (catalogue.effect_place)
    mu: float
    unknown_effects: tuple
    dims: tuple[str, str]  # the cube's grid dims: DIMS, or the physical ones at constant acceleration
    r: np.ndarray  # (n_r,)
    beta: np.ndarray  # (n_beta,), or (n_beta, n_r) at constant acceleration (beta grows with f^2)
    R: np.ndarray  # (n_beta, n_r), like every grid array below
    B: np.ndarray
    A: np.ndarray
    b: np.ndarray
    bs: np.ndarray
    ds: xr.Dataset

    def get(self, name):
        """A per-point variable as an (n_beta, n_r) array, or None when the cube lacks it."""
        if name not in self.ds.data_vars or set(self.ds[name].dims) != set(self.dims):
            return None
        return np.asarray(self.ds[name].transpose(*self.dims).values)

    @property
    def plain(self) -> bool:
        return (not self.unknown_effects and self.zeta == 0.0 and self.mu == 1.0
                and not any(e in self.effects for e in NO_CLOSED_FORM))


def _read(ds: xr.Dataset) -> _Cube:
    physical = all(ACCELERATION_DIMS[d] in ds.dims for d in DIMS) and "force_ratio" not in ds.dims
    dims = (ACCELERATION_DIMS[DIMS[0]], ACCELERATION_DIMS[DIMS[1]]) if physical else DIMS
    for name in DIMS:
        expected = cube_dims(name, (name,), physical)
        if name not in ds.coords or tuple(ds[name].dims) not in (expected, (dims[0],)):
            raise CubeError(f"no coordinate {name}")
    excitation = ds.attrs.get("excitation")
    if not isinstance(excitation, str) or excitation not in EXCITATIONS:
        raise CubeError(f"excitation {excitation!r} is not one of {', '.join(EXCITATIONS)}")
    try:  # the one reader of a cube's JSON (bounded; open_cube has audited it, a Dataset from elsewhere not)
        settings = attributes.method_settings(ds.attrs)
    except attributes.BadAttribute as err:
        raise CubeError(str(err)) from None
    effects = settings["effects"]
    for name, value in effects.items():
        if name in EFFECTS:
            _check_effect(excitation, name, value)
    zeta = effect_value(effects, "viscous_damping")
    mu = effect_value(effects, "static_friction_ratio")
    r = np.asarray(ds["frequency_ratio"].values, dtype=float)
    beta = np.asarray(ds["force_ratio"].transpose(*(d for d in dims if d in ds["force_ratio"].dims)).values,
                      dtype=float)
    R = np.broadcast_to(r, (beta.shape[0], r.size))
    B = beta if beta.ndim == 2 else np.broadcast_to(beta[:, None], R.shape)
    place = effect_place(excitation, effects, "viscous_damping")
    A, _ = scenes.kernel_forcing(excitation, R, zeta, place)
    return _Cube(excitation=excitation, method=str(ds.attrs.get("method", "")), effects=effects,
                 settings=settings, zeta=zeta, place=place, mu=mu,
                 unknown_effects=tuple(sorted(set(effects) - set(EFFECTS))), dims=dims, r=r, beta=beta, R=R,
                 B=B, A=A, b=scenes.friction_ratio(excitation, R, B), bs=mu * B, ds=ds)


def _check_effect(excitation: str, name: str, value) -> None:
    """CubeError unless a recorded effect is a finite number, or {ratio, to} with a place the excitation
    allows where the effect has places."""
    places = EFFECTS[name].places.get(excitation, {})
    if isinstance(value, dict) and places:
        if set(value) != set(PLACED_KEYS) or value["to"] not in places:
            raise CubeError(f"method_settings: effect {name} is not {{ratio, to: {' | '.join(places)}}}: {value!r}")
        value = value["ratio"]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise CubeError(f"method_settings: effect {name} is not a finite number: {value!r}")


def _value(v):
    """A JSON-safe scalar: finite floats stay numbers, NaN and infinities become text."""
    if isinstance(v, str):
        return v
    v = float(v)
    return v if math.isfinite(v) else str(v)


class _Tally:
    """Counts violations and keeps the first examples, in order of r then beta."""

    def __init__(self):
        self.count = 0
        self.found = []  # (r index, beta index, found, expected)

    def add(self, mask, found, expected):
        """mask: (n_beta, n_r) violations; found, expected: callables (i_beta, i_r) -> value."""
        n = int(np.count_nonzero(mask))
        if not n:
            return
        self.count += n
        where = np.argwhere(mask.T)[:MAX_EXAMPLES]  # rows (i_r, i_beta), r-major
        self.found.extend((int(i), int(j), found(j, i), expected(j, i)) for i, j in where)

    def finding(self, cube, rule, checked, offset=0):
        examples = [
            {"r": float(cube.r[i + offset]), "beta": float(cube.B[j, i + offset]), "found": _value(f),
             "expected": _value(e)}
            for i, j, f, e in sorted(self.found, key=lambda x: (x[0], x[1]))[:MAX_EXAMPLES]
        ]
        return Finding(rule, FAILED if self.count else OK, int(checked), self.count, examples)


def _theory_tile(theory, cube: _Cube, cols: slice) -> dict:
    """The closed form on the cube's columns `cols`: one plane, or a column at a time where beta varies
    with the frequency (constant acceleration)."""
    outputs = ("transmissibility", "regime")
    r = cube.r[cols]
    if cube.beta.ndim == 1:
        return theory.compute_tile(cube.excitation, r, cube.beta, outputs)
    columns = [theory.compute_tile(cube.excitation, r[i:i + 1], cube.beta[:, cols][:, i], outputs)
               for i in range(r.size)]
    return {name: np.concatenate([c[name] for c in columns], axis=-1) for name in outputs}


def _missing(rule, cube, *names):
    for name in names:
        if cube.get(name) is None:
            return Finding(rule, SKIPPED, note=f"no {name}")
    return None


def _name(code) -> str:
    return codes.name_of(Regime, code)


def transmissibility_bound(cube: _Cube) -> np.ndarray:
    """The bound of rule `bound` at every point: (A + (4/pi) max(beta, bs)) / |1 - r^2 + 2i zeta r|
    (A with the dashpot's share of the forcing, see the module's notation),
    plus 1 for joined; infinite at r = 1 without damping. 1 - r^2 is evaluated as (1 - r)(1 + r), exact
    to an ulp next to r = 1 (1 - r*r would lose ~1e-16 / |1 - r^2| to rounding)."""
    R = cube.R
    with np.errstate(divide="ignore"):
        bound = (cube.A + (4.0 / np.pi) * np.maximum(cube.B, cube.bs)) / np.hypot((1.0 - R) * (1.0 + R),
                                                                                 2.0 * cube.zeta * R)
    return bound + scenes.response_offset(cube.excitation)  # |x| <= |q| + c


def check_resonance(cube: _Cube) -> Finding:
    """Rule `resonance` (no damping only): at r = 1, unbounded exactly when b <= pi/4.

    At r = 1 the projection of rule `bound` reads 0 = A - F1: a periodic (finite) motion needs the
    friction's first harmonic to cancel the whole forcing, and |F1| <= 4 max(beta, bs) / pi. In slip
    the friction is beta sgn(q'), whose first harmonic is at most 4 beta / pi, reached only by a square
    wave; the energy balance over a period (forcing work pi A X against friction 4 beta X for a large
    amplitude X) makes the amplitude grow without bound when b = beta / A < pi/4 and decay to a finite
    orbit when b > pi/4 (Den Hartog, paper Eqs. 14-15; at b = pi/4 exactly the amplitude still grows,
    like sqrt(t)). So at r = 1 with the mass leaving rest: b <= (pi/4)(1 + TIE_RTOL) must be
    `unbounded`, larger b must not be (nor carry a finite transmissibility above the bound of rule
    `bound`). Where the force's swing A stays inside the static band bs the mass never moves: `stuck`.
    With viscous damping the amplitude at r = 1 is finite (at most the bound of rule `bound`), so the
    rule does not apply.
    """
    rule = "resonance"
    if cube.unknown_effects:
        return Finding(rule, SKIPPED, note=f"unknown effects {', '.join(cube.unknown_effects)}")
    if cube.zeta != 0.0:
        return Finding(rule, SKIPPED, note="viscous damping: no resonance singularity")
    missing = _missing(rule, cube, "regime")
    if missing:
        return missing
    reg = cube.get("regime")
    T = cube.get("transmissibility")
    at = ties.at_resonance(cube.R)
    still = ties.never_moves(cube.A, cube.bs)
    small = cube.b <= dh.RESONANCE_FRICTION_LIMIT * (1.0 + ties.TIE_RTOL)
    tally = _Tally()

    def found(j, i):
        return _name(reg[j, i])

    tally.add(at & still & (reg != Regime.STUCK), found, lambda j, i: "stuck (never moves)")
    tally.add(at & ~still & small & (reg != Regime.UNBOUNDED), found, lambda j, i: "unbounded (b <= pi/4)")
    big = at & ~still & ~small
    tally.add(big & (reg == Regime.UNBOUNDED), found, lambda j, i: "finite (b > pi/4)")
    if T is not None:
        bound = transmissibility_bound(cube)
        with np.errstate(invalid="ignore"):
            over = big & (reg != Regime.UNBOUNDED) & np.isfinite(T) & (T > (1.0 + BOUND_RTOL) * bound)
        tally.add(over, lambda j, i: float(T[j, i]), lambda j, i: f"<= {bound[j, i]:.6g}")
    return tally.finding(cube, rule, np.count_nonzero(at))


def check_bound(cube: _Cube) -> Finding:
    """Rule `bound`: every finite transmissibility is at most the first-harmonic bound.

    Project the equation of motion q'' + 2 zeta q' + q + f = A cos(r t) of a periodic steady state onto
    the forcing frequency (multiply by e^{-i r t} and average over the orbit's period, a whole number
    of forcing periods): with Q1 and F1 the first-harmonic amplitudes of q and f,

        (1 - r^2 + 2i zeta r) Q1 = A - F1

    (A e^{i lead} - F1 for the spring-parallel dashpot, whose forcing A cos(r t + lead) leads the
    base's; the modulus is the same A). The friction force never exceeds max(beta, bs) (kinetic in
    slip, at most static in a stick), and the first harmonic of any signal bounded by M is at most 4M/pi
    (the square wave's), so

        |Q1| <= (A + (4/pi) max(beta, bs)) / |1 - r^2 + 2i zeta r|.

    The transmissibility is |Q1| for force and base (x = q) and |Q1 + 1| <= |Q1| + 1 for joined
    (x = z + cos(r t)). The check allows 1e-6 relative for rounding; without damping the bound is
    infinite at r = 1, and there is nothing to check.
    """
    rule = "bound"
    if cube.unknown_effects:
        return Finding(rule, SKIPPED, note=f"unknown effects {', '.join(cube.unknown_effects)}")
    missing = _missing(rule, cube, "transmissibility")
    if missing:
        return missing
    T = cube.get("transmissibility")
    bound = transmissibility_bound(cube)
    sel = np.isfinite(T) & np.isfinite(bound)
    with np.errstate(invalid="ignore"):
        over = sel & (T > (1.0 + BOUND_RTOL) * bound)
    tally = _Tally()
    tally.add(over, lambda j, i: float(T[j, i]), lambda j, i: f"<= {bound[j, i]:.6g}")
    return tally.finding(cube, rule, np.count_nonzero(sel))


def check_theory(cube: _Cube, chunk: int = THEORY_CHUNK) -> Finding:
    """Rule `theory` (plain model, methods other than `theory`): well inside the continuous region the
    cube agrees with Den Hartog's closed form.

    For b <= 0.98 beta*(r) Den Hartog's stop-free orbit exists and is the steady state every method
    must reach: regime `continuous` and the closed-form first harmonic (the event simulation reproduces
    it to ~1e-13, README). That holds at and next to r = 1/(2n) too: there the stick-free orbits form
    a continuum (or Den Hartog's is the only one, with a multiplier 1 to rounding), but every member
    is continuous with Den Hartog's first harmonic, and a march that still sticks is a creep, not an
    orbit (docs/equations.md §6). Excluded, because the comparison is not a property of the model there:
    within 2 % of beta* (grazing contacts, where rounding of either side decides the regime), within
    1e-4 of r = 1 (the steady state is reached with relative error ~1e-14 / |1 - r|) and points the cube
    reports `unsettled` (rule `unsettled` counts those). At the compared points the regime must equal
    the theory's and |T / T_theory - 1| <= 1e-8 where both are finite; a number on one side only is a
    violation. The closed form is computed on the cube's own grid, THEORY_CHUNK frequency ratios at a
    time.
    """
    from friction_sweep.methods import theory

    rule = "theory"
    if cube.method == "theory":
        return Finding(rule, SKIPPED, note="the theory itself")
    if not cube.plain:
        shown = ", ".join(f"{k}={v}" for k, v in sorted(cube.effects.items()))
        return Finding(rule, SKIPPED, note=f"effects {shown}: no closed form")
    missing = _missing(rule, cube, "regime", "transmissibility")
    if missing:
        return missing
    reg = cube.get("regime")
    T = cube.get("transmissibility")
    checked, count, examples = 0, 0, []
    for start in range(0, cube.r.size, chunk):
        cols = slice(start, start + chunk)
        r = cube.r[cols]
        ref = _theory_tile(theory, cube, cols)
        bstar = dh.continuous_limit(r)
        reg_c, T_c, b_c = reg[:, cols], T[:, cols], cube.b[:, cols]
        sel = ((b_c <= THEORY_MARGIN * bstar[None, :])
               & (np.abs(r - 1.0) >= THEORY_MIN_DETUNING)[None, :]
               & (reg_c != Regime.UNSETTLED))
        T_ref, reg_ref = ref["transmissibility"], ref["regime"]
        fin, fin_ref = np.isfinite(T_c), np.isfinite(T_ref)
        with np.errstate(invalid="ignore"):
            far = fin & fin_ref & ~(np.abs(T_c - T_ref) <= THEORY_RTOL * np.abs(T_ref))
        bad_T = far | (fin != fin_ref)
        bad_reg = reg_c != reg_ref
        tally = _Tally()
        # the lambdas run inside tally.add, with this column block's arrays (bound as defaults)
        tally.add(sel & bad_reg, lambda j, i, a=reg_c: _name(a[j, i]), lambda j, i, a=reg_ref: _name(a[j, i]))
        tally.add(sel & ~bad_reg & bad_T, lambda j, i, a=T_c: _value(a[j, i]),
                  lambda j, i, a=T_ref: _value(a[j, i]))
        part = tally.finding(cube, rule, np.count_nonzero(sel), offset=start)
        checked += part.checked
        count += part.violations
        examples.extend(part.examples)
    examples.sort(key=lambda e: (e["r"], e["beta"]))
    return Finding(rule, FAILED if count else OK, checked, count, examples[:MAX_EXAMPLES])


def check_unsettled(cube: _Cube) -> Finding:
    """Rule `unsettled`: every point has a regime. A periodic steady state exists for every (r, beta)
    of the model (or the motion is unbounded, a regime too); `unsettled` means the method gave up
    before finding it, so the point's numbers are not a steady state. The example says why the search
    stopped (`steady_state`) where the cube has it."""
    rule = "unsettled"
    missing = _missing(rule, cube, "regime")
    if missing:
        return missing
    reg = cube.get("regime")
    why = cube.get("steady_state")

    def found(j, i):
        if why is None:
            return "unsettled"
        return f"unsettled ({codes.name_of(SteadyState, why[j, i])})"

    tally = _Tally()
    tally.add(reg == Regime.UNSETTLED, found, lambda j, i: "a settled regime")
    return tally.finding(cube, rule, reg.size)


def _setting(cube: _Cube, name: str) -> float:
    """A setting of the cube's method as its method_settings record it (the catalogue's default where it
    does not); CubeError unless it is a number in the setting's meaningful range."""
    known = catalogue.method(cube.method).settings[name]
    value = cube.settings.get(name, known.default)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
            or not known.contains(value):
        raise CubeError(f"method_settings: {name} is not a number in {known.describe()}: {value!r}")
    return float(value)


def _closure(cube: _Cube) -> np.ndarray:
    """What a method's accepted orbit may leave unclosed over its measured period, relative to the state:
    steady_tol (|P^k(x) - x| <= steady_tol |x|, the method's own setting) plus the map's own error per
    period: rounding for event (kernels.period_map.map_error), and for rk4 its truncation too,
    (2 pi / r) h^4 / 120 with h = 2 pi / (r steps_per_period)."""
    steady_tol = _setting(cube, "steady_tol")
    error = np.full(cube.R.shape, MAP_ROUNDING)
    if cube.method == "rk4":
        steps = _setting(cube, "steps_per_period")
        h = 2.0 * np.pi / (cube.R * steps)
        error = np.maximum(error, 2.0 * np.pi / cube.R * h ** 4 / 120.0)
    return steady_tol + error


def energy_terms(cube: _Cube, T: np.ndarray, phase: np.ndarray):
    """The energies per forcing period of rule `energy` (units k Y^2, or F0^2 / k for force) from the
    first harmonic of the response: (W, V1, Q) with W the forcing's work, V1 the viscous dissipation of
    the first harmonic alone and Q the complex first-harmonic amplitude of q against the forcing."""
    lead = scenes.forcing_lead(cube.excitation, cube.R, cube.zeta, cube.place)
    c = scenes.response_offset(cube.excitation)
    still = T == 0.0  # no motion (force, base): no phase, and nothing to balance
    lag = np.where(still, 0.0, np.radians(np.where(still, 0.0, phase))) + lead
    Q = T * np.exp(-1j * lag) - c
    W = np.pi * cube.A * T * np.sin(lag)
    V1 = 2.0 * np.pi * cube.zeta * cube.R * np.abs(Q) ** 2
    return W, V1, Q


def check_energy(cube: _Cube) -> Finding:
    """Rule `energy` (simulation methods): every orbit the cube calls a steady state balances the energy
    that enters and leaves it over a period (docs/equations.md §6).

    Multiply q'' + 2 zeta q' + q + f = A cos(r t) by q' and integrate over the orbit's k periods: the
    change of the energy (q'^2 + q^2)/2 equals the forcing's work minus the friction's and the dashpot's
    dissipation, and is zero on a periodic orbit. Per forcing period, with x's first harmonic T at lag phi
    behind the forcing (the stored phase plus the spring-parallel dashpot's lead) and Q = T e^{-i phi} - c
    that of q (x = q + c cos(r t)),

        W  = pi A T sin(phi)               the forcing's work (only q's first harmonic pairs with it)
        F  = friction_energy               kinetic friction x sliding distance (0 where beta = 0)
        V1 = 2 pi zeta r |Q|^2             the dashpot's dissipation by the first harmonic alone

    and the whole viscous dissipation is V1 plus that of the higher harmonics (never negative). So

        W = F + V1      where it is an equality: no damping, or no friction (beta = 0: the motion is
                        linear, a pure harmonic)
        W >= F + V1     elsewhere (with damping and friction)

Where the cube lacks friction_energy (not in the default outputs), F is known only at beta = 0 and at stuck
points (F = 0): there the balance is checked in full; elsewhere only its necessary part W >= V1 (a violation is
a failure, passing proves little: at zeta = 0 it is W >= 0), so the rule's status is `partial` and its
note counts those points and says to add friction_energy to the outputs.

    to within theory.energy's slack, SAFETY x closure x Z^2 + RTOL x (|W| + F + V1) (10 and 1e-9). The
    first term is what the method's acceptance allows: a measured period that starts at x and ends within
    closure x |x| of it (closure = steady_tol + the map's own error, _closure) changes the energy by at
    most about that times |x|^2, with |x| <= Z = max(1, r) max(|Q|, peak + c, A) (the state (q, q') at
    the section; the velocity ~ r q). Checked: every point with a regime (stuck, stick_slip, continuous) and a finite
    transmissibility and phase, except aperiodic ones (averages over 256 periods, not an orbit). A wrong
    orbit (the forcing's work of the wrong sign or size for what it dissipates) fails it.
    """
    rule = "energy"
    if cube.method not in ENERGY_METHODS:
        return Finding(rule, SKIPPED, note=f"method {cube.method or '?'}: not a simulation with a stated accuracy")
    if cube.unknown_effects:
        return Finding(rule, SKIPPED, note=f"unknown effects {', '.join(cube.unknown_effects)}")
    missing = _missing(rule, cube, "transmissibility", "phase", "regime")
    if missing:
        return missing
    T, phase, reg = cube.get("transmissibility"), cube.get("phase"), cube.get("regime")
    why = cube.get("steady_state")
    with np.errstate(invalid="ignore", over="ignore"):
        settled = np.isin(reg, (Regime.STUCK, Regime.STICK_SLIP, Regime.CONTINUOUS)) & np.isfinite(T)
        sel = settled & (np.isfinite(phase) | (T == 0.0))
        if why is not None:
            sel &= why != SteadyState.APERIODIC
        W, V1, Q = energy_terms(cube, np.where(sel, T, 0.0), np.where(sel, phase, 0.0))
        stored = cube.get("friction_energy")
        frictionless = (cube.B == 0.0) | (reg == Regime.STUCK)  # no friction, or no sliding: F = 0
        F = np.where(frictionless, 0.0, stored if stored is not None else np.nan)
        known = np.isfinite(F)
        equality = known & (frictionless | (cube.zeta == 0.0))
        F = np.where(known, F, 0.0)
        residual = W - F - V1
        peak = cube.get("peak_transmissibility")
        size = np.maximum(np.abs(Q), cube.A)
        if peak is not None:
            size = np.maximum(size, np.nan_to_num(peak) + scenes.response_offset(cube.excitation))
        size = size * np.maximum(1.0, cube.R)
        tol = energy.slack(_closure(cube), size, W, F, V1)
        bad = sel & ~np.where(equality, energy.holds(residual, tol, True), energy.holds(residual, tol, False))
    tally = _Tally()
    tally.add(bad, lambda j, i: f"W - F - V1 = {residual[j, i]:.6g} (W {W[j, i]:.6g}, F {F[j, i]:.6g}, "
              f"V1 {V1[j, i]:.6g})",
              lambda j, i: f"{'|W - F - V1|' if equality[j, i] else '-(W - F - V1)'} <= {tol[j, i]:.3g}")
    finding = tally.finding(cube, rule, np.count_nonzero(sel))
    partly = int(np.count_nonzero(sel & ~known))
    if partly:
        finding.note = (f"{partly} of {finding.checked} points (beta > 0, moving) checked only for W >= V1: without "
                        "friction_energy the friction's share is unknown (add friction_energy to outputs)")
        if finding.status == OK:
            finding.status = PARTIAL
    return finding


def check_family(cube: _Cube) -> Finding:
    """Rule `family` (information, never a violation): points whose steady state is the continuum of
    stick-free orbits at r = 1/(2n) without damping, where the first harmonic belongs to the family
    and no single orbit is privileged. Counted so that a user knows which numbers are of that kind."""
    rule = "family"
    why = cube.get("steady_state")
    if why is None:
        return Finding(rule, SKIPPED, note="no steady_state")
    mask = why == SteadyState.FAMILY
    n = int(np.count_nonzero(mask))
    tally = _Tally()
    tally.add(mask, lambda j, i: "family", lambda j, i: "information")
    out = tally.finding(cube, rule, why.size)
    return Finding(rule, INFO, out.checked, 0, out.examples,
                   note=f"{n} point{'s' if n != 1 else ''} on a stick-free orbit family (r = 1/(2n))")


RULES = (check_resonance, check_bound, check_theory, check_energy, check_unsettled, check_family)


#: rules that also hold for the state from a moving start (static friction: `*_moving` variables)
MOVING_RULES = (check_bound, check_energy, check_unsettled)


def check(ds: xr.Dataset) -> list[Finding]:
    """Run every rule on a result cube; raises CubeError if the Dataset is not a cube they can read.
    Where the cube also holds the states from a moving start, MOVING_RULES run on them too (rule names
    with the suffix `_moving`)."""
    cube = _read(ds)
    findings = [rule(cube) for rule in RULES]
    twin = moving_twin(ds)
    if twin is not None:
        moving = _read(twin)
        for rule in MOVING_RULES:
            finding = rule(moving)
            finding.rule += schema.MOVING_SUFFIX
            findings.append(finding)
    return findings


def moving_twin(ds: xr.Dataset) -> xr.Dataset | None:
    """The cube as the states from the moving start make it (static friction: each `*_moving` variable under
    its own name, in place of the one from rest), for the rules that hold at any steady state; None where
    the cube has no such variables."""
    twins = [str(n)[: -len(schema.MOVING_SUFFIX)] for n in ds.data_vars if str(n).endswith(schema.MOVING_SUFFIX)]
    if not twins:
        return None
    return ds.drop_vars([n for n in twins if n in ds]).rename({n + schema.MOVING_SUFFIX: n for n in twins})


def failed(findings) -> bool:
    return any(f.status == FAILED for f in findings)
