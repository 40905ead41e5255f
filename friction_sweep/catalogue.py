"""What each method can do, in one place: the spec validates against it, the CLI builds its help and
`fsweep info --methods` / `fsweep settings` from it, and the methods read their defaults here.

Numba-free and import-light (the spec layer and `fsweep validate` read it without loading a kernel).
Adding an effect or a setting touches this catalogue, the kernel that models it and its tests.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Literal

#: the three scenes of the paper (docs/equations.md §1): a force on the mass; base motion against a fixed
#: rubbing wall; base and wall moving together
EXCITATIONS = ("force", "base", "joined")

#: output groups a spec can ask for; the per-point variables each writes are the methods' business
DEFAULT_OUTPUTS = ("transmissibility", "phase", "regime")  # what a spec that names none gets
#: design quantities (docs/equations.md §6): friction's energy per period, the force on the supports
DESIGN_OUTPUTS = ("friction_energy", "transmitted_force")
MODEL_OUTPUTS = (*DEFAULT_OUTPUTS, *DESIGN_OUTPUTS)  # what the closed form gives as well as a simulation
#: the steady orbit's stability (its largest Floquet multiplier): only a simulation has a period map
STABILITY_OUTPUTS = ("stability",)
SIMULATED_OUTPUTS = (*MODEL_OUTPUTS, *STABILITY_OUTPUTS)  # what any simulation gives
#: the exact Fourier coefficients of the orbit's response and friction force up to harmonic `settings.harmonics`,
#: per grid point on a dim of their own: only the event kernel's closed-form pieces give them exactly
HARMONIC_OUTPUTS = ("harmonics",)
GRID_OUTPUTS = (*SIMULATED_OUTPUTS, *HARMONIC_OUTPUTS)  # per grid point
OUTPUTS = (*GRID_OUTPUTS, "time_history")  # time histories: of chosen points, on their own dims


def number_text(x: float) -> str:
    """A number as a reader writes it: 1000000, 1e-06, 10000000000."""
    return str(int(x)) if float(x).is_integer() and abs(x) < 1e15 else f"{x:g}"


@dataclass(frozen=True)
class Bounded:
    """A number's meaningful range [low, high] (or [low, high) where `high_open`), and why. Where `floor`
    is set (low = 0), a nonzero value must also be at least `floor`: 0 stays allowed (it turns the thing
    off), values between are too small for double precision to compute with."""

    low: float
    high: float
    why: str
    high_open: bool = False
    floor: float = 0.0

    def contains(self, value: float) -> bool:
        return (self.low <= value and (value < self.high if self.high_open else value <= self.high)
                and (value == 0.0 or value >= self.floor))

    def describe(self) -> str:
        high = f"{number_text(self.high)}{')' if self.high_open else ']'}"
        if self.floor > 0.0:
            return f"0 or [{number_text(self.floor)}, {high}"
        return f"[{number_text(self.low)}, {high}"


@dataclass(frozen=True)
class Setting(Bounded):
    """One accuracy or budget knob of a method (`settings:` in a spec): its default and meaningful range.

    Values outside the range are refused: inside it every value gives a right answer or an honest label
    (`unsettled`), at a cost the run's estimate covers; `why` says what the bounds protect.
    """

    kind: Literal["int", "float"] = "float"
    default: float = 0.0


@dataclass(frozen=True)
class Effect(Bounded):
    """A physical effect beyond plain Coulomb friction (`scene: effects:`); absent means `off`, the value
    of the plain model, and a run without it is bit-identical to the plain model.

    An effect with `places` sits somewhere: per excitation, the places it may be attached `to` and what
    each means, the first being where a bare number puts it. Such an effect is given as a number or as
    `{ratio: number, to: place}` (EffectValue)."""

    meaning: str = ""
    off: float = 0.0
    places: Mapping[str, Mapping[str, str]] = field(default_factory=dict)

    def place_names(self) -> tuple[str, ...]:
        """Every place any excitation allows, in the catalogue's order."""
        return tuple(dict.fromkeys(p for by in self.places.values() for p in by))

    def shape(self) -> str:
        """How a spec writes the effect, for `fsweep info --methods` and `fsweep settings`."""
        if not self.places:
            return f"a number in {self.describe()}"
        allowed = "; ".join(f"{ex} {' | '.join(by)}" for ex, by in self.places.items())
        return (f"a number in {self.describe()} (the ratio, at the first place listed), or "
                f"{{ratio: number, to: {' | '.join(self.place_names())}}} ({allowed})")


#: the smallest nonzero damping ratio. The damped closed form of a slip piece (kernels/segments.py) adds
#: terms of the forced response's size A / |1 - r^2 + 2i zeta r| (A / (2 zeta) at resonance) that cancel to
#: the motion's, so at resonance an orbit carries rounding of about 10 eps / zeta of itself (measured, base
#: r = 1, beta = 0.8: 4e-6 at zeta = 1e-10, 6.5e-7 at 1e-9, 1.4e-7 at 1e-8, more than the damping's own
#: effect, ~14 zeta); from 1e-6 it is below 1e-9 and the damping's effect dominates it. Far below, exp(-2 pi
#: zeta) rounds to 1 (zeta < 2e-17) and no double-precision solver sees the dashpot at all: orbits of any
#: size pass for steady states (tests/test_energy_balance.py)
VISCOUS_DAMPING_FLOOR = 1e-6

#: the keys of an effect given with its place
PLACED_KEYS = ("ratio", "to")

#: an effect's value as a spec gives it: a number, or {ratio, to} for an effect with places
EffectValue = float | Mapping[str, float | str]
Effects = Mapping[str, EffectValue]

EFFECTS: Mapping[str, Effect] = MappingProxyType({
    "viscous_damping": Effect(
        0.0, 1.0, "the damping ratio zeta of the dashpot's force 2 zeta v, v the velocity across it "
        f"(underdamped), 0 without a dashpot; below {VISCOUS_DAMPING_FLOOR:g} the rounding of the damped motion at "
        "resonance (terms of "
        "size 1/(2 zeta) cancel, ~10 eps / zeta of the orbit is left) exceeds 1e-9 and outgrows the damping's own "
        "effect, and below 2e-17 exp(-2 pi zeta) rounds to 1: no double-precision solver sees the dashpot",
        high_open=True, floor=VISCOUS_DAMPING_FLOOR,
        meaning="viscous damping ratio zeta of a dashpot (docs/equations.md §6)", off=0.0,
        places=MappingProxyType({
            "force": {"ground": "from the mass to the ground"},
            "base": {"ground": "from the mass to the ground (the fixed wall's frame)",
                     "base": "from the mass to the moving base, in parallel with the spring"},
            "joined": {"base": "from the mass to the moving base and wall, on the relative velocity"},
        })),
    "static_friction_ratio": Effect(1.0, 100.0, "measured ratios are 1-2; beyond 100 the stick band swallows "
                                    "every excitation the grid allows",
                                    meaning="static over kinetic friction force (a stuck mass breaks loose above "
                                    "the static force)", off=1.0),
    "contact_stiffness": Effect(1e-3, 1e8, "the contact spring k_t over the main spring k: below 1e-3 the slider "
                                "barely moves the mass, beyond 1e8 a stick's swings on the contact spring "
                                "(sqrt(kappa) per natural period) cost more than a point's work budget",
                                meaning="stiffness kappa = k_t/k of a tangential spring in series with the slider "
                                "(a Jenkins element; joined: on the relative motion; docs/equations.md §7)",
                                off=0.0),
})


def effect_value(effects: Effects | None, name: str) -> float:
    """An effect's value in a scene (the ratio where it is given with its place): as given, else the plain
    model's (`off`)."""
    value = (effects or {}).get(name, EFFECTS[name].off)
    return float(value["ratio"] if isinstance(value, Mapping) else value)


def effect_place(excitation: str, effects: Effects | None, name: str) -> str:
    """Where an effect with places sits in a scene: its `to`, else (a bare number, or absent) the first
    place the excitation allows."""
    value = (effects or {}).get(name)
    if isinstance(value, Mapping):
        return str(value["to"])
    return next(iter(EFFECTS[name].places[excitation]))


def resolved_effects(excitation: str, effects: Effects | None) -> dict[str, EffectValue]:
    """The effects as a record states them (a cube's method_settings): an effect with places always as
    {ratio, to}, a bare number at its first place."""
    out: dict[str, EffectValue] = {}
    for name, value in (effects or {}).items():
        if name in EFFECTS and EFFECTS[name].places:
            out[name] = {"ratio": effect_value(effects, name), "to": effect_place(excitation, effects, name)}
        else:
            out[name] = value
    return out


def effect_lines(excitation: str, effects: Effects | None) -> list[str]:
    """One readable line per effect of a scene (`fsweep validate`, the cube's `effects` attribute)."""
    lines = []
    for name, value in (effects or {}).items():
        effect = EFFECTS.get(name)
        if effect is None:
            lines.append(f"{name} {value!r}")
        elif effect.places:
            place = effect_place(excitation, effects, name)
            lines.append(f"{name} {number_text(effect_value(effects, name))}, to: {place} "
                         f"({effect.places[excitation][place]})")
        else:
            lines.append(f"{name} {number_text(effect_value(effects, name))}")
    return lines


@dataclass(frozen=True)
class Method:
    """A numba-free record of one sweep method (its implementation: friction_sweep.methods.<name>)."""

    name: str
    summary: str
    settings: Mapping[str, Setting]
    excitations: tuple[str, ...] = EXCITATIONS
    effects: tuple[str, ...] = ()
    outputs: tuple[str, ...] = DEFAULT_OUTPUTS
    #: settings that `accuracy:` owns (a spec with accuracy: may not give them): those the benchmark's
    #: calibration varies, which it sets, and those the calibration held at their defaults
    accuracy_knobs: tuple[str, ...] = ()
    #: whose calibration `accuracy:` reads
    calibrated_as: str | None = None
    #: whether it can run a stepped-sine sweep (`sweep:`), each point started from its neighbour's orbit
    sweep: bool = False
    #: how it computes what has no knob, recorded with the cube's settings
    algorithm: Mapping[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:  # read-only, as the record is frozen
        object.__setattr__(self, "settings", MappingProxyType(dict(self.settings)))
        object.__setattr__(self, "algorithm", MappingProxyType(dict(self.algorithm)))

    @property
    def defaults(self) -> dict[str, float | int]:
        return {k: int(s.default) if s.kind == "int" else s.default for k, s in self.settings.items()}

    @property
    def time_history(self) -> bool:
        return "time_history" in self.outputs


def _int(default: int, low: float, high: float, why: str) -> Setting:
    return Setting(low, high, why, kind="int", default=default)


def _float(default: float, low: float, high: float, why: str) -> Setting:
    return Setting(low, high, why, kind="float", default=default)


# Bounds measured on grids of 77 r x 30 beta against the defaults (closing note of issue 14): inside
# them every value labels every point right or honestly (`unsettled`), at a cost the estimate bounds.
_STEADY = {
    "steady_tol": _float(1e-10, 1e-13, 1e-6, "the relative change per period below which the map has settled "
                         "(|P^k(x) - x| <= steady_tol |x|): looser mislabels slow transients near the stick-slip "
                         "limit, tighter than rounding finds false period-2 orbits"),
    "stop_tol": _float(1e-12, 1e-15, 1e-10, "a stop is |v| <= stop_tol x the state's size: looser misplaces stops "
                       "(r = 1 goes unsettled from 1e-9), tighter than rounding never finds them"),
    "max_periods": _int(2000, 1, 100_000, "forcing periods marched per point at most (cost grows with it)"),
    "max_orbit_period": _int(256, 1, 1024, "longest period-k orbit looked for (static friction locks onto k up to "
                             "~250; each period's cost grows with it)"),
    "work_budget": _int(5_000_000, 1, 10**8, "stop searches and events per point at most: 0.1-0.3 us each, so at "
                        "most about 30 s a point"),
    "shoot_after": _int(0, 0, 1_000_000, "periods marched before the first shooting attempt; 0: first from "
                        "Den Hartog's orbit where the steady state is unique, before any march (fastest, make bench)"),
    "shoot_every": _int(48, 1, 1_000_000, "periods between shooting attempts (structures: the longest gap; their "
                        "attempts follow a miss after 1, 2, 4, ... periods)"),
    "initial_displacement": _float(0.0, -2.0, 2.0, "start of the march at forcing phase 0, in the equation's "
                                   "length unit: farther starts settle on wrong or no orbits within the budget"),
    "initial_velocity": _float(0.0, -2.0, 2.0, "start of the march, in the equation's velocity unit: farther "
                               "starts settle on wrong or no orbits within the budget"),
}
#: the highest harmonic of the output `harmonics` (fsweep's exact coefficients, methods event and auto)
MAX_HARMONIC = 64
_HARMONICS = _int(16, 1, MAX_HARMONIC, "highest harmonic k of the output harmonics (exact Fourier coefficients "
                  "at k r): each costs a closed-form integral per piece of the orbit and a plane of the cube")
_STARTS = _int(2, 1, 2, "1: from rest only; 2: also from a moving start where static exceeds kinetic friction")
#: With static above kinetic friction a point can have two steady states; the simulation methods then
#: solve it from a second start as well (README, "Two steady states") and store that state's per-point
#: variables beside those from rest, each name with this suffix.
MOVING_SUFFIX = "_moving"
#: the simulations (event exactly, rk4 on its grid) model the Jenkins contact too (kernels/jenkins.py,
#: kernels/jenkins_rk4.py); the closed forms and the paper's procedure do not
_SIMULATED = ("viscous_damping", "static_friction_ratio", "contact_stiffness")


def _without(settings: dict[str, Setting], *names: str) -> dict[str, Setting]:
    return {k: v for k, v in settings.items() if k not in names}


_METHODS = (
    Method(
        "theory", "Den Hartog's closed form: exact where the motion is continuous, a forecast of the regime "
        "elsewhere", settings={}, outputs=MODEL_OUTPUTS,
        algorithm={
            "first_harmonic": "exact x0 cos(r t) term plus Gauss-Legendre projection of the friction part, "
            "40 + ceil((1 + r) pi / r) nodes over a half period",
            "continuity_sup_S": "dense samples (>= 2048, 256 per natural period) then golden-section refinement",
            "joined_peak": "dense samples of |x| then bisection on d|x|/dtau",
        },
    ),
    Method(
        "event", "exact stick-slip: closed-form segments between events, steady state by march and shooting",
        settings={**_STEADY, "starts": _STARTS, "harmonics": _HARMONICS}, effects=_SIMULATED, outputs=OUTPUTS,
        accuracy_knobs=("stop_tol", "steady_tol"), calibrated_as="event", sweep=True,
    ),
    Method(
        "rk4", "fixed-step classical Runge-Kutta with a real stick mode: the baseline that shows what the closed "
        "forms buy", effects=_SIMULATED, outputs=SIMULATED_OUTPUTS, accuracy_knobs=("steady_tol", "steps_per_period"),
        calibrated_as="rk4",
        sweep=True,
        settings={**_without(_STEADY, "stop_tol"), "starts": _STARTS,
                  "steps_per_period": _int(256, 256, 100_000, "fixed RK4 steps per forcing period: fewer give "
                                           "errors above 1e-4 (84 % at 16) and false resonances; cost grows with "
                                           "it")},
    ),
    Method(
        "paper", "the paper's own procedure: ode45 from rest with a sgn friction law, stops counted from "
        "samples (reproduces its figures, errors included)",
        settings={
            # a point holds periods x samples_per_period samples: at most 10^7 (80 MB) with these bounds
            "periods": _int(200, 20, 10_000, "forcing periods simulated from rest: fewer leave the transient in "
                            "the measurement (cost grows with it)"),
            "samples_per_period": _int(64, 16, 1000, "output samples per forcing period: more count a smooth "
                                       "point's samples as stops; memory grows with it"),
            "transient_fraction": _float(0.5, 0.0, 0.9, "share of the periods discarded as transient; at least a "
                                         "tenth is kept to measure"),
            "rtol": _float(1e-3, 1e-10, 1e-3, "ode45's relative tolerance (default: MATLAB's): looser errs by tens "
                           "of percent, tighter than 1e-10 costs hours a point"),
            "atol": _float(1e-6, 1e-12, 1e-6, "ode45's absolute tolerance (default: MATLAB's): looser labels "
                           "moving points stuck"),
            "stick_velocity": _float(1e-3, 1e-3, 0.1, "a sample is stuck when |v| <= this x max |v|: outside, "
                                     "stick-slip reads as continuous"),
            "stuck_displacement_per_atol": _float(1000.0, 100.0, 1000.0, "no motion: max |q| <= this x atol; "
                                                  "larger labels moving points stuck"),
            "max_evaluations": _int(20_000_000, 10_000, 10**8, "right-hand-side evaluations per point at most: "
                                    "5.7 us each, so at most about 10 min a point"),
        },
    ),
    Method(
        "auto", "the theory where the mass provably slides without stops, the event simulation everywhere else "
        "(method_used says which)", outputs=OUTPUTS, accuracy_knobs=("stop_tol", "steady_tol"),
        calibrated_as="event",
        settings={**_STEADY, "theory_margin": _float(0.02, 1e-6, 1.0, "relative distance from the theory's "
                                                     "continuous limit inside which the simulation decides"),
                  "harmonics": _HARMONICS},
    ),
)

METHODS: Mapping[str, Method] = MappingProxyType({m.name: m for m in _METHODS})


def method(name: str) -> Method:
    try:
        return METHODS[name]
    except KeyError:
        raise KeyError(f"unknown method {name!r} (available: {', '.join(METHODS)})") from None


def able(capability: str) -> tuple[str, ...]:
    """Methods with a capability: an excitation, effect or output name, 'sweep' or 'accuracy'."""
    def has(m: Method) -> bool:
        if capability == "sweep":
            return m.sweep
        if capability == "accuracy":
            return bool(m.accuracy_knobs)
        return capability in m.excitations or capability in m.effects or capability in m.outputs
    return tuple(m.name for m in _METHODS if has(m))
