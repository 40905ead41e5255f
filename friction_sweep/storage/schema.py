"""The result cube contract: every stored variable's dims, dtype and CF attributes, in one table.

Figure scripts and users rely on these names; methods only produce arrays keyed by them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from friction_sweep import codes
from friction_sweep.catalogue import EFFECTS, MAX_HARMONIC, MOVING_SUFFIX
from friction_sweep.codes import MethodUsed, Regime, SteadyState
from friction_sweep.theory.phase import PHASE_RANGE_DEG

GRID_DIMS = ("force_ratio", "frequency_ratio")
#: the dims of a cube at constant base acceleration (spec/system.py): the physical axes, since beta grows
#: with f^2 along the sweep; frequency_ratio is then a coordinate on `frequency`, force_ratio a 2-D one
ACCELERATION_DIMS = {"force_ratio": "friction_force", "frequency_ratio": "frequency"}
#: the dim of the time-history points (outputs: time_history): not `history`, which would shadow the CF
#: global attribute of that name (`ds.history` would be the dim's coordinate, not the provenance line);
#: not `orbit`, since an unbounded or unsettled point's history holds no orbit
HISTORY_DIM = "history_point"
#: the name a cube written before issue 33 gave that dim (storage.cube.open_cube maps it)
LEGACY_HISTORY_DIM = "history"
HISTORY_DIMS = (HISTORY_DIM, "sample")
#: the dim of the output `harmonics`: the harmonic number k = 0..H of the forcing frequency, first so that a
#: plane of one harmonic is a grid plane
HARMONIC_DIM = "harmonic"
HARMONIC_DIMS = (HARMONIC_DIM, *GRID_DIMS)
CONVENTIONS = "CF-1.10"
#: No variable has a CF standard_name or axis. The standard-name table holds none of these quantities but
#: `time`, which CF then wants in units "since an epoch" (a history's time is elapsed from a section), and
#: axis X/Y/Z mark space (the CF checker then asks for latitude/longitude units). tests/test_names.py runs
#: the checker on every kind of cube.


# Valid values (friction_sweep.storage.audit checks a cube against them, for `fsweep info` to refuse a cube
# that breaks them). They are schema metadata only, not written to the file: CF readers such as
# netCDF4-python mask values outside valid_min/valid_max by default, which would hide exactly the
# corruption the audit is there to report, and the cubes' attributes stay as they were.
#
# A float value is valid when it is NaN (no value: unbounded, unsettled, or not backed by the method)
# or finite and inside `valid_range` (inclusive). Infinities are never valid: no method writes one
# (unbounded points are NaN). An integer flag variable holds only its CF flag_values; `integral`
# float variables hold only whole numbers.

#: Largest amplitude a method can write (transmissibilities, peaks, time histories, in units of the
#: excitation): every finite one obeys (A + 4/pi max(beta, beta_s)) / |1 - r^2 + 2i zeta r| (+1 joined,
#: `fsweep check` rule `bound`), motion needs A > beta_s, and no method resolves |1 - r| below ~1e-12
#: (theory: the resonance tie; simulations: kernels.shoot.RESOLVABLE), so real values stay below
#: ~1e12. Far above that, a value is garbage (a flipped exponent bit), not physics.
AMPLITUDE_MAX = 1e15
#: Counts stored as float64 are exact whole numbers only up to 2^53.
COUNT_MAX = 2.0**53
#: Phases are wrapped into PHASE_RANGE_DEG = [-90, 270); the wrap's rounding can give 270 exactly
#: (a lag a hair below -90 degrees), so the closed interval is valid.
PHASE_VALID = (PHASE_RANGE_DEG[0], PHASE_RANGE_DEG[1])
AMPLITUDE_VALID = (0.0, AMPLITUDE_MAX)
DISPLACEMENT_VALID = (-AMPLITUDE_MAX, AMPLITUDE_MAX)
COUNT_VALID = (0.0, COUNT_MAX)
FRACTION_VALID = (0.0, 1.0)
NONNEGATIVE = (0.0, math.inf)
#: frequency ratios are > 0: the smallest positive double is the inclusive minimum
POSITIVE = (math.nextafter(0.0, 1.0), math.inf)


def cube_dims(name: str, dims: tuple[str, ...], physical_dims: bool) -> tuple[str, ...]:
    """The dims the variable `name` (schema dims `dims`) has in a cube: as the schema says, or in a cube
    with physical dims renamed, the force ratio then spanning both grid dims."""
    if not physical_dims:
        return dims
    if name == "force_ratio":
        dims = GRID_DIMS
    return tuple(ACCELERATION_DIMS.get(d, d) for d in dims)


@dataclass(frozen=True)
class Variable:
    dims: tuple[str, ...]
    dtype: type
    long_name: str
    units: str
    extra: dict = field(default_factory=dict)
    #: inclusive (min, max) of valid finite values (see above); None: no range (flag variables)
    valid_range: tuple[float, float] | None = None
    #: the valid values are whole numbers
    integral: bool = False
    #: what the short `long_name` leaves out (cases, definitions, conventions): CF `comment`. A long_name is
    #: one line of at most ~60 characters, since xarray labels a plot's axis "long_name [units]"
    comment: str = ""

    def attrs(self, excitation: str) -> dict:
        force, energy = _force_energy_references(excitation)
        refs = {"ref": _reference(excitation), "force_ref": force, "energy_ref": energy}
        attrs = {"long_name": self.long_name.format(**refs)}
        if self.units:  # a coordinate of names has none
            attrs["units"] = self.units
        attrs.update(self.extra)
        comment = "; ".join(c for c in (self.comment.format(**refs), self.extra.get("comment", "")) if c)
        if comment:
            attrs["comment"] = comment
        return attrs

    @property
    def flag_values(self):
        """The valid codes of an integer flag variable (its CF flag_values), or None."""
        return self.extra.get("flag_values")


def _reference(excitation: str) -> str:
    return "F0/k" if excitation == "force" else "Y"


def _force_energy_references(excitation: str) -> tuple[str, str]:
    """The units forces and energies are given in: (F0, F0^2/k) for force, (k Y, k Y^2) otherwise."""
    return ("F0", "F0^2/k") if excitation == "force" else ("k Y", "k Y^2")


_PHASE_NOTE = {
    "comment": "lag of the response behind the excitation, positive when the response follows; "
    f"wrapped into [{PHASE_RANGE_DEG[0]:g}, {PHASE_RANGE_DEG[1]:g}) degrees"
}

COORDS = {
    "frequency_ratio": Variable(("frequency_ratio",), np.float64, "frequency ratio r = omega / omega_n", "1",
                                 valid_range=POSITIVE),
    "force_ratio": Variable(
        ("force_ratio",),
        np.float64,
        "force ratio beta = F_mu / ({force_ref})",
        "1",
        valid_range=NONNEGATIVE,
        comment="friction force over the amplitude of the spring force (k Y) or of the external force (F0)",
    ),
}

#: physical coordinates beside (r, beta), where the spec has a `system:` (spec/system.py); not dimensions
PHYSICAL_COORDS = {
    "frequency": Variable(("frequency_ratio",), np.float64, "forcing frequency f = r f_n", "Hz",
                          valid_range=POSITIVE),
    "friction_force": Variable(("force_ratio",), np.float64, "friction force F_mu = beta F_k", "N",
                               valid_range=NONNEGATIVE),
}

#: coordinates on the time-history points' dim: where each history lies (a method writes them beside the
#: history_* variables)
HISTORY_COORDS = {
    "history_frequency_ratio": Variable((HISTORY_DIM,), np.float64, "frequency ratio r of the time-history point",
                                        "1", valid_range=POSITIVE),
    "history_force_ratio": Variable((HISTORY_DIM,), np.float64, "force ratio beta of the time-history point", "1",
                                    valid_range=NONNEGATIVE),
}

#: the coordinate of the harmonics' dim (outputs: harmonics; the run writes it beside them)
HARMONIC_COORDS = {
    HARMONIC_DIM: Variable((HARMONIC_DIM,), np.int64, "harmonic number k (frequency k r of the forcing's r)", "1",
                           valid_range=(0.0, float(MAX_HARMONIC)), integral=True),
}
#: coordinates a run writes among its arrays (not the grid's): each lies on a dim of its own
ARRAY_COORDS = {**HISTORY_COORDS, **HARMONIC_COORDS}

_HARMONIC_NOTE = ("one-sided complex Fourier coefficient of the steady orbit, exact (integrated in closed form over "
                  "the event kernel's pieces): {what}(t) = Re sum_k c_k exp(i k omega t), c_k = real + i imag, t from "
                  "a maximum of the excitation, so that |c_1| is the first-harmonic {first} and its lag "
                  "-arg(c_1) the phase; Parseval: mean square = c_0^2 + (sum over k >= 1 of |c_k|^2) / 2 (period-1 "
                  "orbits; an orbit of n > 1 periods has subharmonics besides)")


def _harmonic(what: str, symbol: str, part: str, first: str) -> Variable:
    return Variable(HARMONIC_DIMS, np.float64, f"{part} part of the harmonics of {what}", "1",
                    valid_range=DISPLACEMENT_VALID,
                    comment=_HARMONIC_NOTE.replace("{what}", symbol).replace("{first}", first))


def _effect(name: str, long_name: str) -> Variable:
    """An effect's scalar coordinate: its value, in the range the catalogue gives it."""
    effect = EFFECTS[name]
    return Variable((), np.float64, long_name, "1", valid_range=(effect.low, effect.high))


#: scalar coordinates (no dims): each effect the scene declares and each constant of the physical system the
#: spec knows, one value per cube, so that a family of cubes swept over one of them concatenates along it
#: (README, "Analysing a cube")
SCALAR_COORDS = {
    "viscous_damping": _effect("viscous_damping", "viscous damping ratio zeta of the dashpot"),
    "static_friction_ratio": _effect("static_friction_ratio", "static over kinetic friction force mu_s / mu_k"),
    "contact_stiffness": _effect("contact_stiffness", "contact stiffness ratio kappa = k_t / k"),
    "natural_frequency": Variable((), np.float64, "natural frequency f_n = sqrt(k / m) / (2 pi)", "Hz",
                                  valid_range=POSITIVE),
    "mass": Variable((), np.float64, "mass m", "kg", valid_range=POSITIVE),
    "stiffness": Variable((), np.float64, "spring stiffness k", "N m-1", valid_range=POSITIVE),
    "length_scale": Variable((), np.float64, "length unit {ref} of the dimensionless displacements", "m",
                             valid_range=POSITIVE),
    "excitation_force": Variable((), np.float64, "force unit {force_ref} of the force ratio beta = F_mu / {force_ref}",
                                 "N", valid_range=POSITIVE),
    "base_acceleration": Variable((), np.float64, "amplitude a of the base's acceleration, held along the sweep",
                                  "m s-2", valid_range=POSITIVE),
}

VARIABLES = {
    "transmissibility": Variable(
        GRID_DIMS,
        np.float64,
        "first-harmonic transmissibility |X| / {ref}",
        "1",
        valid_range=AMPLITUDE_VALID,
        comment="displacement transmissibility |X(r)|/|Y(r)|: the response's amplitude at the forcing frequency "
        "over {ref}",
    ),
    "peak_transmissibility": Variable(
        GRID_DIMS, np.float64, "peak transmissibility max|x| / {ref}", "1", valid_range=AMPLITUDE_VALID
    ),
    "phase": Variable(
        GRID_DIMS,
        np.float64,
        "first-harmonic phase lag of the response",
        "degree",
        _PHASE_NOTE,
        valid_range=PHASE_VALID,
    ),
    "peak_phase": Variable(
        GRID_DIMS,
        np.float64,
        "phase lag between the maxima",
        "degree",
        _PHASE_NOTE,
        valid_range=PHASE_VALID,
    ),
    "regime": Variable(
        GRID_DIMS,
        np.int8,
        "motion regime of the steady state",
        "1",
        codes.flags(Regime),
    ),
    "stops_per_period": Variable(
        GRID_DIMS,
        np.float64,
        "stops per forcing period",
        "1",
        valid_range=COUNT_VALID,  # not whole: a period-k orbit averages its stops over k periods
        comment="number of stops (slip to stick transitions) per forcing period; NaN where unknown",
    ),
    "slips_per_period": Variable(
        GRID_DIMS,
        np.float64,
        "slider slips per forcing period",
        "1",
        valid_range=COUNT_VALID,
        comment="slips of the contact's slider per forcing period (effect contact_stiffness: a reversal is a "
        "slip, a short stick and a slip the other way); NaN without friction",
    ),
    "floquet_multiplier": Variable(
        GRID_DIMS,
        np.float64,
        "largest Floquet multiplier of the steady orbit",
        "1",
        valid_range=NONNEGATIVE,
        comment="output stability: largest modulus among the multipliers of the steady orbit's period map over its "
        "orbit_period periods (below 1: attracting); NaN where undefined: at rest (regime stuck, or a Jenkins "
        "slider that never slips: a continuum of rest states), on the r = 1/(2n) family (steady_state family), "
        "without a periodic steady state (regime unbounded or unsettled, steady_state aperiodic), and where the "
        "period map is not smooth at the orbit (a grazing stop or band exit, a period that starts held by static "
        "friction alone: regime stick_slip or continuous with steady_state converged), and where method auto "
        "took the theory (steady_state not_simulated)",
    ),
    "continuous_limit": Variable(
        ("frequency_ratio",),
        np.float64,
        "continuous-motion limit beta*(r)",
        "1",
        valid_range=NONNEGATIVE,
        comment="largest force ratio with continuous (non-stop) motion, Den Hartog's beta*(r) in the scene's "
        "force-ratio convention",
    ),
    "stuck_fraction": Variable(GRID_DIMS, np.float64, "fraction of the period spent stuck", "1",
                               comment="fraction of the steady-state period spent stuck",
                               valid_range=FRACTION_VALID),
    "periods": Variable(GRID_DIMS, np.float64, "forcing periods integrated for the point", "1",
                        valid_range=COUNT_VALID,  # not whole: method paper records where a failed solve stopped
                        comment="all told: marched, shooting's evaluations, measured"),
    "steady_state": Variable(
        GRID_DIMS,
        np.int8,
        "why the steady-state search stopped",
        "1",
        codes.flags(SteadyState),
    ),
    "orbit_period": Variable(
        GRID_DIMS, np.float64, "period of the steady orbit in forcing periods", "1",
        valid_range=(1.0, COUNT_MAX), integral=True, comment="1: harmonic, k: subharmonic",
    ),
    # design quantities (docs/equations.md §6, "Energy balance" and "Transmitted force")
    "friction_energy": Variable(
        GRID_DIMS, np.float64, "friction energy per forcing period / ({energy_ref})", "1", valid_range=NONNEGATIVE,
        comment="energy dissipated by friction per forcing period (friction force x sliding distance) / "
        "({energy_ref}); 0 when stuck, NaN without a steady state",
    ),
    "transmitted_force": Variable(
        GRID_DIMS, np.float64, "force transmitted to the supports / ({force_ref})", "1", valid_range=NONNEGATIVE,
        comment="first-harmonic amplitude of the force that spring, friction and dashpot together exert on the "
        "supports / ({force_ref})",
    ),
    "method_used": Variable(
        GRID_DIMS,
        np.int8,
        "method that produced the point (method auto)",
        "1",
        codes.flags(MethodUsed),
    ),
    # time histories of selected points (outputs: time_history), on their own dims
    "history_orbit_period": Variable((HISTORY_DIM,), np.float64, "period of the stored orbit in forcing periods", "1",
                                     valid_range=COUNT_VALID, integral=True),  # 0: no steady state
    "history_regime": Variable(
        (HISTORY_DIM,),
        np.int8,
        "motion regime of the time-history point",
        "1",
        codes.flags(Regime),
    ),
    "history_time": Variable(HISTORY_DIMS, np.float64, "time in forcing periods from a steady-state section", "1",
                             valid_range=NONNEGATIVE),
    "history_displacement": Variable(HISTORY_DIMS, np.float64, "response displacement x / {ref}", "1",
                                     valid_range=DISPLACEMENT_VALID),
    "history_excitation": Variable(HISTORY_DIMS, np.float64,
                                   "excitation (force or base displacement) / its amplitude", "1",
                                   valid_range=(-1.0, 1.0)),
    "history_relative_displacement": Variable(
        HISTORY_DIMS, np.float64, "displacement in the equation of motion / {ref}", "1",
        valid_range=DISPLACEMENT_VALID, comment="x; z = x - y for joined",
    ),
    "history_relative_velocity": Variable(
        HISTORY_DIMS, np.float64, "velocity in the equation of motion / ({ref} omega_n)", "1",
        valid_range=DISPLACEMENT_VALID, comment="dx/dt; dz/dt for joined; in {ref} per 1/omega_n",
    ),
    "history_friction_force": Variable(
        HISTORY_DIMS, np.float64, "friction force on the mass / ({force_ref})", "1",
        valid_range=DISPLACEMENT_VALID,
        comment="the contact's force in the equation of motion (sgn v times the kinetic friction while slipping, the "
        "force that holds the mass while stuck; the Jenkins contact's spring force); against "
        "history_relative_displacement: the hysteresis loop",
    ),
    # exact harmonics (outputs: harmonics), in the units of their time histories
    "response_harmonic_real": _harmonic("the response x / {ref}", "x", "real", "transmissibility"),
    "response_harmonic_imag": _harmonic("the response x / {ref}", "x", "imaginary", "transmissibility"),
    "friction_harmonic_real": _harmonic("friction / ({force_ref})", "f", "real", "friction force"),
    "friction_harmonic_imag": _harmonic("friction / ({force_ref})", "f", "imaginary", "friction force"),
    # joined base-wall excitation only: the relative motion z = x - y (paper Sect. 4)
    "relative_peak_amplitude": Variable(
        GRID_DIMS, np.float64, "peak relative mass-wall displacement |Z|/|Y| (paper Eq. 34)", "1",
        valid_range=AMPLITUDE_VALID,
    ),
    "relative_peak_phase": Variable(
        GRID_DIMS,
        np.float64,
        "phase lag phi_yz of z behind y, between maxima",
        "degree",
        _PHASE_NOTE,
        valid_range=PHASE_VALID,
    ),
    "peak_phase_xz": Variable(
        GRID_DIMS,
        np.float64,
        "phase lag phi_xz of z behind x, between maxima",
        "degree",
        _PHASE_NOTE,
        valid_range=PHASE_VALID,
    ),
}

#: physical variables: each a dimensionless one times the length scale L (Y, or F0/k for force) or, for time,
#: forcing periods over the frequency (storage/physical.py says which)
VARIABLES.update({
    "displacement_amplitude": Variable(GRID_DIMS, np.float64, "first-harmonic displacement amplitude |X|", "m",
                                       valid_range=(0.0, math.inf), comment="transmissibility times {ref}"),
    "peak_displacement": Variable(GRID_DIMS, np.float64, "peak displacement max|x|", "m",
                                  valid_range=(0.0, math.inf), comment="peak_transmissibility times {ref}"),
    "dissipated_energy": Variable(GRID_DIMS, np.float64, "energy dissipated by friction per period", "J",
                                  valid_range=NONNEGATIVE, comment="friction_energy times {energy_ref}"),
    "force_amplitude": Variable(GRID_DIMS, np.float64, "force transmitted to the supports", "N",
                                valid_range=NONNEGATIVE,
                                comment="first-harmonic amplitude; transmitted_force times {force_ref}"),
    "history_physical_time": Variable(HISTORY_DIMS, np.float64, "time from a steady-state section", "s",
                                      valid_range=NONNEGATIVE),
    "history_physical_displacement": Variable(HISTORY_DIMS, np.float64, "response displacement x", "m",
                                              valid_range=(-math.inf, math.inf)),
})

#: per-point variables that describe one steady state (and so have a "_moving" twin)
STATE_VARIABLES = ("transmissibility", "peak_transmissibility", "phase", "peak_phase", "regime", "stops_per_period",
                   "stuck_fraction", "periods", "steady_state", "orbit_period", "friction_energy",
                   "transmitted_force", "displacement_amplitude", "peak_displacement", "dissipated_energy",
                   "force_amplitude", "floquet_multiplier", "slips_per_period")
for _name in STATE_VARIABLES:
    _v = VARIABLES[_name]
    VARIABLES[_name + MOVING_SUFFIX] = replace(
        _v, long_name=_v.long_name + ", moving start",
        comment="; ".join(c for c in ("of the state reached from a moving start (the orbit kinetic friction alone "
                                      "sustains)", _v.comment) if c))
VARIABLES["steady_states"] = Variable(
    GRID_DIMS,
    np.int8,
    "number of distinct steady states (a lower bound)",
    "1",
    {"comment": "reached from the starts (rest, moving); two states are one when both are stuck, both unbounded, "
     "both aperiodic, or both move with the same regime and stops per period and first-harmonic "
     "transmissibilities within 1e-5 relative; an unsettled result counts as no state"},
    valid_range=(0.0, 2.0),  # two starts at most
)

# ---- structure cubes (several masses and contacts: a spec with `structure:`, DESIGN §7) -------------------
# The 1-DoF names above keep their meaning; a structure cube has its own dims and table, chosen by its
# `structure` attribute (is_structure): the plane (friction_scale, frequency), with a mass's variables
# along `dof` and a contact's along `contact`.

#: the global attribute holding the solved structure (JSON: masses, springs, dampers, contacts, forcing,
#: base_amplitude), which marks a cube as a structure cube
STRUCTURE_ATTRIBUTE = "structure"
STRUCTURE_DIMS = ("friction_scale", "frequency")
DOF_DIMS = (*STRUCTURE_DIMS, "dof")
CONTACT_DIMS = (*STRUCTURE_DIMS, "contact")
_STRUCTURE_UNITS = {"comment": "in the structure's own units: force excitation, its length unit; base excitation, "
                    "over base_amplitude (a transmissibility); a physical structure's length unit is length_scale "
                    "metres"}

STRUCTURE_COORDS = {
    "friction_scale": Variable(("friction_scale",), np.float64, "factor on every contact's friction force", "1",
                               valid_range=NONNEGATIVE),
    "frequency": Variable(("frequency",), np.float64, "angular frequency omega of the excitation", "1",
                          {"comment": "radians per the structure's time unit"}, valid_range=POSITIVE),
    "dof": Variable(("dof",), str, "mass (degree of freedom) of the structure", ""),
    "contact": Variable(("contact",), str, "friction contact of the structure", ""),
}

#: a structure cube's coordinates where they apply (a cube need not have them): the frequency ratios, and a
#: physical structure's physical coordinates and scales (spec.structure_units: frequency is then
#: omega / omega_0, an amplitude times length_scale metres, a friction energy times force_scale x
#: length_scale joules)
STRUCTURE_EXTRA_COORDS = {
    **HARMONIC_COORDS,  # the output harmonics' numbers
    # where each time history lies (outputs: time_history)
    "history_frequency": Variable((HISTORY_DIM,), np.float64, "angular frequency of the time-history point", "1",
                                  valid_range=POSITIVE, comment="as the frequency coordinate (a physical "
                                  "structure's: over reference_frequency)"),
    "history_friction_scale": Variable((HISTORY_DIM,), np.float64, "friction_scale of the time-history point", "1",
                                       valid_range=NONNEGATIVE),
    "history_frequency_hz": Variable((HISTORY_DIM,), np.float64, "forcing frequency of the time-history point",
                                     "Hz", valid_range=POSITIVE),
    # the first natural frequencies of the linear structure, every contact stuck or every contact free
    # (structures.model.natural_frequencies; free: left out where a mass is held only by a contact)
    "frequency_ratio_stuck": Variable(("frequency",), np.float64, "frequency over the first natural frequency, "
                                      "contacts stuck", "1", valid_range=POSITIVE),
    "frequency_ratio_free": Variable(("frequency",), np.float64, "frequency over the first natural frequency, "
                                     "contacts free", "1", valid_range=POSITIVE),
    "frequency_hz": Variable(("frequency",), np.float64, "forcing frequency f = omega omega_0 / (2 pi)", "Hz",
                             valid_range=POSITIVE),
    "friction_force": Variable(("friction_scale", "contact"), np.float64, "kinetic friction force of the contact",
                               "N", valid_range=NONNEGATIVE),
    "reference_frequency": Variable((), np.float64, "angular frequency unit omega_0", "rad s-1",
                                    valid_range=POSITIVE, comment="the first natural frequency, contacts as "
                                    "grid.reference says"),
    "mass_scale": Variable((), np.float64, "mass unit m_0 (the first DoF's mass)", "kg", valid_range=POSITIVE),
    "stiffness_scale": Variable((), np.float64, "stiffness unit k_0 = m_0 omega_0^2", "N m-1", valid_range=POSITIVE),
    "force_scale": Variable((), np.float64, "force unit F_0 (largest forcing, or k_0 Y)", "N", valid_range=POSITIVE),
    "length_scale": Variable((), np.float64, "length unit L = F_0 / k_0 (or Y) of the amplitudes", "m",
                             valid_range=POSITIVE),
}

STRUCTURE_VARIABLES = {
    "amplitude": Variable(DOF_DIMS, np.float64, "first-harmonic amplitude of the mass", "1",
                          _STRUCTURE_UNITS, valid_range=AMPLITUDE_VALID, comment="of its absolute displacement"),
    "peak_amplitude": Variable(DOF_DIMS, np.float64, "peak absolute displacement max|x| of the mass", "1",
                               _STRUCTURE_UNITS, valid_range=AMPLITUDE_VALID, comment="over the steady orbit"),
    "phase": Variable(DOF_DIMS, np.float64, "first-harmonic phase lag of the mass", "degree", _PHASE_NOTE,
                      valid_range=PHASE_VALID, comment="NaN where the mass stands still (amplitude 0)"),
    "regime": Variable(CONTACT_DIMS, np.int8, "motion regime of the contact", "1", codes.flags(Regime),
                       comment="in the steady state"),
    "stops_per_period": Variable(CONTACT_DIMS, np.float64, "stops per forcing period at the contact", "1",
                                 valid_range=COUNT_VALID, comment="a stop: slip to stick; NaN where unknown"),
    "slips_per_period": Variable(CONTACT_DIMS, np.float64, "slips of the Jenkins slider per forcing period", "1",
                                 valid_range=COUNT_VALID, comment="NaN for a rigid contact"),
    "stuck_fraction": Variable(CONTACT_DIMS, np.float64, "fraction of the period the contact is stuck", "1",
                               valid_range=FRACTION_VALID,
                               comment="rigid contact: time its relative velocity is held at zero; Jenkins contact: "
                               "time it holds the mass (a stick during which the relative velocity returned to "
                               "zero, as the 1-DoF Jenkins kernel), 1 where its slider never slips; a contact "
                               "without friction: 0"),
    "friction_energy": Variable(CONTACT_DIMS, np.float64, "friction energy per forcing period", "1",
                                valid_range=NONNEGATIVE,
                                comment="the energy the contact's friction dissipates (friction force x sliding "
                                "distance), in the structure's units; NaN without a steady state"),
    "steady_state": Variable(STRUCTURE_DIMS, np.int8, "why the steady-state search stopped", "1",
                             codes.flags(SteadyState)),
    "orbit_period": Variable(STRUCTURE_DIMS, np.float64, "steady orbit's period in forcing periods", "1",
                             valid_range=(1.0, COUNT_MAX), integral=True, comment="1 harmonic, k subharmonic"),
    "periods": Variable(STRUCTURE_DIMS, np.float64, "forcing periods integrated for the point", "1",
                        valid_range=COUNT_VALID, comment="all told"),
    "floquet_multiplier": Variable(STRUCTURE_DIMS, np.float64, "largest Floquet multiplier of the steady orbit", "1",
                                   valid_range=NONNEGATIVE, comment="output stability: largest modulus among the "
                                   "multipliers of the steady orbit's period map over its orbit_period periods "
                                   "(below 1: attracting); NaN where undefined (a contact stuck all period: a "
                                   "continuum of stuck positions; without a periodic steady state; where the "
                                   "period map is not smooth at the orbit)"),
}
#: exact harmonics (outputs: harmonics; structures.harmonics): each mass's displacement and each contact's force,
#: the harmonic last, so that the plane (friction_scale, frequency) leads as in every structure variable
STRUCTURE_VARIABLES.update({
    f"{row}_harmonic_{part}": replace(_harmonic(what, symbol, word, first), dims=(*dims, HARMONIC_DIM), extra=extra,
                                      long_name=f"{what} harmonics, {word} part")
    for row, what, symbol, first, dims, extra in (
        ("response", "mass displacement", "x", "amplitude", DOF_DIMS, _STRUCTURE_UNITS),
        ("friction", "contact force", "lambda", "force", CONTACT_DIMS,
         {"comment": "lambda, the force on the contact's relative coordinate (the masses feel -w_j lambda_j), as "
          "the time histories' contact_force"}))
    for part, word in (("real", "real"), ("imag", "imaginary"))})
#: static above kinetic friction at a contact: each variable from the moving start too (the 1-DoF rule above,
#: structures.starts), and the count of distinct states
for _name, _v in list(STRUCTURE_VARIABLES.items()):
    STRUCTURE_VARIABLES[_name + MOVING_SUFFIX] = replace(
        _v, long_name=_v.long_name + ", moving start",
        comment="; ".join(c for c in ("of the state reached from a moving start (the orbit kinetic friction alone "
                                      "sustains)", _v.comment) if c))
STRUCTURE_VARIABLES["steady_states"] = replace(
    VARIABLES["steady_states"], dims=STRUCTURE_DIMS,
    extra={"comment": "reached from the starts (rest, moving); two states are one when every contact is stuck in "
           "both, both are unbounded, or every contact has the same regime and stops per period and every mass's "
           "first-harmonic amplitude agrees within 1e-5 relative; an unsettled result counts as no state"})
#: time histories of chosen points (outputs: time_history; structures.time_histories), from rest, on dims of
#: their own (no _moving twin): each mass's displacement and each contact's force and relative displacement
STRUCTURE_VARIABLES.update({
    "history_orbit_period": replace(VARIABLES["history_orbit_period"], long_name="period of the stored orbit in "
                                    "forcing periods", comment="0 where the point has no steady state (its samples "
                                    "NaN)"),
    "history_time": Variable(HISTORY_DIMS, np.float64, "time in forcing periods from the section", "1",
                             valid_range=NONNEGATIVE, comment="from a maximum of the excitation (t = 0), over the "
                             "orbit's history_orbit_period periods; NaN past a shorter orbit's end"),
    "history_displacement": Variable((*HISTORY_DIMS, "dof"), np.float64, "absolute displacement of the mass", "1",
                                     _STRUCTURE_UNITS, valid_range=DISPLACEMENT_VALID),
    "history_contact_force": Variable((*HISTORY_DIMS, "contact"), np.float64, "force lambda of the contact", "1",
                                      valid_range=DISPLACEMENT_VALID,
                                      comment="on the contact's relative coordinate u (the masses feel -w lambda): "
                                      "sigma mu slipping, the constraint force stuck (rigid), k_t (u - p) (Jenkins); "
                                      "0 without friction; against history_relative_displacement, the hysteresis "
                                      "loop, whose area is friction_energy; in the structure's force unit"),
    "history_relative_displacement": Variable((*HISTORY_DIMS, "contact"), np.float64,
                                              "relative displacement u of the contact", "1", _STRUCTURE_UNITS,
                                              valid_range=DISPLACEMENT_VALID,
                                              comment="u = w . x minus the base's motion at an end on the base"),
})


def is_structure(attrs) -> bool:
    """Whether a cube with these global attributes is a structure cube (its table: STRUCTURE_VARIABLES)."""
    return STRUCTURE_ATTRIBUTE in attrs
