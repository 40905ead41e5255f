"""The calibration spec: which measurements, which scene and method, which parameters with which priors.

    data:
      file: rig.csv                            # relative to the spec file
      columns:
        frequency_ratio: frequency_ratio       # or drive_frequency: {column: omega, unit: rad/s}
        force_ratio: force_ratio               # or friction_force: {column: F, unit: N}
        phase: phase_deg                       # first-harmonic lag, degrees; and/or transmissibility: T
        phase_uncertainty: sd_deg              # optional, per row (degrees); transmissibility_uncertainty: of log T
        series: run                            # optional: what groups rows (default: the force column's values)
      holdout: [0.087]                         # optional: series predicted but not fitted (out of sample)
    scene: {excitation: base}
    system: {natural_frequency: 19.5721 rad/s, excitation_force: 2.5 N}   # as fsweep run's (physical units)
    method: event                              # theory (continuous motion only) or event
    settings: {}                               # the method's settings, as fsweep run takes them
    parameters:                                # each a prior: {normal: [mu, sd]}, {uniform: [lo, hi]}, ...
      friction_ratio: {uniform: [0.01, 1]}     # one per series; or friction_force (N), or friction_scale (one)
      natural_frequency: {normal: [19.5721 rad/s, 0.5 rad/s]}
      viscous_damping: {half_normal: 0.02}     # event only, as every effect
      static_friction_ratio: {uniform: [1, 2]}
      noise_phase: {half_normal: 5 deg}        # noise_transmissibility: the sd of log T
      discrepancy_phase: {normal: [0 deg, 3 deg]}   # a phase offset the model lacks (sensor lag, fixture)
    sampler: {walkers: 32, seed: 0, autocorr_times: 50, min_ess: 1000, max_steps: 20000}
    output: results/calibration                # a folder: posterior.nc, map.csv, report.md, figures

Validated like a sweep spec (ruamel.yaml + pydantic; every problem as `file:line:column: key: reason`).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Annotated, Any

from pydantic import BaseModel, Field, PrivateAttr, Strict, field_validator, model_validator
from pydantic import ValidationError as _ValidationError

from friction_sweep import packaged
from friction_sweep.catalogue import EFFECTS, EXCITATIONS, METHODS, able
from friction_sweep.spec.base import Model, Sourced, problem, raise_all, show
from friction_sweep.spec.errors import SpecError
from friction_sweep.spec.load import KeyPath, parse_yaml, read_text
from friction_sweep.spec.model import setting_problems
from friction_sweep.spec.parse import problems_of
from friction_sweep.spec.quantities import ANGLE, FORCE, FREQUENCY, RATIO, Kind, QuantityError, to_si
from friction_sweep.spec.system import System

from .priors import KINDS, Prior

#: methods a calibration can use: the closed form where it is valid, the exact simulation everywhere
CALIBRATION_METHODS = ("theory", "event")

#: the parameters a calibration can infer, and what each is measured in (None: decided by the spec)
PARAMETERS: dict[str, Kind | None] = {
    "friction_ratio": RATIO,  # per series: beta = F_mu / F_k
    "friction_force": FORCE,  # per series, with system.excitation_force
    "friction_scale": RATIO,  # one factor on every series' beta from the data
    "natural_frequency": None,  # a frequency with system.natural_frequency; else relative to the data's
    "viscous_damping": RATIO,
    "static_friction_ratio": RATIO,
    "noise_phase": ANGLE,
    "noise_transmissibility": RATIO,  # sd of log T
    "discrepancy_phase": ANGLE,
}
FRICTION_PARAMETERS = ("friction_ratio", "friction_force", "friction_scale")
#: the measured quantities a spec's data may hold, with the noise parameter each needs
MEASURED = {"phase": "noise_phase", "transmissibility": "noise_transmissibility"}


class ColumnUnit(Model):
    """A data column in a physical unit."""

    column: str
    unit: str


class Columns(Model):
    frequency_ratio: str | None = None
    drive_frequency: ColumnUnit | None = None
    force_ratio: str | None = None
    friction_force: ColumnUnit | None = None
    phase: str | None = None
    transmissibility: str | None = None
    phase_uncertainty: str | None = None
    transmissibility_uncertainty: str | None = None
    series: str | None = None

    @model_validator(mode="after")
    def _one_of_each(self):
        problems = []
        for a, b in (("frequency_ratio", "drive_frequency"), ("force_ratio", "friction_force")):
            if (getattr(self, a) is None) == (getattr(self, b) is None):
                both = getattr(self, a) is not None
                problems.append(problem("column_pair", f"give one of {a} or {b} (got {'both' if both else 'neither'})",
                                        (b if both else a,)))
        if self.phase is None and self.transmissibility is None:
            problems.append(problem("nothing_measured", "give the measured phase and/or transmissibility column"))
        for measured in MEASURED:
            if getattr(self, f"{measured}_uncertainty") is not None and getattr(self, measured) is None:
                problems.append(problem("uncertainty_alone", f"{measured}_uncertainty needs the {measured} column",
                                        (f"{measured}_uncertainty",)))
        raise_all("columns", problems)
        return self

    def unit_problems(self) -> list:
        """Units that are not of the column's kind."""
        out = []
        for name, kind in (("drive_frequency", FREQUENCY), ("friction_force", FORCE)):
            given = getattr(self, name)
            if given is not None:
                try:
                    to_si(f"1 {given.unit}", kind)
                except QuantityError as err:
                    out.append(problem("unit", str(err), (name, "unit")))
        return out


class Data(Model):
    file: str  # relative to the spec's folder, or package:PATH (a file shipped with the package)
    columns: Columns
    holdout: Annotated[list[float | str], Field(min_length=1)] | None = None

    @field_validator("file")
    @classmethod
    def _packaged(cls, file: str) -> str:
        reason = packaged.problem(file)
        if reason is not None:
            raise problem("packaged_file", reason)
        return file


#: the largest seed: emcee draws from numpy's RandomState, which takes seeds 0 .. 2**32 - 1
MAX_SEED = 2**32 - 1


class Sampler(Model):
    """The ensemble sampler's settings and the targets its run must meet (the diagnostics)."""

    walkers: Annotated[int, Strict(), Field(ge=8, le=1024)] = 32
    seed: Annotated[int, Strict(), Field(ge=0, le=MAX_SEED)] = 0
    #: the run's length at least this many integrated autocorrelation times of every parameter
    autocorr_times: Annotated[float, Strict(), Field(ge=5, le=10_000)] = 50.0
    #: effective sample size of every parameter at least this
    min_ess: Annotated[int, Strict(), Field(ge=10, le=10**7)] = 1000
    max_steps: Annotated[int, Strict(), Field(ge=100, le=10**7)] = 20_000
    #: steps between convergence checks
    check_every: Annotated[int, Strict(), Field(ge=10, le=10**6)] = 200
    #: posterior draws the posterior predictive is computed from
    predictive_draws: Annotated[int, Strict(), Field(ge=10, le=10_000)] = 400


class CalibrationSpec(Sourced):
    data: Data
    scene: dict[str, Any]
    system: System | None = None
    method: str = "event"
    settings: dict[str, Any] = Field(default_factory=dict)
    parameters: dict[str, Any]
    sampler: Sampler = Field(default_factory=Sampler)
    output: str | None = None
    _priors: dict[str, Prior] = PrivateAttr(default_factory=dict)
    _doc: Any = PrivateAttr(default=None)

    @field_validator("scene")
    @classmethod
    def _scene(cls, scene: dict[str, Any]) -> dict[str, Any]:
        unknown = [k for k in scene if k != "excitation"]
        problems = [problem("unknown_key", f"unknown key {show(k)} (allowed: excitation; effects are calibrated "
                            "as parameters)", (k,)) for k in unknown]
        if scene.get("excitation") not in EXCITATIONS:
            problems.append(problem("unknown_excitation", f"unknown excitation {show(scene.get('excitation'))} "
                                    f"(expected one of: {', '.join(EXCITATIONS)})", ("excitation",)))
        raise_all("scene", problems)
        return scene

    @field_validator("method")
    @classmethod
    def _method(cls, method: str) -> str:
        if method not in CALIBRATION_METHODS:
            raise problem("calibration_method", f"must be one of {', '.join(CALIBRATION_METHODS)} "
                          f"(got {show(method)}): the closed form where the motion is continuous, the exact "
                          "simulation everywhere")
        return method

    @model_validator(mode="after")
    def _consistent(self):
        problems = [problem(p.type, p.message(), ("data", "columns", *p.context["at"]))
                    for p in self.data.columns.unit_problems()]
        problems += setting_problems(self.method, self.settings) + self._parameter_problems()
        if "starts" in self.settings:
            problems.append(problem("calibration_starts", "a calibration computes each point from rest (the state a "
                                    "rig shows after starting from rest): settings.starts does not apply",
                                    ("settings", "starts")))
        raise_all("CalibrationSpec", problems)
        return self

    def locate(self, *path: str | int) -> str:
        """`file:line:column: key` of a key of the spec, for a problem found after validation."""
        line, column = self._doc.locate(path) if self._doc is not None else (None, None)
        where = self._source_path + (f":{line}:{column}" if line is not None else "")
        return f"{where}: {'.'.join(str(p) for p in path)}"

    @property
    def excitation(self) -> str:
        return str(self.scene["excitation"])

    @property
    def priors(self) -> dict[str, Prior]:
        """The parameters' priors in SI (Hz, N) or dimensionless, degrees for angles, in spec order."""
        return self._priors

    @property
    def reference_frequency(self) -> float | None:
        """f_n the spec states (Hz): the data's frequency ratios are against it, a natural_frequency prior in Hz."""
        return None if self.system is None else self.system.natural_frequency_si

    @property
    def reference_force(self) -> float | None:
        return None if self.system is None else self.system.reference_force

    def _parameter_problems(self) -> list:
        out = []
        columns = self.data.columns
        friction = [name for name in FRICTION_PARAMETERS if name in self.parameters]
        if len(friction) > 1:
            out.append(problem("two_frictions", f"give the friction one way: {' or '.join(friction)}",
                               ("parameters", friction[-1])))
        for name, value in self.parameters.items():
            at = ("parameters", name)
            if name not in PARAMETERS:
                out.append(problem("unknown_parameter", f"unknown parameter {show(name)} (known: "
                                   f"{', '.join(PARAMETERS)})", at))
                continue
            if name in EFFECTS and name not in METHODS[self.method].effects:
                out.append(problem("effect_unsupported", f"method {self.method!r} does not model {name} "
                                   f"(methods that do: {', '.join(m for m in able(name) if m in CALIBRATION_METHODS)})",
                                   at))
                continue
            kind = PARAMETERS[name]
            if name == "natural_frequency":
                kind = FREQUENCY if self.reference_frequency is not None else RATIO
            if name == "friction_force" and self.reference_force is None:
                out.append(problem("needs_force", "a friction force needs the excitation's force to compare with: "
                                   "give system.excitation_force (or base_amplitude with the stiffness)", at))
                continue
            if name.startswith("noise_") and getattr(columns, name.removeprefix("noise_")) is None:
                out.append(problem("noise_unmeasured", f"the data has no {name.removeprefix('noise_')} column", at))
                continue
            if name == "discrepancy_phase" and columns.phase is None:
                out.append(problem("noise_unmeasured", "the data has no phase column", at))
                continue
            prior = _prior(value, kind, at, out)  # type: ignore[arg-type]
            if prior is not None:
                self._priors[name] = prior
        if columns.drive_frequency is not None and self.reference_frequency is None:
            out.append(problem("needs_natural_frequency", "drive frequencies need the natural frequency they are "
                               "measured against: give system.natural_frequency (or mass and stiffness)",
                               ("data", "columns", "drive_frequency")))
        if columns.friction_force is not None and self.reference_force is None:
            out.append(problem("needs_force", "friction forces need the excitation's force to compare with: give "
                               "system.excitation_force", ("data", "columns", "friction_force")))
        for measured, noise in MEASURED.items():
            if getattr(columns, measured) is not None and noise not in self.parameters \
                    and getattr(columns, f"{measured}_uncertainty") is None:
                out.append(problem("no_noise", f"the {measured} needs a noise level: a {noise} prior or a "
                                   f"{measured}_uncertainty column", ("parameters",)))
        return out


def _prior(value: Any, kind: Kind, at: KeyPath, problems: list) -> Prior | None:
    """A prior from its one-key mapping, its numbers read in the parameter's unit."""
    if not isinstance(value, dict) or len(value) != 1 or next(iter(value)) not in KINDS:
        problems.append(problem("prior", f"must be a prior: one of {', '.join(f'{{{k}: ...}}' for k in KINDS)} "
                                f"(got {show(value)})", at))
        return None
    name, numbers = next(iter(value.items()))
    numbers = numbers if isinstance(numbers, list) else [numbers]
    read = []
    for i, x in enumerate(numbers):
        try:
            read.append(to_si(x, kind))
        except QuantityError as err:
            problems.append(problem("quantity", str(err), (*at, name, i) if len(numbers) > 1 else (*at, name)))
    if len(read) != len(numbers):
        return None
    try:
        return Prior(name, tuple(read))
    except ValueError as err:
        problems.append(problem("prior", str(err), (*at, name)))
        return None


#: which model validates the mapping at each key path (to list the keys it allows)
_MODELS: dict[KeyPath, type[BaseModel]] = {
    (): CalibrationSpec, ("data",): Data, ("data", "columns"): Columns, ("sampler",): Sampler, ("system",): System,
    ("data", "columns", "drive_frequency"): ColumnUnit, ("data", "columns", "friction_force"): ColumnUnit,
}


def load_calibration_spec(path: str | os.PathLike[str]) -> CalibrationSpec:
    """Read and validate the calibration spec at `path` (SpecError listing every problem)."""
    return parse_calibration_text(read_text(path), source=os.fspath(path))


def parse_calibration_text(text: str, source: str = "<string>") -> CalibrationSpec:
    doc = parse_yaml(text, source)
    if not isinstance(doc.data, dict):
        raise SpecError.single(source, "the calibration spec must be a mapping of keys", line=1, column=1)
    if "structure" in doc.data:  # issue 30's structures are swept, not yet calibrated (issue 31)
        line, column = doc.locate(("structure",), key=True)
        raise SpecError.single(source, "a structure (several masses and contacts) is not calibrated yet: fsweep "
                               "calibrate fits the 1-DoF scenes; sweep it with fsweep run", key="structure",
                               line=line, column=column)
    try:
        spec = CalibrationSpec.model_validate(doc.data)
    except _ValidationError as e:
        raise SpecError(_every_problem(e, doc)) from None
    spec._source_path = source
    spec._text = text
    spec._doc = doc
    return spec


#: keys whose problem stops the checks across the spec (pydantic runs them only once every key validates),
#: each with the keys of the problems those checks would find that still hold without it: all of them where
#: none of the checks reads the key; where some do, the problems of the keys those read are left out (they
#: would be judged against a default, not the spec: a natural_frequency prior read as a ratio without system)
_HIDING: dict[KeyPath, tuple[str, ...]] = {
    ("sampler",): (), ("output",): (), ("data", "file"): (), ("data", "holdout"): (), ("scene",): (),
    ("system",): ("parameters.natural_frequency", "parameters.friction_force", "data.columns.drive_frequency",
                  "data.columns.friction_force"),
    ("method",): ("settings", "parameters.viscous_damping", "parameters.static_friction_ratio"),
}


def _every_problem(exc: _ValidationError, doc) -> list:
    """Every problem of the spec at once: where a key of _HIDING failed, the spec is validated again without
    it (its default applies) and what that finds is added, less what depends on that key."""
    problems = problems_of(exc, doc, _MODELS)
    failed = {tuple(err["loc"][:len(key)]) for err in exc.errors() for key in _HIDING}
    dropped = [key for key in _HIDING if key in failed]
    if not dropped:
        return problems
    unjudged = tuple(prefix for key in dropped for prefix in (".".join(map(str, key)), *_HIDING[key]))
    try:
        CalibrationSpec.model_validate(_without(doc.data, dropped))
    except _ValidationError as again:
        seen = {(p.key, p.reason) for p in problems}
        problems += [p for p in problems_of(again, doc, _MODELS) if (p.key, p.reason) not in seen
                     and not any(p.key == u or p.key.startswith((u + ".", u + "[")) for u in unjudged)]
    return sorted(problems, key=lambda p: (p.line is None, p.line or 0, p.column or 0))


#: what stands in for a required key that failed, in the second validation
_PLACEHOLDERS: dict[KeyPath, Any] = {("data", "file"): "-", ("scene",): {"excitation": "base"}}


def _without(data: dict, keys: list[KeyPath]) -> dict:
    """A copy of the spec's mapping without `keys` (their defaults apply; a required one becomes a
    placeholder, _PLACEHOLDERS)."""
    out = dict(data)
    for key in keys:
        holder = out
        for part in key[:-1]:
            if not isinstance(holder.get(part), dict):
                break
            holder[part] = holder = dict(holder[part])
        else:
            holder.pop(key[-1], None)
            if key in _PLACEHOLDERS:  # required: its own problem is reported already
                holder[key[-1]] = _PLACEHOLDERS[key]
    return out


def data_path(spec: CalibrationSpec) -> Path:
    """The data file: a packaged one (`package:PATH`, packaged.py), else relative to the spec's folder."""
    if packaged.named(spec.data.file):
        return packaged.resolve(spec.data.file)
    return (Path(spec.source_path).parent / spec.data.file) if spec.source_path != "<string>" else \
        Path(spec.data.file)

