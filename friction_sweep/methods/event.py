"""The exact event-driven simulation as a sweep method (kernels in friction_sweep.kernels).

Per grid point: from rest, march the stroboscopic map with closed-form slip and stick segments
until it repeats (or shoot for the periodic orbit), then measure over whole periods. Where the steady
state is unique (static = kinetic friction), Newton shooting starts from Den Hartog's continuous orbit
instead, where that exists: one exact period confirms it where the motion is continuous, and it is a
close start where the motion sticks. Valid in every regime; the theory's continuous limit is written
alongside for reference.

With static above kinetic friction a point can hold two steady states (a mass stopped at a reversal
stays stuck if the force there is below the static friction), so each point is also solved from a
moving start: the state of the orbit that kinetic friction alone sustains there (the same point with
static = kinetic friction). Its variables are stored beside those from rest with the suffix
`_moving`, and `steady_states` counts the distinct states found (a lower bound: more starts could
find more). With static = kinetic friction the period map does not expand distances and one start
suffices; nothing is added then.

With the effect contact_stiffness (a Jenkins contact, docs/equations.md §7) a point runs the Jenkins
kernels (kernels/jenkins.py, or jenkins_rk4.py for method rk4, driven by jenkins_steady.py) instead and
writes `slips_per_period` with the regime; a point without it never touches them. The output group
`stability` adds each orbit's largest Floquet multiplier, `floquet_multiplier`, in every scene.
"""

from __future__ import annotations

import numpy as np

from friction_sweep import catalogue
from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels import steady
from friction_sweep.kernels.period_map import integrator
from friction_sweep.kernels.point import JenkinsPoint, Point
from friction_sweep.kernels.settings import (
    KERNEL_EVENT,
    SET_KERNEL,
    SET_STOP_TOL,
    SET_WORK_BUDGET,
    settings_record,
)
from friction_sweep.methods import theory
from friction_sweep.storage.schema import MOVING_SUFFIX
from friction_sweep.theory import den_hartog, phase, scenes
from friction_sweep.theory.transmitted import transmitted_force

CATALOGUE = catalogue.method("event")

VARIABLES = {
    "transmissibility": ("transmissibility", "peak_transmissibility"),
    "phase": ("phase", "peak_phase"),
    "regime": ("regime", "stops_per_period", "stuck_fraction", "periods", "steady_state", "orbit_period"),
    "friction_energy": ("friction_energy",),
    "transmitted_force": ("transmitted_force",),
    "stability": ("floquet_multiplier",),
}
_INTEGER = {"regime": np.int8, "steady_state": np.int8}
#: the output `harmonics`: one-sided Fourier coefficients k = 0..H of the response and of the friction force,
#: each (harmonic, force_ratio, frequency_ratio) (storage.schema)
HARMONIC_VARIABLES = ("response_harmonic_real", "response_harmonic_imag", "friction_harmonic_real",
                      "friction_harmonic_imag")
#: written with the regime where the contact is a Jenkins element (effect contact_stiffness)
JENKINS_VARIABLES = ("slips_per_period",)

#: one state found from two starts: first-harmonic transmissibilities within this relative difference
#: (each solve settles to steady_tol on the state; near-neutral orbits carry that error amplified)
SAME_STATE_RTOL = 1e-5


def variables_for(excitation: str, outputs) -> tuple[str, ...]:
    names: list[str] = []
    for group in outputs:
        names.extend(VARIABLES.get(group, ()))
    return tuple(names)


def point_parameters(excitation: str, r, beta, effects=None):
    """Kernel parameters per point: forcing amplitude A, response offset c, kinetic and static
    friction, damping ratio (docs/equations.md §1: joined is z'' + z + beta sgn z' = r^2 cos, x = z + cos;
    the spring-parallel dashpot of base raises A to sqrt(1 + (2 zeta r)^2), theory.scenes)."""
    effects = effects or {}
    r = np.asarray(r, dtype=float)
    beta = np.asarray(beta, dtype=float)
    damping = catalogue.effect_value(effects, "viscous_damping")
    A, c = scenes.kernel_forcing(excitation, r, damping, catalogue.effect_place(excitation, effects, "viscous_damping"))
    bk = beta.copy()
    bs = beta * catalogue.effect_value(effects, "static_friction_ratio")
    zeta = np.full_like(r, damping)
    return A, c, bk, bs, zeta


def forcing_lead(excitation: str, r, effects=None) -> np.ndarray:
    """Per point, how far (radians) the kernel's forcing leads the excitation (theory.scenes): nonzero only
    for the spring-parallel dashpot of base. The kernels run in the forcing's frame, whose section is the
    forcing's maximum; every phase they report is against the forcing."""
    return scenes.forcing_lead(excitation, r, catalogue.effect_value(effects, "viscous_damping"),
                               catalogue.effect_place(excitation, effects, "viscous_damping"))


def _against_excitation(raw, lead) -> None:
    """Phases of raw kernel rows (in place) against the excitation instead of the kernel's forcing, which
    leads it by `lead`: a lag behind the forcing is `lead` less behind the excitation. Rows without a lead
    are not touched (re-wrapping would round them)."""
    shifted = lead != 0.0
    if shifted.any():
        degrees = np.degrees(lead[shifted])
        for slot in (steady.OUT_PHASE, steady.OUT_PEAK_PHASE):
            raw[shifted, slot] = phase.wrap_degrees(raw[shifted, slot] - degrees)


def newton_guess(A, r, bk, bs, zeta, settings: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Newton's start per point: Den Hartog's continuous orbit at the excitation's maximum
    (theory.den_hartog.section_state), in the kernel's units (times A), where its model is the point's
    (no damping, static = kinetic friction) and the kernel has the exact Jacobian that settles it in one
    period where the motion is continuous (the event kernel); NaN elsewhere, and where the closed form
    has no solution. Where the motion sticks it is still a closer start than rest (measured on the
    paper planes: 4.98 periods a stick-slip point against 5.22 from rest, base; 4.95 against 5.19,
    joined). The kernel uses a guess only where the steady state is unique (kernels.steady._unique), so
    it changes how fast the answer comes, not the answer."""
    use = (zeta == 0.0) & (bs == bk) & (bk > 0.0) & (settings[SET_KERNEL] == KERNEL_EVENT)
    q = np.full(r.shape, np.nan)
    v = np.full(r.shape, np.nan)
    if use.any():
        with np.errstate(divide="ignore", invalid="ignore"):
            qd, vd = den_hartog.section_state(r[use], bk[use] / A[use])
        q[use], v[use] = A[use] * qd, A[use] * vd
    return q, v


def kernel_settings(settings: dict | None = None) -> np.ndarray:
    """The steady-state kernel's settings record: `settings` (kernel: KERNEL_RK4 for method rk4) over the
    catalogue's defaults, the event kernel's (which ignores rk4's steps_per_period); `starts` is this
    module's business, not the kernel's."""
    values = {**CATALOGUE.defaults, **catalogue.method("rk4").defaults, "kernel": KERNEL_EVENT, "stability": 0,
              **(settings or {})}
    values.pop("starts")
    values.pop("harmonics")  # the output's size, not a kernel knob
    return settings_record(values)


def for_outputs(settings: dict | None, outputs) -> dict:
    """The kernel settings a tile's outputs call for: the orbit's Floquet multiplier is measured only where
    the output group `stability` asks (for rk4 and for orbits of k > 1 periods it costs periods)."""
    return {**(settings or {}), "stability": int("stability" in outputs)}


def contact_stiffness(effects) -> float:
    """The Jenkins contact's stiffness kappa = k_t/k; 0 (off) for the rigid contact."""
    return catalogue.effect_value(effects, "contact_stiffness")


def solve_flat(excitation, r, beta, effects=None, start=None, **settings):
    """Raw kernel outputs (n, OUT_SIZE) for 1-D arrays of points, phases against the excitation; start:
    per-point (q0, v0) arrays instead of the settings' one start. The start and end states (end_q, end_v)
    are at the kernel's section, the forcing's maximum (forcing_lead). With a Jenkins contact the rows
    are jenkins_steady's (n, JOUT_SIZE), whose first OUT_SIZE slots are these, and a start is per-point
    (q0, v0, w0, mode0) arrays (a settled orbit's end_q, end_v, end_w, end_mode)."""
    r = np.ascontiguousarray(r, dtype=float)
    beta = np.ascontiguousarray(np.broadcast_to(beta, r.shape), dtype=float)
    A, c, bk, bs, zeta = point_parameters(excitation, r, beta, effects)
    sett = kernel_settings(settings)
    kappa = contact_stiffness(effects)
    if kappa > 0.0:
        from friction_sweep.kernels import jenkins_steady  # compiled only where the effect is declared

        out = np.empty((r.size, jenkins_steady.JOUT_SIZE))
        kappas = np.full(r.shape, kappa)
        if start is None:
            jenkins_steady.solve_points_jenkins(A, r, bk, bs, zeta, c, kappas, sett, out, integrator(sett))
        else:
            q0, v0, w0, m0 = (np.ascontiguousarray(x, dtype=float) for x in start)
            jenkins_steady.solve_points_jenkins_from(A, r, bk, bs, zeta, c, kappas, sett, q0, v0, w0, m0, out,
                                                     integrator(sett))
        _against_excitation(out, forcing_lead(excitation, r, effects))
        return out
    out = np.empty((r.size, steady.OUT_SIZE))
    gq, gv = newton_guess(A, r, bk, bs, zeta, sett)
    if start is None:
        steady.solve_points(A, r, bk, bs, zeta, c, sett, gq, gv, out, integrator(sett))
    else:
        q0, v0 = (np.ascontiguousarray(s, dtype=float) for s in start)
        steady.solve_points_from(A, r, bk, bs, zeta, c, sett, q0, v0, gq, gv, out, integrator(sett))
    _against_excitation(out, forcing_lead(excitation, r, effects))
    return out


def harmonics(excitation: str, r, beta, raw, H: int, effects=None, settings=None) -> dict[str, np.ndarray]:
    """The output `harmonics` of points (r, beta) (1-D) from their solve's raw rows: the orbit replayed from its
    state (end_q, end_v, end_mode) with every piece integrated against exp(-i k r t) in closed form
    (kernels/harmonics.py; the Jenkins contact's too), k = 0..H. Response x = q + c cos(r t) and friction force f
    (the Jenkins contact's spring force while its slider sticks), one-sided (x = Re sum X_k
    e^{i k r t}), against the excitation (t from its maximum). A point held stuck (regime stuck, which also
    covers a creep below the steady tolerance, as the first harmonic's measurement does) is q = end_q,
    f = A cos(r t) - end_q exactly; one with no steady state is NaN. Arrays (H + 1, n), by HARMONIC_VARIABLES."""
    from friction_sweep.kernels import harmonics as kernel  # compiled only where the output is asked for

    r = np.ascontiguousarray(r, dtype=float)
    beta = np.ascontiguousarray(np.broadcast_to(beta, r.shape), dtype=float)
    A, c, bk, bs, zeta = point_parameters(excitation, r, beta, effects)
    sett = kernel_settings(settings)
    orbit = np.nan_to_num(raw[:, steady.OUT_ORBIT_PERIOD]).astype(np.int64)
    end_q = np.ascontiguousarray(raw[:, steady.OUT_END_Q])
    end_v = np.ascontiguousarray(raw[:, steady.OUT_END_V])
    end_mode = np.nan_to_num(raw[:, steady.OUT_END_MODE]).astype(np.int64)
    harm = np.empty((r.size, 2, H + 1), dtype=complex)
    kappa = contact_stiffness(effects)
    rigid = np.ones(r.shape, dtype=bool)
    if kappa > 0.0:
        from friction_sweep.kernels import jenkins_steady

        end_w = np.ascontiguousarray(raw[:, jenkins_steady.JOUT_END_W])
        rigid = ~np.isfinite(end_w)  # a Jenkins point without friction is the rigid model's: no slider position
        kernel.harmonics_points_jenkins(A, r, bk, bs, zeta, c, kappa, end_q, end_v, end_w, end_mode, orbit,
                                        sett[SET_STOP_TOL], int(sett[SET_WORK_BUDGET]), harm)
    if rigid.any():
        part = np.empty((int(rigid.sum()), 2, H + 1), dtype=complex)
        kernel.harmonics_points(*(np.ascontiguousarray(a[rigid]) for a in (A, r, bk, bs, zeta, c, end_q, end_v,
                                                                          end_mode, orbit)),
                                sett[SET_STOP_TOL], int(sett[SET_WORK_BUDGET]), part)
        harm[rigid] = part
    # the rigid contact's stuck state (the Jenkins contact's `stuck` is its slider's: the mass still swings)
    stuck = (raw[:, steady.OUT_REGIME] == Regime.STUCK) & rigid
    harm[stuck] = 0.0
    harm[stuck, 0, 0] = end_q[stuck]
    harm[stuck, 1, 0] = -end_q[stuck]
    harm[stuck, 1, 1] = A[stuck]
    x = harm[:, 0, :]
    x[:, 1] += c  # the excitation's share of the response, c cos(r t)
    # from the kernel's section (the forcing's maximum) to the excitation's: t_kernel = t + lead / r
    turn = np.exp(1j * np.outer(forcing_lead(excitation, r, effects), np.arange(H + 1)))
    x = (x * turn).T
    f = (harm[:, 1, :] * turn).T
    return dict(zip(HARMONIC_VARIABLES, (x.real, x.imag, f.real, f.imag), strict=True))


def two_starts(effects) -> bool:
    """Whether a point can hold two steady states: static friction above kinetic."""
    return catalogue.effect_value(effects, "static_friction_ratio") > 1.0


def solve_moving(excitation, r, beta, effects=None, **settings):
    """Raw kernel outputs from a moving start: the state (at the excitation's maximum) of the orbit
    that kinetic friction alone sustains at each point, or where that motion grows without bound,
    the state where its march gave up (a start that the model with static friction then follows)."""
    kinetic = {k: v for k, v in (effects or {}).items() if k != "static_friction_ratio"}
    seed = solve_flat(excitation, r, beta, kinetic, **{**settings, "stability": 0})  # only its end state is kept
    start = [np.nan_to_num(seed[:, steady.OUT_END_Q], nan=0.0, posinf=0.0, neginf=0.0),
             np.nan_to_num(seed[:, steady.OUT_END_V], nan=0.0, posinf=0.0, neginf=0.0)]
    if contact_stiffness(effects) > 0.0:
        from friction_sweep.kernels import jenkins_steady

        # the slider where the seed left it, in its mode; where the seed has no state, at rest relaxed
        w0 = seed[:, jenkins_steady.JOUT_END_W]
        m0 = seed[:, steady.OUT_END_MODE]
        known = np.isfinite(w0) & np.isfinite(m0) & np.isfinite(seed[:, steady.OUT_END_Q])
        start += [np.where(known, w0, np.nan), np.where(known, m0, 0.0)]
    return solve_flat(excitation, r, beta, effects, start, **settings)


def count_states(first, second):
    """Distinct steady states among two raw results (README, "Two steady states"): distinct_states of their
    regimes, stops per period, transmissibilities and steady-state codes."""
    return distinct_states(*((first[:, slot], second[:, slot]) for slot in (
        steady.OUT_REGIME, steady.OUT_STOPS_PER_PERIOD, steady.OUT_TRANSMISSIBILITY, steady.OUT_STEADY_STATE)))


def distinct_states(regime, stops, amplitude, steady_state):
    """Distinct steady states at each point among two results, each argument a pair (first, second) of arrays
    over the points; regime and stops may carry a trailing axis (a structure's contacts), amplitude too (its
    masses), and a point agrees only where every entry does. Unsettled results are no state. One state: both
    stuck (wherever held), both unbounded, both aperiodic, or the same regime and stops per period with
    amplitudes within SAME_STATE_RTOL."""

    def every(x):
        return np.asarray(x).reshape(np.shape(x)[0], -1).all(axis=1)

    codes = [np.asarray(c) for c in regime]
    answered = [every(c != Regime.UNSETTLED) for c in codes]
    t1, t2 = amplitude
    same_kind = every(codes[0] == codes[1])
    moving_alike = (same_kind & every(stops[0] == stops[1])
                    & every(np.abs(t1 - t2) <= SAME_STATE_RTOL * np.maximum(np.abs(t1), np.abs(t2))))
    aperiodic = (steady_state[0] == SteadyState.APERIODIC) & (steady_state[1] == SteadyState.APERIODIC)
    same = same_kind & (every(codes[0] == Regime.STUCK) | every(codes[0] == Regime.UNBOUNDED) | aperiodic
                        | moving_alike)
    n = answered[0].astype(np.int8) + answered[1].astype(np.int8)
    return (n - (answered[0] & answered[1] & same)).astype(np.int8)


def compute_tile(excitation: str, r, beta, outputs, effects=None, settings=None) -> dict[str, np.ndarray]:
    settings = for_outputs(settings, outputs)
    starts = int(settings.pop("starts", CATALOGUE.defaults["starts"]))
    H = int(settings.pop("harmonics", CATALOGUE.defaults["harmonics"]))
    r = np.asarray(r, dtype=float)
    beta = np.asarray(beta, dtype=float)
    R, B = np.meshgrid(r, beta)
    jenkins = contact_stiffness(effects) > 0.0
    raw = solve_flat(excitation, R.ravel(), B.ravel(), effects, **settings)
    names = variables_for(excitation, outputs)
    if jenkins and "regime" in outputs:
        names += JENKINS_VARIABLES
    result = _per_point(raw, names, excitation, R)
    if "harmonics" in outputs:
        result.update({name: values.reshape(H + 1, *R.shape) for name, values in
                       harmonics(excitation, R.ravel(), B.ravel(), raw, H, effects, settings).items()})
    if starts > 1 and two_starts(effects):
        moving = solve_moving(excitation, R.ravel(), B.ravel(), effects, **settings)
        twins = _per_point(moving, names, excitation, R)
        result.update({name + MOVING_SUFFIX: values for name, values in twins.items()})
        if "regime" in outputs:
            result["steady_states"] = count_states(raw, moving).reshape(R.shape)
    result["continuous_limit"] = theory.continuous_limit(excitation, r)
    return result


def compute_sweep_tile(excitation: str, r, beta, outputs, effects=None, settings=None,
                       direction: str = "up") -> dict[str, np.ndarray]:
    """A tile of a swept run: for each force ratio, the frequency ratios in sweep order (ascending for
    `up`, descending for `down`), each point started from the orbit of the one before
    (kernels.steady.solve_sweep), at the kernel's section (the forcing's maximum, which for the
    spring-parallel dashpot is not the base's: forcing_lead). The sweep is the start, so there is no second
    one (`starts`, which kernel_settings leaves out)."""
    r = np.asarray(r, dtype=float)
    beta = np.asarray(beta, dtype=float)
    order = np.argsort(r, kind="stable")
    if direction == "down":
        order = order[::-1]
    sett = kernel_settings(for_outputs(settings, outputs))
    rs = np.ascontiguousarray(r[order])
    kappa = contact_stiffness(effects)
    names = variables_for(excitation, outputs)
    size = steady.OUT_SIZE
    if kappa > 0.0:
        from friction_sweep.kernels import jenkins_steady  # compiled only where the effect is declared

        size = jenkins_steady.JOUT_SIZE
        if "regime" in outputs:
            names += JENKINS_VARIABLES
    raw = np.empty((beta.size, r.size, size))
    for j, b in enumerate(beta):
        A, c, bk, bs, zeta = point_parameters(excitation, rs, np.full(rs.shape, b), effects)
        row = np.empty((r.size, size))
        if kappa > 0.0:
            jenkins_steady.solve_sweep_jenkins(A, rs, bk, bs, zeta, c, np.full(rs.shape, kappa), sett, row,
                                               integrator(sett))
        else:
            steady.solve_sweep(A, rs, bk, bs, zeta, c, sett, *newton_guess(A, rs, bk, bs, zeta, sett), row,
                              integrator(sett))
        _against_excitation(row, forcing_lead(excitation, rs, effects))
        raw[j, order] = row
    result = _per_point(raw.reshape(-1, size), names, excitation, np.broadcast_to(r, (beta.size, r.size)))
    result["continuous_limit"] = theory.continuous_limit(excitation, r)
    return result


def kernel_variable(name: str, raw, excitation: str, r) -> np.ndarray:
    """One variable from raw kernel rows (n, OUT_SIZE) of points at frequency ratios r (n,): a slot of the
    row, or `transmitted_force`, derived from the first harmonic (theory.transmitted)."""
    if name == "transmitted_force":
        return transmitted_force(excitation, r, raw[:, steady.OUT_TRANSMISSIBILITY], raw[:, steady.OUT_PHASE])
    if name in JENKINS_VARIABLES:
        from friction_sweep.kernels import jenkins_steady

        return raw[:, jenkins_steady.JOUT[name]]
    return raw[:, steady.OUT[name]]


def _per_point(raw, names, excitation, R) -> dict[str, np.ndarray]:
    """The variables `names` from raw kernel rows of the points of the grid R (frequency ratios, the
    grid's shape), in that shape."""
    result = {}
    for name in names:
        values = kernel_variable(name, raw, excitation, R.ravel()).reshape(R.shape)
        if name in _INTEGER:
            values = values.astype(_INTEGER[name])
        result[name] = values
    return result


def friction_force(q, v, forcing, bk, bs):
    """The rigid contact's force f on the mass in q'' + 2 zeta q' + q + f = forcing (docs/equations.md §1), at
    samples (q, v) where the kernel's forcing is `forcing`: bk sgn v while slipping; at rest the force that
    holds the mass, forcing - q (q' = q'' = 0), which the stick band bounds by bs (at an instant of reversal,
    where friction is set-valued, the nearest value of the band)."""
    return np.where(v != 0.0, bk * np.sign(v), np.clip(forcing - q, -bs, bs))


def time_histories(excitation: str, points, samples_per_period: int, effects=None, settings=None):
    """Steady-state orbits of the given (r, beta) points, sampled uniformly in time.

    Returns arrays of shape (n_points, n_samples) with n_samples = samples_per_period times the
    longest orbit period among the points (shorter orbits are padded with NaN): time in forcing
    periods from a maximum of the excitation, the response x, the excitation, the relative displacement
    (the equation's q or z), its velocity and the friction force (friction_force, or the Jenkins contact's
    spring force: against the relative displacement, the hysteresis loop); plus per point the orbit period and
    the regime. Where the
    kernel's forcing leads the excitation (forcing_lead), the orbit is replayed from the kernel's section
    one period longer and sampled at the excitation's times, so the samples are exact, whatever the orbit.
    """
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    r, beta = pts[:, 0], pts[:, 1]
    settings = dict(settings or {})  # one solve from the settings' start (kernel_settings drops `starts`)
    raw = solve_flat(excitation, r, beta, effects, **settings)
    sett = kernel_settings(settings)
    A, c, bk, bs, zeta = point_parameters(excitation, r, beta, effects)
    lead = forcing_lead(excitation, r, effects)
    kappa = contact_stiffness(effects)
    if kappa > 0.0:
        from friction_sweep.kernels import jenkins_steady
    orbit = np.where(np.isfinite(raw[:, steady.OUT_ORBIT_PERIOD]), raw[:, steady.OUT_ORBIT_PERIOD], 0).astype(int)
    n = samples_per_period * max(1, int(orbit.max(initial=1)))
    shape = (pts.shape[0], n)
    out = {name: np.full(shape, np.nan) for name in
           ("history_time", "history_displacement", "history_excitation", "history_relative_displacement",
            "history_relative_velocity", "history_friction_force")}
    frac = np.arange(samples_per_period) / samples_per_period
    for i in range(pts.shape[0]):
        k = orbit[i]
        if k == 0:  # no steady state: nothing honest to show
            continue
        T = 2 * np.pi / r[i]
        ts = frac * T
        # the excitation's time t is the kernel's t + delay; the samples at kernel times ts + delay, sorted
        # into one period (those past its end wrap to its start), fall `wrapped` samples late in the replay
        delay = lead[i] / r[i]
        shifted = ts + delay
        wrapped = int(np.count_nonzero(shifted >= T)) if delay else 0
        kts = np.concatenate((shifted[samples_per_period - wrapped:] - T, shifted[:samples_per_period - wrapped]))
        periods = k + (delay != 0.0)
        sq = np.empty((periods, samples_per_period))
        sv = np.empty((periods, samples_per_period))
        sw = np.full((periods, samples_per_period), np.nan)  # the Jenkins slider's position
        q0, v0, mode0 = raw[i, steady.OUT_END_Q], raw[i, steady.OUT_END_V], int(raw[i, steady.OUT_END_MODE])
        if kappa > 0.0 and np.isfinite(raw[i, jenkins_steady.JOUT_END_W]):
            status = jenkins_steady.sample_orbit_jenkins(
                q0, v0, raw[i, jenkins_steady.JOUT_END_W], mode0,
                JenkinsPoint(A[i], r[i], bk[i], bs[i], zeta[i], c[i], kappa), sett[SET_STOP_TOL],
                int(sett[SET_WORK_BUDGET]), periods, kts, sq, sv, sw)
        else:  # the rigid model's (a Jenkins point without friction is one: no slider position)
            status = steady.sample_orbit(q0, v0, mode0, Point(A[i], r[i], bk[i], bs[i], zeta[i], c[i]),
                                         sett[SET_STOP_TOL], int(sett[SET_WORK_BUDGET]), periods, kts, sq, sv)
        if status != 0:  # the replay ran out of budget: incomplete samples are not shown
            continue
        m = k * samples_per_period
        q_at = sq.ravel()[wrapped:wrapped + m]
        v_at = sv.ravel()[wrapped:wrapped + m]
        angle = r[i] * np.tile(ts, k)
        out["history_time"][i, :m] = (np.arange(m) / samples_per_period)
        out["history_relative_displacement"][i, :m] = q_at
        out["history_relative_velocity"][i, :m] = v_at
        out["history_excitation"][i, :m] = np.cos(angle)
        out["history_displacement"][i, :m] = q_at + c[i] * np.cos(angle)
        w_at = sw.ravel()[wrapped:wrapped + m]
        if np.isfinite(w_at).all():  # the Jenkins contact: its spring's force, kappa (q - w)
            out["history_friction_force"][i, :m] = kappa * (q_at - w_at)
        else:
            out["history_friction_force"][i, :m] = friction_force(q_at, v_at, A[i] * np.cos(angle + lead[i]), bk[i],
                                                                  bs[i])
    out["history_orbit_period"] = orbit.astype(float)
    out["history_regime"] = raw[:, steady.OUT_REGIME].astype(np.int8)
    return out
