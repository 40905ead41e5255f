"""A structure spec: several masses, springs, dashpots and friction contacts (DESIGN §7), swept over the
(friction_scale, frequency) plane. A spec with a `structure:` key is one of these; every other spec is a
1-DoF sweep (spec.model.Spec), which this module leaves as it was.

    scene: {excitation: force}                 # force | base
    structure:
      masses: {blade: 1.0, damper: 0.1}        # named degrees of freedom, in the cube's dof order
      springs: [[ground, blade, 1.0], ...]     # [a, b, stiffness]; a, b: a mass, ground or base
      dampers: [[ground, blade, 0.004]]        # optional viscous dashpots, same form
      contacts: [{name: platform, between: [damper, ground], friction: 0.3}, ...]
      forcing: {blade: 1.0}                    # force excitation; base excitation: base_amplitude
    grid: {frequency: {start: 0.2, stop: 3.0, num: 561}, friction_scale: [0.5, 1.0]}

In place of masses, springs and dampers, a structure may be a reduced model (issue 31): `matrices: {file,
dofs, damping_ratios}` (M, K, C from a .npz or .mat, spec.reduced) or `modes: {frequencies,
damping_ratios, shapes}`; exactly one of masses, matrices, modes. Written with units it is physical
(spec.structure_units: read in SI, solved dimensionless); the grid may then give `frequency` with its
unit, and any structure `frequency_ratio` against its first natural frequency with every contact stuck or
free (`grid.reference`).

Refused, each at its key (`file:line:column: key: reason`): a mass, spring, dashpot or contact end that
names no mass (nor ground, nor base); an element or contact between a mass and itself, or between two
supports (ground and base hold no mass between them); a mass that is not positive; a stiffness, damping
or friction that is negative (a Jenkins contact's stiffness must be positive: zero is no contact spring);
a static friction ratio outside [1, 100]; two contacts of one name, a mass named `ground` or `base`, a
name no cube may hold; `forcing` under base excitation, `base_amplitude` under force excitation (where the
base holds still, as ground does), base excitation with nothing connected to the base, force excitation
without a nonzero force; no masses or no contacts; and a structure with an unrestrained rigid-body motion.
A reduced model's file is refused at `file` with the reason spec.reduced gives (missing, foreign, too
large, without M or K, a matrix not square, of another size than dofs, not finite, not symmetric, not
definite where it must be), and so are springs or dashpots beside it, damping given twice, and shapes
that are singular or not square; a physical structure's number without its unit or of another dimension,
and a frequency ratio against a reference that has a rigid-body motion.

The restraint rule: with every contact stuck (a Jenkins contact as its spring k_t, a rigid contact as a
rigid link w_jᵀx = 0), the stiffness must hold every motion: K_stuck restricted to the motions the rigid
links allow, Nᵀ K_stuck N, is positive definite (its least eigenvalue above 1e-12 of its largest).
Otherwise some motion meets no force at all, stuck or slipping, and drifts without bound. A mass held only
by a contact is restrained (it moves only while that contact slips, against a constant friction force:
the engine's singular-stiffness case), and damping restrains nothing.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal

import numpy as np
from pydantic import (
    BeforeValidator,
    Field,
    PrivateAttr,
    Strict,
    ValidationError,
    ValidationInfo,
    field_validator,
    model_validator,
)

from friction_sweep.printable import name_problem

from . import grid as g
from .base import Model as _Model
from .base import Sourced as _Sourced
from .base import problem as _error
from .base import raise_all as _raise_all
from .base import show
from .model import (
    HistoryPoints,
    SamplesPerPeriod,
    Sweep,
    _array_axis,
    _axis,
    _axis_size,
    _axis_values,
    _bound_problem,
    _Range,
    checked_output_path,
    sweep_and_starts,
)
from .structure_units import DEFAULT_REFERENCE, REFERENCES, StructureMap, frequency_axis_is_physical, is_physical
from .structure_units import to_si_structure as _to_si_structure

#: the two supports an element may connect a mass to: `base` moves under base excitation, `ground` never
SUPPORTS = ("ground", "base")
EXCITATIONS = ("force", "base")
#: the method that solves a structure unless the spec names another (friction_sweep.structures, the exact
#: event-driven engine), and every method that can: rk4 integrates the same modes on a fixed grid
METHOD = "event"
METHODS = ("event", "rk4")
#: output groups a structure spec may ask for, and the cube variables each brings (storage.schema's
#: STRUCTURE_VARIABLES); `slips_per_period` only where a contact is a Jenkins element
OUTPUT_GROUPS = {
    "amplitude": ("amplitude", "peak_amplitude"),
    "phase": ("phase",),
    "regime": ("regime", "stops_per_period", "slips_per_period", "stuck_fraction", "periods", "steady_state",
               "orbit_period"),
    "friction_energy": ("friction_energy",),
    "stability": ("floquet_multiplier",),
    "harmonics": ("response_harmonic_real", "response_harmonic_imag", "friction_harmonic_real",
                  "friction_harmonic_imag"),
    # on dims of their own (history_point, sample), beside the plane: batch.structure_sweep.histories
    "time_history": (),
}
DEFAULT_OUTPUTS = ("amplitude", "phase", "regime")
#: a static over kinetic friction ratio: measured ratios are 1-2 (the 1-DoF effect's bounds)
STATIC_RATIO = (1.0, 100.0)
#: the base's amplitude where a base excitation gives none (amplitudes are then transmissibilities as they are)
DEFAULT_BASE_AMPLITUDE = 1.0
#: the kind of a problem with a mapping's key (a mass's name, a forced mass): located at the key, not its value
KEY_PROBLEM = "key_problem"
#: the most masses, and the most contacts, a structure has (a cube's `dof` and `contact` names)
MAX_NAMES = 1024
#: the ways a structure is given: masses with springs and dampers, a reduced model's matrices, or its modes
MODEL_FORMS = ("masses", "matrices", "modes")
#: the stiffness left to a motion with every contact stuck, relative to the largest, below which it is free
RESTRAINT_RTOL = 1e-12

Finite = Annotated[float, Strict(), Field(allow_inf_nan=False)]
PositiveNumber = Annotated[float, Strict(), Field(allow_inf_nan=False, gt=0)]
NonNegativeNumber = Annotated[float, Strict(), Field(allow_inf_nan=False, ge=0)]


def _number_problem(value: Any, *, positive: bool) -> str | None:
    """Why `value` is no stiffness, damping or friction (positive: no mass), or None."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return f"must be a number (got {show(value)})"
    if not np.isfinite(float(value)):
        return f"must be a finite number (got {show(value)})"
    if positive and value <= 0:
        return f"must be > 0 (got {show(value)})"
    if value < 0:
        return f"must be >= 0 (got {show(value)})"
    return None


def _name_problem(value: Any) -> str | None:
    if not isinstance(value, str) or not value:
        return f"must be a non-empty name (got {show(value)})"
    problem = name_problem(value)
    return None if problem is None else f"{show(value)} {problem}"


def _elements(what: str, unit: str):
    """A list of [a, b, value] (a spring's stiffness, a dashpot's damping), each checked for its form and
    value here; whether a and b name masses is the structure's check."""

    def read(v: Any) -> Any:
        if v is None:  # `dampers:` left empty
            return ()
        if not isinstance(v, list):
            raise _error("elements_type", f"must be a list of [a, b, {unit}] (got {show(v)})")
        problems = []
        out = []
        for i, item in enumerate(v):
            if not isinstance(item, list) or len(item) != 3:
                problems.append(_error("element_form", f"a {what} is [a, b, {unit}]: a list of two ends (a mass, "
                                       f"ground or base) and a number (got {show(item)})", (i,)))
                continue
            for k in (0, 1):
                if (reason := _name_problem(item[k])) is not None:
                    problems.append(_error("element_end", reason, (i, k)))
            if (reason := _number_problem(item[2], positive=False)) is not None:
                problems.append(_error("element_value", f"a {what}'s {unit} {reason}", (i, 2)))
            out.append(tuple(item))
        _raise_all(what, problems)
        return tuple((a, b, float(x)) for a, b, x in out)

    return Annotated[tuple[tuple[str, str, float], ...], BeforeValidator(read)]


if TYPE_CHECKING:  # what pydantic builds from _elements, as a type checker can read it
    Springs = tuple[tuple[str, str, float], ...]
    Dampers = tuple[tuple[str, str, float], ...]
else:
    Springs = _elements("spring", "stiffness")
    Dampers = _elements("dashpot", "damping")


class StructureScene(_Model):
    excitation: str

    @field_validator("excitation", mode="before")
    @classmethod
    def _known(cls, v: Any) -> Any:
        if not isinstance(v, str) or v not in EXCITATIONS:
            raise _error("unknown_excitation", f"a structure's excitation is one of: {', '.join(EXCITATIONS)} "
                         f"(got {show(v)}; the 1-DoF `joined` scene is a structure whose spring and contact both "
                         "go to base)")
        return v


class Contact(_Model):
    """A Coulomb contact between two ends: rigid, or a Jenkins element where `stiffness` is given."""

    name: str
    between: tuple[str, str]
    friction: NonNegativeNumber
    stiffness: PositiveNumber | None = None
    static_friction_ratio: Annotated[float, Strict(), Field(allow_inf_nan=False, ge=STATIC_RATIO[0],
                                                            le=STATIC_RATIO[1])] = 1.0

    @field_validator("name", mode="before")
    @classmethod
    def _name(cls, v: Any) -> Any:
        if (reason := _name_problem(v)) is not None:
            raise _error("contact_name", reason)
        return v

    @field_validator("between", mode="before")
    @classmethod
    def _ends(cls, v: Any) -> Any:
        if not isinstance(v, list) or len(v) != 2:
            raise _error("contact_ends", f"must be [a, b]: the contact's two ends, each a mass, ground or base "
                         f"(got {show(v)})")
        _raise_all("between", [_error("contact_end", reason, (k,)) for k in (0, 1)
                               if (reason := _name_problem(v[k])) is not None])
        return tuple(v)


def _masses(v: Any) -> Any:
    if not isinstance(v, dict):
        raise _error("masses_type", f"must be a mapping of mass names to masses (got {show(v)})")
    if not v:
        raise _error("masses_empty", "a structure needs at least one mass")
    if len(v) > MAX_NAMES:
        raise _error("masses_many", f"{len(v)} masses; a structure has at most {MAX_NAMES}")
    problems = []
    for name, m in v.items():
        if name in SUPPORTS:
            problems.append(_error(KEY_PROBLEM, f"{name!r} names a support (ground, base), not a mass: name the "
                                   "mass otherwise", (name,)))
        elif (reason := _name_problem(name)) is not None:
            problems.append(_error(KEY_PROBLEM, reason, (name,)))
        elif (reason := _number_problem(m, positive=True)) is not None:
            problems.append(_error("mass_value", f"a mass {reason}", (name,)))
    _raise_all("masses", problems)
    return {str(k): float(x) for k, x in v.items()}


def _dof_names(v: Any) -> Any:
    """A list of DoF names (a reduced model's rows, in order): each a name, none twice, none a support."""
    if not isinstance(v, list) or not v:
        raise _error("dofs_type", f"must be a non-empty list of DoF names, one per row of the matrices (got {show(v)})")
    if len(v) > MAX_NAMES:
        raise _error("dofs_many", f"{len(v)} DoFs; a structure has at most {MAX_NAMES}")
    problems = []
    for i, name in enumerate(v):
        if name in SUPPORTS:
            problems.append(_error("dof_name", f"{name!r} names a support (ground, base), not a DoF", (i,)))
        elif (reason := _name_problem(name)) is not None:
            problems.append(_error("dof_name", reason, (i,)))
        elif name in v[:i]:
            problems.append(_error("dof_duplicate", f"DoF {name!r} is named twice (first at [{v.index(name)}])", (i,)))
    _raise_all("dofs", problems)
    return tuple(v)


def _spec_folder(info: ValidationInfo) -> Path:
    """The folder a spec's relative file names resolve against: its own (parse passes its source), else here."""
    source = (info.context or {}).get("source") if isinstance(info.context, dict) else None
    return Path(source).parent if source and not str(source).startswith("<") else Path(".")


class Matrices(_Model):
    """`structure.matrices`: a reduced model's M, K (and C) from a file (spec.reduced), its DoFs named
    in the matrices' order; `damping_ratios` (one per mode, or one for all) where the file has no C."""

    file: str
    dofs: Annotated[tuple[str, ...], BeforeValidator(_dof_names)]
    damping_ratios: tuple[NonNegativeNumber, ...] | None = None
    _matrices: tuple[np.ndarray, np.ndarray, np.ndarray] | None = PrivateAttr(default=None)

    @field_validator("file", mode="before")
    @classmethod
    def _file_name(cls, v: Any) -> Any:
        if not isinstance(v, str) or not v:
            raise _error("model_file", f"must be the name of a .npz or .mat file (got {show(v)})")
        return v

    @model_validator(mode="after")
    def _load(self, info: ValidationInfo) -> Matrices:
        from .reduced import ModelError, load_matrices, modal_damping

        path = Path(self.file)
        path = path if path.is_absolute() else _spec_folder(info) / path
        n = len(self.dofs)
        try:
            M, K, C = load_matrices(path, n)
        except ModelError as err:
            raise _error("model_file", str(err), ("file",)) from None
        ratios = self.damping_ratios
        if ratios is not None:
            if C is not None:
                raise _error("damping_twice", f"{path} holds C: give damping by C or by damping_ratios, not both",
                             ("damping_ratios",))
            if len(ratios) not in (1, n):
                raise _error("damping_ratios_size", f"{len(ratios)} damping ratios for {n} modes: give one per mode "
                             "(ascending frequency) or one for all", ("damping_ratios",))
            C = modal_damping(M, K, np.broadcast_to(np.asarray(ratios, dtype=float), (n,)))
        self._matrices = (M, K, np.zeros((n, n)) if C is None else C)
        return self

    @property
    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(M, K, C), C zero where neither the file nor damping ratios give damping."""
        assert self._matrices is not None
        return self._matrices


class Modes(_Model):
    """`structure.modes`: a structure known by its modes (spec.reduced.from_modes): angular natural
    frequencies (the structure's units), damping ratios, and mass-normalised shapes at as many named DoFs as
    modes, `{dof: [value in mode 1, mode 2, ...]}`."""

    frequencies: tuple[NonNegativeNumber, ...]
    damping_ratios: tuple[NonNegativeNumber, ...] | None = None
    shapes: dict[str, tuple[Finite, ...]]
    _matrices: tuple[np.ndarray, np.ndarray, np.ndarray] | None = PrivateAttr(default=None)

    @field_validator("shapes", mode="before")
    @classmethod
    def _shape_names(cls, v: Any) -> Any:
        if not isinstance(v, dict) or not v:
            raise _error("shapes_type", f"must be a mapping of DoF names to mode-shape values (got {show(v)})")
        _dof_names(list(v))
        return v

    @model_validator(mode="after")
    def _build(self) -> Modes:
        from .reduced import ModelError, from_modes

        n = len(self.frequencies)
        problems = []
        if len(self.shapes) != n:
            problems.append(_error("modes_size", f"{len(self.shapes)} DoFs for {n} modes: name as many DoFs as modes "
                                   "(the shapes' matrix is square)", ("shapes",)))
        for name, row in self.shapes.items():
            if len(row) != n:
                problems.append(_error("modes_size", f"{len(row)} values for {n} modes: give one per mode",
                                       ("shapes", name)))
        if self.damping_ratios is not None and len(self.damping_ratios) not in (1, n):
            problems.append(_error("damping_ratios_size", f"{len(self.damping_ratios)} damping ratios for {n} modes: "
                                   "give one per mode or one for all", ("damping_ratios",)))
        _raise_all("modes", problems)
        ratios = np.broadcast_to(np.asarray(self.damping_ratios or (0.0,), dtype=float), (n,))
        try:
            self._matrices = from_modes(np.asarray(self.frequencies, dtype=float), ratios,
                                        np.array(list(self.shapes.values()), dtype=float).reshape(n, n))
        except ModelError as err:
            raise _error("modes_singular", str(err), ("shapes",)) from None
        return self

    @property
    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        assert self._matrices is not None
        return self._matrices


class Structure(_Model):
    """`structure:` of a spec (the module's docstring says what is refused, and the restraint rule)."""

    masses: Annotated[dict[str, float] | None, BeforeValidator(_masses)] = None
    matrices: Matrices | None = None
    modes: Modes | None = None
    springs: Springs = ()
    dampers: Dampers = ()
    contacts: tuple[Contact, ...]
    forcing: dict[str, Finite] | None = None
    base_amplitude: PositiveNumber | None = None
    #: "physical": every quantity with its unit, read in SI (spec.structure_units); set where any is written so
    units: Literal["physical"] | None = None

    @model_validator(mode="before")
    @classmethod
    def _si(cls, data: Any) -> Any:
        if not is_physical(data):
            return data
        converted, problems = _to_si_structure(data)
        _raise_all("structure", problems)
        return converted

    @field_validator("contacts", mode="before")
    @classmethod
    def _some_contacts(cls, v: Any) -> Any:
        if v is None or v == []:
            raise _error("contacts_empty", "a structure needs at least one contact: without friction it is linear, "
                         "X = (K - omega^2 M + i omega C)^-1 F, and friction_scale sweeps nothing")
        if isinstance(v, list) and len(v) > MAX_NAMES:
            raise _error("contacts_many", f"{len(v)} contacts; a structure has at most {MAX_NAMES}")
        return v

    @model_validator(mode="after")
    def _connected(self) -> Structure:
        forms = [k for k in MODEL_FORMS if getattr(self, k) is not None]
        if len(forms) != 1:
            raise _error("model_form", "give the structure one way: masses (with springs and dampers), matrices "
                         f"(a reduced model's file) or modes (got {' and '.join(forms) or 'none of them'})",
                         (forms[-1],) if forms else ())
        if self.masses is None:
            extra = [k for k in ("springs", "dampers") if getattr(self, k)]
            if extra:
                raise _error("model_elements", f"{extra[0]} are for a structure of masses: a reduced model's "
                             "stiffness and damping are in its matrices", (extra[0],))
        problems = list(self._end_problems())
        names: dict[str, int] = {}
        for j, c in enumerate(self.contacts):
            if c.name in names:
                problems.append(_error("contact_duplicate", f"contact name {c.name!r} is given twice (first as "
                                       f"contacts[{names[c.name]}])", ("contacts", j, "name")))
            names.setdefault(c.name, j)
        for name in self.forcing or {}:
            if name not in self.dofs:
                problems.append(_error(KEY_PROBLEM, f"{show(name)} is no mass (masses: "
                                       f"{', '.join(self.dofs)})", ("forcing", name)))
        _raise_all("structure", problems)
        _raise_all("structure", self._restraint_problems())
        return self

    @property
    def dofs(self) -> tuple[str, ...]:
        """The structure's degrees of freedom by name, in the cube's dof order."""
        if self.matrices is not None:
            return self.matrices.dofs
        if self.modes is not None:
            return tuple(self.modes.shapes)
        return tuple(self.masses or ())

    @property
    def given_matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """(M, K, C) of a reduced model (matrices or modes); None for a structure of masses."""
        form = self.matrices if self.matrices is not None else self.modes
        return None if form is None else form.matrices

    def _end_problems(self):
        ends = set(self.dofs) | set(SUPPORTS)
        known = f"a mass ({', '.join(self.dofs)}), ground or base"
        items = [("springs", i, (a, b), (i,)) for i, (a, b, _) in enumerate(self.springs)]
        items += [("dampers", i, (a, b), (i,)) for i, (a, b, _) in enumerate(self.dampers)]
        items += [("contacts", j, c.between, (j, "between")) for j, c in enumerate(self.contacts)]
        for key, _, (a, b), at in items:
            bad = False
            for k, end in enumerate((a, b)):
                if end not in ends:
                    bad = True
                    yield _error("unknown_end", f"{show(end)} is no mass: an end is {known}", (key, *at, k))
            if bad:
                continue
            what = {"springs": "a spring", "dampers": "a dashpot", "contacts": "a contact"}[key]
            if a == b:
                yield _error("same_ends", f"{what} between {a!r} and itself acts on nothing: its two ends must "
                             "differ", (key, *at, 1))
            elif a in SUPPORTS and b in SUPPORTS:
                yield _error("no_mass", f"{what} between {a} and {b} holds no mass: one end must be a mass",
                             (key, *at, 1))

    def linear(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(M, K, W, kt): the linear structure's mass and stiffness (springs or a model's), each contact's
        direction w_j (rows) and Jenkins stiffness (0 for a rigid contact), as spec.natural_frequencies takes them."""
        n = len(self.dofs)
        index = {name: i for i, name in enumerate(self.dofs)}

        def direction(a: str, b: str) -> np.ndarray:
            w = np.zeros(n)
            if a in index:
                w[index[a]] += 1.0
            if b in index:
                w[index[b]] -= 1.0
            return w

        given = self.given_matrices
        if given is None:
            M, K = np.diag([(self.masses or {})[name] for name in self.dofs]), np.zeros((n, n))
            for a, b, k in self.springs:
                w = direction(a, b)
                K += k * np.outer(w, w)
        else:
            M, K = given[0], given[1].copy()
        W = np.array([direction(*c.between) for c in self.contacts]).reshape(len(self.contacts), n)
        kt = np.array([0.0 if c.stiffness is None else c.stiffness for c in self.contacts])
        return M, K, W, kt

    def _restraint_problems(self):
        _, K, W, kt = self.linear()
        n = len(self.dofs)
        K = K + (W.T * kt) @ W  # with every contact stuck: a Jenkins contact as its spring
        rigid = list(W[kt == 0.0])
        N = np.eye(n)
        if rigid:  # the motions the stuck rigid contacts allow: the null space of their directions
            _, s, vt = np.linalg.svd(np.array(rigid), full_matrices=True)
            rank = int(np.count_nonzero(s > 1e-12 * s.max()))
            N = vt[rank:].T
        if N.shape[1] == 0:
            return []
        held, vectors = np.linalg.eigh(N.T @ K @ N)
        scale = float(np.abs(K).max())
        if held[0] > RESTRAINT_RTOL * scale and scale > 0:
            return []
        motion = N @ vectors[:, 0]
        moving = [name for name, x in zip(self.dofs, motion, strict=True) if abs(x) > 1e-6 * np.abs(motion).max()]
        at = {"masses": ("masses", moving[0]), "matrices": ("matrices", "dofs", self.dofs.index(moving[0])),
              "modes": ("modes", "shapes", moving[0])}[self.form]
        return [_error(KEY_PROBLEM if self.form != "matrices" else "unrestrained",
                       f"unrestrained: with every contact stuck, nothing holds the motion of "
                       f"{', '.join(map(repr, moving))} (a rigid-body motion): connect it to ground or base by a "
                       "spring or a contact", at)]

    @property
    def form(self) -> str:
        """How the structure is given: "masses", "matrices" or "modes" (MODEL_FORMS)."""
        return next(k for k in MODEL_FORMS if getattr(self, k) is not None)

    @property
    def base_motion(self) -> float:
        """The base's amplitude under base excitation: as given, else DEFAULT_BASE_AMPLITUDE."""
        return DEFAULT_BASE_AMPLITUDE if self.base_amplitude is None else self.base_amplitude

    def describe(self) -> list[str]:
        """The structure in a few lines (fsweep validate and info)."""
        if self.matrices is not None:
            lines = [f"matrices: {self.matrices.file}, dofs " + ", ".join(self.matrices.dofs)]
        elif self.modes is not None:
            lines = ["modes: angular frequencies " + ", ".join(f"{w:g}" for w in self.modes.frequencies)
                     + " at dofs " + ", ".join(self.modes.shapes)]
        else:
            lines = ["masses: " + ", ".join(f"{k} {v:g}" for k, v in (self.masses or {}).items())]
        if self.springs:
            lines.append("springs: " + ", ".join(f"{a}-{b} {k:g}" for a, b, k in self.springs))
        if self.dampers:
            lines.append("dampers: " + ", ".join(f"{a}-{b} {c:g}" for a, b, c in self.dampers))
        for c in self.contacts:
            kind = "rigid" if c.stiffness is None else f"Jenkins, stiffness {c.stiffness:g}"
            static = f", static ratio {c.static_friction_ratio:g}" if c.static_friction_ratio != 1.0 else ""
            lines.append(f"contact {c.name}: {c.between[0]}-{c.between[1]}, friction {c.friction:g}, {kind}{static}")
        if self.forcing:
            lines.append("forcing: " + ", ".join(f"{k} {v:g}" for k, v in self.forcing.items()))
        return lines


class FrequencyRange(_Range):
    start: PositiveNumber
    stop: PositiveNumber


class ScaleRange(_Range):
    start: NonNegativeNumber
    stop: NonNegativeNumber


def _positive(values):
    return values > 0


def _nonnegative(values):
    return values >= 0


if TYPE_CHECKING:
    FrequencyAxis = float | list[float] | np.ndarray | FrequencyRange
    ScaleAxis = float | list[float] | np.ndarray | ScaleRange
else:
    FrequencyAxis = _axis(PositiveNumber, FrequencyRange, _array_axis(
        _positive, "> 0", "the angular frequency of the excitation, in the structure's units"))
    ScaleAxis = _axis(NonNegativeNumber, ScaleRange, _array_axis(
        _nonnegative, ">= 0", "a factor on every contact's friction"))


class StructureGrid(_Model):
    """The plane: angular frequencies of the excitation (the structure's units) by friction scales (a
    factor on every contact's friction; absent: 1, the friction as given)."""

    frequency: FrequencyAxis | None = None
    frequency_ratio: FrequencyAxis | None = None
    reference: Literal["stuck", "free"] = DEFAULT_REFERENCE  # type: ignore[assignment]
    friction_scale: ScaleAxis = 1.0
    _values: dict[str, np.ndarray] = PrivateAttr(default_factory=dict)

    @field_validator("reference", mode="before")
    @classmethod
    def _reference(cls, v: Any) -> Any:
        if v not in REFERENCES:
            raise _error("reference", f"the natural frequency a frequency ratio is taken against: one of "
                         f"{', '.join(REFERENCES)} (every contact stuck, or every contact free) (got {show(v)})")
        return v

    @model_validator(mode="after")
    def _build(self):
        given = [k for k in ("frequency", "frequency_ratio") if getattr(self, k) is not None]
        if len(given) != 1:
            raise _error("frequency_axis", "give the frequencies one way: frequency (angular, or with its unit in a "
                         "physical structure) or frequency_ratio (against the first natural frequency) (got "
                         f"{' and '.join(given) or 'neither'})", (given[-1],) if given else ())
        axis_name = given[0]
        nf, ns = _axis_size(getattr(self, axis_name)), _axis_size(self.friction_scale)
        if nf * ns > g.MAX_POINTS:
            raise _error("too_many_points", f"grid has {nf * ns} points ({ns} x {nf}); at most {g.MAX_POINTS} "
                         "are allowed")
        for name in (axis_name, "friction_scale"):
            axis = getattr(self, name)
            values = _axis_values(axis)
            if isinstance(axis, _Range) and (g.first_not_increasing(values) is not None or values[-1] > axis.stop):
                raise _error("grid_too_fine", f"spacing is finer than {g.SIGNIFICANT_DIGITS} significant digits: "
                             "values collide", (name,))
            values.flags.writeable = False
            self._values[name] = values
        return self

    def values(self, name: str) -> np.ndarray:
        values = self._values[name]
        values.flags.writeable = False  # re-set after unpickling
        return values

    @property
    def written_frequency(self) -> np.ndarray:
        """The frequency axis as the spec writes it: `frequency`, or `frequency_ratio` where it gives that."""
        return self.values("frequency_ratio" if self.frequency_ratio is not None else "frequency")


class StructureTimeHistory(_Model):
    """Points (frequency, friction_scale) whose steady orbits are stored (outputs: time_history), sampled
    samples_per_period times a forcing period over the orbit's periods (structures.time_histories)."""

    points: HistoryPoints
    samples_per_period: SamplesPerPeriod = 256

    @field_validator("points")
    @classmethod
    def _in_range(cls, v):
        problems = []
        for i, (w, scale) in enumerate(v):
            if not w > 0:
                problems.append(_error("history_frequency", f"the angular frequency must be > 0 (got {show(w)})",
                                       (i, 0)))
            if not scale >= 0:
                problems.append(_error("history_friction_scale", f"friction_scale must be >= 0 (got {show(scale)})",
                                       (i, 1)))
        _raise_all("points", problems)
        return v


class StructureSpec(_Sourced):
    """A validated structure spec. Grid values: `frequency`, `friction_scale` (read-only float64)."""

    scene: StructureScene
    structure: Structure
    grid: StructureGrid
    method: str = METHOD
    outputs: tuple[str, ...] = DEFAULT_OUTPUTS
    output: str | None = None
    settings: dict[str, Any] = Field(default_factory=dict)
    #: the error the run must meet: the method's knobs from the benchmark's structure rows (`fsweep bench`,
    #: bench.workprecision.STRUCTURE_ROWS), as the 1-DoF spec's `accuracy:`
    accuracy: Annotated[float, Strict(), Field(allow_inf_nan=False, gt=0, lt=1)] | None = None
    #: a stepped-sine sweep along frequency at each friction scale (the 1-DoF `sweep:`, structures.starts)
    sweep: Sweep | None = None
    time_history: StructureTimeHistory | None = None

    @field_validator("method", mode="before")
    @classmethod
    def _structure_method(cls, v: Any) -> Any:
        if v not in METHODS:
            raise _error("structure_method", f"a structure is solved by method {METHOD!r}, the exact event-driven "
                         f"engine, or 'rk4', fixed-step Runge-Kutta with the same modes (got {show(v)})")
        return v

    @field_validator("outputs", mode="before")
    @classmethod
    def _outputs(cls, v: Any) -> Any:
        known = ", ".join(OUTPUT_GROUPS)
        if not isinstance(v, (list, tuple)):
            raise _error("outputs_type", f"must be a list of output names (got {show(v)})")
        if not v:
            raise _error("outputs_empty", f"must not be empty (choose from: {known})")
        for i, name in enumerate(v):
            if not isinstance(name, str) or name not in OUTPUT_GROUPS:
                raise _error("unknown_output", f"unknown output {show(name)} for a structure (known: {known})", (i,))
            if name in v[:i]:
                raise _error("duplicate_output", f"output {name!r} is listed twice", (i,))
        return tuple(sorted(v, key=list(OUTPUT_GROUPS).index))

    @field_validator("output", mode="before")
    @classmethod
    def _output_path(cls, v: Any) -> Any:
        return checked_output_path(v)  # the one rule for where a result goes

    @field_validator("settings", mode="before")
    @classmethod
    def _settings(cls, v: Any, info: ValidationInfo) -> Any:
        from friction_sweep.catalogue import METHODS as CATALOGUED

        if v is None:  # `settings:` left empty
            return {}
        if not isinstance(v, dict):
            raise _error("settings_type", f"must be a mapping of settings (got {show(v)})")
        method = info.data.get("method", METHOD)  # validated before settings (field order)
        known = CATALOGUED[method].settings
        allowed = STRUCTURE_SETTINGS[method]
        problems = []
        for key, value in v.items():
            if key in DESIGN_SETTINGS:  # a mass's name: checked against the structure in _excitation
                if not isinstance(value, str) or not value:
                    problems.append(_error("setting_type", f"must be a mass's name (got {show(value)})", (key,)))
            elif key not in allowed:
                problems.append(_error("unknown_setting", f"unknown setting {show(key)} for a structure solved by "
                                       f"{method} (allowed: {', '.join(allowed + DESIGN_SETTINGS)})", (key,)))
            elif (reason := _bound_problem(known[key].kind, known[key], value)) is not None:
                problems.append(_error("setting_range", reason, (key,)))
        _raise_all("settings", problems)
        return v

    _map: StructureMap | None = PrivateAttr(default=None)
    _frequency: np.ndarray | None = PrivateAttr(default=None)
    _history_frequency: np.ndarray | None = PrivateAttr(default=None)

    @model_validator(mode="before")
    @classmethod
    def _physical_frequency(cls, data: Any) -> Any:
        """A physical structure's grid frequency, with its unit, as angular frequencies in rad/s; a plain one's
        refused where it carries a unit (and the reverse)."""
        from pydantic_core import PydanticCustomError

        from .quantities import FREQUENCY
        from .system import physical_axis

        if not isinstance(data, dict) or not isinstance(data.get("grid"), dict) or "frequency" not in data["grid"]:
            return data
        axis = data["grid"]["frequency"]
        physical, written = is_physical(data.get("structure")), frequency_axis_is_physical(axis)
        if not physical:
            if written:
                raise _error("frequency_unit", "a frequency with a unit needs a physical structure (masses, "
                             "stiffnesses and frictions with their units); here it is the structure's angular "
                             "frequency, a number", ("grid", "frequency"))
            return data
        try:
            hz = physical_axis(axis, FREQUENCY)
        except PydanticCustomError as err:
            raise _error(err.type, err.message(), ("grid", "frequency", *(err.context or {}).get("at", ()))) from None
        except ValidationError as err:
            _raise_all("grid", [_error(e["type"], e["msg"], ("grid", "frequency", *(e.get("ctx") or {}).get("at", ())))
                                for e in err.errors()])
        return {**data, "grid": {**data["grid"], "frequency": [2.0 * math.pi * f for f in hz]}}

    @model_validator(mode="before")
    @classmethod
    def _physical_history(cls, data: Any) -> Any:
        """The time-history points' frequencies written as the grid's: a physical structure's with their unit
        (as angular frequencies in rad/s from here on, like its grid's), where its grid gives `frequency`;
        plain numbers otherwise (the structure's angular frequencies, or frequency ratios with a grid of
        `frequency_ratio`)."""
        from .quantities import FREQUENCY, QuantityError, to_si

        if not isinstance(data, dict) or not isinstance(data.get("time_history"), dict):
            return data
        points = data["time_history"].get("points")
        grid = data.get("grid")
        if not isinstance(points, list) or not isinstance(grid, dict):
            return data
        with_unit = is_physical(data.get("structure")) and "frequency" in grid
        problems, converted = [], []
        for i, p in enumerate(points):
            if not (isinstance(p, list) and len(p) == 2):
                converted.append(p)  # the field's own checks say why
                continue
            at = ("time_history", "points", i, 0)
            if not with_unit:
                if isinstance(p[0], str):
                    problems.append(_error("history_unit", "a frequency with a unit goes with a physical "
                                           "structure's grid of frequencies; here it is a number, as the grid's "
                                           "(the structure's angular frequency, or a frequency ratio)", at))
                converted.append(p)
                continue
            if not isinstance(p[0], str):
                problems.append(_error("history_unit", f"a physical structure's point gives its frequency with a "
                                       f"unit, as its grid does (e.g. '12 Hz'; got {show(p[0])})", at))
                continue
            try:
                converted.append([2.0 * math.pi * to_si(p[0], FREQUENCY), p[1]])
            except QuantityError as err:
                problems.append(_error("quantity", str(err), at))
        _raise_all("time_history", problems)
        return {**data, "time_history": {**data["time_history"], "points": converted}}

    @model_validator(mode="after")
    def _excitation(self):
        _raise_all("Spec", [*self._excitation_problems(), *self._harmonic_problems(), *self._accuracy_problems(),
                            *self._history_problems()])
        self._scale()
        return self

    def _scale(self) -> None:
        """A physical structure's map to the dimensionless one (spec.structure_units), and the engine's
        frequencies: omega / omega_0, or the frequency ratios as given (a plain structure: its frequencies, or
        the ratios times its reference natural frequency)."""
        from .structure_units import structure_map
        from .system import ratios

        grid = self.grid
        by_ratio = grid.frequency_ratio is not None
        history = None if self.time_history is None else np.array([p[0] for p in self.time_history.points])
        if self.structure.units != "physical" and not by_ratio:
            self._history_frequency = history
            return
        try:
            mapped = structure_map(self.structure, self.scene.excitation, grid.reference)
        except ValueError as err:
            raise _error("reference", str(err), ("grid", "reference")) from None
        given = grid.written_frequency

        def engine(values: np.ndarray) -> np.ndarray:
            if self.structure.units == "physical":
                return values if by_ratio else ratios(values, mapped.omega)
            return values * mapped.omega

        if self.structure.units == "physical":
            self._map = mapped
        frequency = engine(given)
        self._history_frequency = None if history is None else engine(history)
        if not (np.isfinite(frequency).all() and (frequency > 0).all()):
            raise _error("frequency_range", "the frequencies over the reference natural frequency leave a double's "
                         "range", ("grid",))
        frequency.flags.writeable = False
        self._frequency = frequency

    def describe(self) -> list[str]:
        """The structure in a few lines, and a physical one's map to the dimensionless one (fsweep validate)."""
        lines = self.structure.describe()
        if self.structure.units == "physical":
            lines[0] = "in SI units (kg, N/m, N s/m, N, m): " + lines[0]
        if self._map is not None:
            lines += self._map.describe()
        return lines

    @property
    def physical(self) -> StructureMap | None:
        """A physical structure's scales and dimensionless definition (spec.structure_units), else None."""
        return self._map

    def _excitation_problems(self):
        if self.sweep is not None and "starts" in self.settings:  # the 1-DoF spec's rule
            yield sweep_and_starts()
        st, excitation = self.structure, self.scene.excitation
        for key in DESIGN_SETTINGS:
            if key in self.settings and self.settings[key] not in st.dofs:
                yield _error("unknown_dof", f"{show(self.settings[key])} is not a mass of the structure (masses: "
                             f"{', '.join(st.dofs)})", ("settings", key))
        elements = [("springs", i, (a, b)) for i, (a, b, _) in enumerate(st.springs)]
        elements += [("dampers", i, (a, b)) for i, (a, b, _) in enumerate(st.dampers)]
        elements += [("contacts", j, c.between) for j, c in enumerate(st.contacts)]
        if excitation == "force":
            if st.base_amplitude is not None:
                yield _error("amplitude_force", "a force excitation's amplitudes are `forcing: {mass: force}`; "
                             "base_amplitude is for excitation base", ("structure", "base_amplitude"))
            if st.forcing is None:
                yield _error("forcing_missing", "a force excitation needs `forcing: {mass: amplitude}`",
                             ("structure",))
            elif not any(st.forcing.values()):
                yield _error("forcing_zero", "every forcing amplitude is 0: nothing drives the structure",
                             ("structure", "forcing"))
        else:
            if st.forcing is not None:
                yield _error("forcing_base", "forcing is for excitation force: under base excitation the base's "
                             "motion (base_amplitude) drives the structure", ("structure", "forcing"))
            if not any("base" in ends for _, _, ends in elements):
                yield _error("base_unconnected", "nothing connects to base, so the base's motion drives nothing: "
                             "connect a spring, dashpot or contact to base", ("structure",))

    def _accuracy_problems(self):
        """`accuracy:` sets the method's accuracy knobs (catalogue): not beside them (the 1-DoF spec's rule)."""
        from friction_sweep.catalogue import METHODS as CATALOGUED

        if self.accuracy is None:
            return
        knobs = sorted(set(self.settings) & set(CATALOGUED[self.method].accuracy_knobs))
        if knobs:
            yield _error("accuracy_and_knobs", f"give either accuracy or the knobs it sets, not both "
                         f"(settings also has {', '.join(knobs)})", ("accuracy",))

    def _history_problems(self):
        """`time_history:` with the output time_history, and the output with it, not in a swept run (the 1-DoF
        spec's rules); its samples bounded (its points' frequencies: _physical_history)."""
        from .model import MAX_HISTORY_SAMPLES

        wanted, given = "time_history" in self.outputs, self.time_history is not None
        if wanted and not given:
            yield _error("history_missing", "outputs lists time_history: give `time_history: {points: [[frequency, "
                         "friction_scale], ...]}`", ("outputs",))
        if given and not wanted:
            yield _error("history_unused", "time_history is given but not listed in outputs", ("time_history",))
        if not (wanted and given):
            return
        assert self.time_history is not None
        if self.sweep is not None:
            yield _error("sweep_and_history", "a swept run's time histories would not follow the sweep: store them "
                         "from a run without sweep", ("sweep",))
        rows = len(self.time_history.points) * self.time_history.samples_per_period * max(
            len(self.structure.dofs), len(self.structure.contacts))
        if rows > MAX_HISTORY_SAMPLES:
            yield _error("history_size", f"{rows} samples (points x samples per period x masses or contacts) exceed "
                         f"{MAX_HISTORY_SAMPLES} per variable", ("time_history", "samples_per_period"))

    @property
    def history_points(self) -> np.ndarray:
        """The time-history points (P, 2): the engine's angular frequency (as `frequency`: a physical
        structure's over omega_0, a frequency ratio's times the reference natural frequency) and friction_scale."""
        assert self.time_history is not None and self._history_frequency is not None
        scale = np.array([p[1] for p in self.time_history.points], dtype=float)
        return np.column_stack([self._history_frequency, scale])

    def _harmonic_problems(self):
        """The output `harmonics` (settings.harmonics: its highest harmonic H; structures.harmonics): the exact
        engine's (the event method), H + 1 values per point and mass or contact, not for a swept run (the
        1-DoF spec's rules)."""
        from friction_sweep.catalogue import METHODS as CATALOGUED

        wanted = "harmonics" in self.outputs
        if not wanted and "harmonics" in self.settings:
            yield _error("harmonics_unused", "given, but harmonics is not listed in outputs",
                         ("settings", "harmonics"))
        if not wanted:
            return
        if self.method != METHOD:
            yield _error("harmonics_method", f"the harmonics are integrated exactly over the event engine's orbit: "
                         f"method {METHOD!r}, not {self.method!r}", ("method",))
        if self.sweep is not None:
            yield _error("harmonics_sweep", "a swept run does not store harmonics: run the grid without sweep",
                         ("sweep",))
        H = self.settings.get("harmonics", CATALOGUED[METHOD].defaults["harmonics"])
        values = self.grid.values("friction_scale").size * self.grid.written_frequency.size * (H + 1) * max(
            len(self.structure.dofs), len(self.structure.contacts))
        if isinstance(H, int) and values > g.MAX_POINTS:
            yield _error("harmonics_size", f"{values} values (grid points x {H + 1} harmonics x masses or contacts) "
                         f"exceed {g.MAX_POINTS} per variable", ("settings", "harmonics") if "harmonics" in
                         self.settings else ("outputs",))

    @property
    def frequency(self) -> np.ndarray:
        """The engine's angular frequencies (a physical structure's: over omega_0, spec.structure_units)."""
        if self._frequency is not None:
            self._frequency.flags.writeable = False  # re-set after unpickling
            return self._frequency
        return self.grid.values("frequency")

    @property
    def friction_scale(self) -> np.ndarray:
        return self.grid.values("friction_scale")

    @property
    def two_starts(self) -> bool:
        """Whether each point is solved from a moving start too (structures.starts): static above kinetic
        friction at some contact, and `starts` (the event method's setting) allows a second start."""
        from friction_sweep.catalogue import METHODS

        if self.sweep is not None:  # the sweep is the start: no second one
            return False
        starts = self.settings.get("starts", METHODS[METHOD].defaults["starts"])
        return starts > 1 and any(c.static_friction_ratio > 1.0 for c in self.structure.contacts)

    @property
    def variables(self) -> tuple[str, ...]:
        """The cube's variables, in output order (slips_per_period only with a Jenkins contact); with two starts
        each again from the moving start (MOVING_SUFFIX), and with the regime `steady_states`."""
        from friction_sweep.catalogue import MOVING_SUFFIX

        jenkins = any(c.stiffness is not None for c in self.structure.contacts)
        names = tuple(name for group in self.outputs for name in OUTPUT_GROUPS[group]
                      if name != "slips_per_period" or jenkins)
        if not self.two_starts:
            return names
        return (*names, *(name + MOVING_SUFFIX for name in names),
                *(("steady_states",) if "regime" in self.outputs else ()))


#: the settings a structure run takes, per method: the steady-state search knobs (catalogue: their defaults and
#: ranges), which the engine reads; rk4 its steps per period, and not stop_tol (as for one mass: a switch's
#: rounding tolerance there, kept at event's default)
_STEADY_KNOBS = ("max_periods", "max_orbit_period", "work_budget", "shoot_after", "shoot_every", "starts")
STRUCTURE_SETTINGS = {"event": ("steady_tol", "stop_tol", *_STEADY_KNOBS, "harmonics"),
                      "rk4": ("steady_tol", "steps_per_period", *_STEADY_KNOBS)}
#: the settings of fsweep peak / optimize / backbone (friction_sweep.design.structure), which the engine does
#: not read: peak_dof, the mass whose resonance peak is taken
DESIGN_SETTINGS = ("peak_dof",)
