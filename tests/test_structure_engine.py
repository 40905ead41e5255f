"""The multi-DoF engine (friction_sweep.structures, kernels/structure) against independent truths.

- one mass, one contact: the dedicated 1-DoF kernels (methods.event, a separately written engine) in
  every regime, force, base and joined, rigid and Jenkins, with damping and static friction;
- zero friction: the linear response (K - w^2 M + i w C)^-1 F, solved here by numpy;
- very large friction: the linear structure with its contacts stuck (rigid contacts as constraints
  x = N q, Jenkins contacts as their springs), solved here;
- sizes up to 20 masses and 8 contacts run, on one compilation.

The independent integrator (DOP853 with event switching) is tests/test_structure_reference.py's (REF).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from friction_sweep.codes import Regime, SteadyState
from friction_sweep.kernels import steady as one_dof
from friction_sweep.methods import event
from friction_sweep.structures import ContactDef, StructureDef, assemble, natural_frequencies, solve_points

R = np.array([0.2, 0.3, 0.5, 0.8, 1.0, 1.2, 1.5, 2.0, 3.0])
BETAS = (0.1, 0.5, 0.9, 1.2)


def one_mass(scene: str, beta: float = 1.0, zeta: float = 0.0, kappa: float | None = None,
             ratio: float = 1.0) -> StructureDef:
    """The 1-DoF scenes as structures (DESIGN §7): force: forcing on the mass, contact to ground; base:
    spring (and dashpot) to the base, contact to ground; joined: spring and contact to the base."""
    to = "base" if scene in ("base", "joined") else "ground"
    wall = "base" if scene == "joined" else "ground"
    contact = ContactDef("c", ("m", wall), beta, kappa, ratio)
    dampers = ((to, "m", 2.0 * zeta),) if zeta else ()
    return StructureDef("force" if scene == "force" else "base", {"m": 1.0}, ((to, "m", 1.0),), dampers,
                        (contact,), {"m": 1.0} if scene == "force" else {})


def _effects(zeta, kappa, ratio, scene):
    effects = {}
    if zeta:
        effects["viscous_damping"] = {"ratio": zeta, "to": "base"} if scene != "force" else zeta
    if kappa:
        effects["contact_stiffness"] = kappa
    if ratio != 1.0:
        effects["static_friction_ratio"] = ratio
    return effects


def _compare(scene, zeta=0.0, kappa=None, ratio=1.0, betas=BETAS, r=R):
    for beta in betas:
        a = assemble(one_mass(scene, 1.0, zeta, kappa, ratio))
        got = solve_points(a, r, np.full(r.size, beta))
        # the 1-DoF force scene is the base scene's equation (x'' + x + beta sgn x' = cos r t)
        ref = event.solve_flat("base" if scene == "force" else scene, r, np.full(r.size, beta),
                               _effects(zeta, kappa, ratio, scene))
        # r = 1/(2n) undamped: the 1-DoF kernels flag the family of stick-free orbits (FAMILY), whose first
        # harmonic is every member's; the engine reports the member it settles on (its peak may differ)
        family = ref[:, one_dof.OUT_STEADY_STATE] == SteadyState.FAMILY
        ok = (ref[:, one_dof.OUT_STEADY_STATE] == SteadyState.CONVERGED) | family
        np.testing.assert_array_equal(got["steady_state"] == SteadyState.CONVERGED, ok, err_msg=f"{beta=}")
        np.testing.assert_allclose(got["amplitude"][ok, 0], ref[ok, one_dof.OUT_TRANSMISSIBILITY], rtol=0,
                                   atol=1e-10, err_msg=f"{beta=}")
        single = ok & ~family
        np.testing.assert_allclose(got["peak_amplitude"][single, 0], ref[single, one_dof.OUT_PEAK_TRANSMISSIBILITY],
                                   rtol=0, atol=1e-9, err_msg=f"{beta=}")
        np.testing.assert_array_equal(got["regime"][:, 0], ref[:, one_dof.OUT_REGIME].astype(np.int8),
                                      err_msg=f"{beta=}")
        np.testing.assert_array_equal(got["stops_per_period"][ok, 0], ref[ok, one_dof.OUT_STOPS_PER_PERIOD],
                                      err_msg=f"{beta=}")
        moving = ok & (ref[:, one_dof.OUT_TRANSMISSIBILITY] > 1e-6)
        lag = np.abs((got["phase"][moving, 0] - ref[moving, one_dof.OUT_PHASE] + 180) % 360 - 180)
        assert np.all(lag < 1e-7), (beta, lag)
        # a mass the kernels find standing still (stuck the whole period under force excitation) has no phase
        still = ok & (ref[:, one_dof.OUT_TRANSMISSIBILITY] == 0.0)
        np.testing.assert_array_equal(got["amplitude"][still, 0], 0.0, err_msg=f"{beta=}")
        assert np.all(np.isnan(got["phase"][still, 0])) and np.all(np.isnan(ref[still, one_dof.OUT_PHASE])), beta
        assert np.all(np.isfinite(got["phase"][moving, 0])), beta


@pytest.mark.parametrize("scene", ["force", "base", "joined"])
def test_one_mass_rigid_reproduces_the_1dof_kernels(scene):
    _compare(scene)


@pytest.mark.parametrize("scene", ["force", "base"])
def test_one_mass_with_damping_reproduces_the_1dof_kernels(scene):
    _compare(scene, zeta=0.05, betas=(0.1, 0.5, 0.9))


@pytest.mark.parametrize("scene, zeta", [("force", 0.0), ("force", 0.05), ("base", 0.0)])
def test_one_mass_rigid_at_friction_equal_to_the_force_amplitude_never_moves(scene, zeta):
    """beta = A = 1: the forcing's swing touches the band tangentially at each maximum, a tie (ties.py) that
    the 1-DoF kernels decide as no motion from rest (Eqs. 24, 41). The engine once let the stuck force's rounding
    decide there: stick-slip, 2 stops a period, stuck 0.99999998 of it."""
    _compare(scene, zeta=zeta, betas=(1.0,))
    got = solve_points(assemble(one_mass(scene, 1.0, zeta)), R, np.ones(R.size))
    assert (got["regime"] == Regime.STUCK).all() and (got["stuck_fraction"] == 1.0).all()


def test_one_mass_static_friction_reproduces_the_1dof_kernels():
    _compare("base", ratio=1.3, betas=(0.3, 0.6, 0.9))


@pytest.mark.parametrize("scene", ["force", "base", "joined"])
def test_one_mass_jenkins_reproduces_the_1dof_kernels(scene):
    """Transmissibility, and exactly regime, stops and slips: the 1-DoF Jenkins kernel's labels, its creep
    rule included (stick-slip at r = 0.3, where the held mass creeps several times per stop)."""
    from friction_sweep.kernels.jenkins_steady import JOUT_SLIPS

    r = np.array([0.3, 0.5, 0.6, 0.8, 0.9, 1.3, 1.5, 2.0])
    for beta in (0.2, 0.6):
        a = assemble(one_mass(scene, 1.0, kappa=10.0))
        got = solve_points(a, r, np.full(r.size, beta))
        ref = event.solve_flat("base" if scene == "force" else scene, r, np.full(r.size, beta),
                               {"contact_stiffness": 10.0})
        ok = ref[:, one_dof.OUT_STEADY_STATE] == SteadyState.CONVERGED
        assert ok.all()
        np.testing.assert_allclose(got["amplitude"][:, 0], ref[:, one_dof.OUT_TRANSMISSIBILITY], atol=1e-10)
        np.testing.assert_array_equal(got["regime"][:, 0], ref[:, one_dof.OUT_REGIME].astype(np.int8))
        np.testing.assert_array_equal(got["stops_per_period"][:, 0], ref[:, one_dof.OUT_STOPS_PER_PERIOD])
        np.testing.assert_array_equal(got["slips_per_period"][:, 0], ref[:, JOUT_SLIPS])
    assert Regime.STICK_SLIP in got["regime"] or scene == "joined"


@pytest.mark.parametrize("scene", ["force", "joined"])
def test_one_mass_jenkins_with_static_friction_starts_where_the_1dof_kernels_start(scene):
    """Static friction holds two states here (kappa 10, zeta 0.02, mu_s/mu 1.5, beta 0.7), and the start decides.
    From rest the 1-DoF Jenkins kernel's slider is loaded: the contact holds the mass against the forcing, as a
    rigid contact would. The engine's start is that one (steady._rest_sliders), so it reaches the same state, in
    amplitude, peak, phase, regime and stops. A relaxed slider, the engine's earlier start, reached stick-slip
    (force: 0.6947) at every r here, where the 1-DoF kernel stays stuck (0.0916). (Base with its spring-parallel
    dashpot reaches the same states too, but the 1-DoF kernel starts at the maximum of its forcing, which leads
    the base by atan(2 zeta r), and the engine at the base's: the start's slips leave the stuck slider 1e-4 apart,
    and the peaks with it.)"""
    _compare(scene, zeta=0.02, kappa=10.0, ratio=1.5, betas=(0.7,), r=np.linspace(0.15, 0.66, 8))


@pytest.mark.parametrize("scene", ["force", "base", "joined"])
def test_one_mass_undamped_jenkins_with_static_friction_is_the_1dof_kernels(scene):
    """Undamped, kappa 10, mu_s/mu 1.5: the stuck mass's free motion never dies out. The 1-DoF kernel takes the
    stuck orbit where that free motion can never carry the contact force across the static band (from rest, or
    after a marched period without slips: its reach |centre| + |forced| + |free|); the engine does the same
    (steady._held_forever, the free part bounded by its energy, exact at n = 1). It once ran to the period cap
    at each of these points, or (w 0.66, beta 0.7) took a stuck orbit from its first period where the motion
    slips later and settles continuous (0.821, not 0.095)."""
    r = np.array([0.6615384615384616, 0.8, 1.5, 2.0, 2.1961538461538463])
    _compare(scene, kappa=10.0, ratio=1.5, betas=(0.7, 1.5, 3.0), r=r)


@pytest.mark.parametrize("kt", [5.0, None])
def test_an_undamped_structure_held_in_every_band_settles_on_its_stuck_forced_orbit(kt):
    """Undamped, static equal to kinetic friction: in the limit of vanishing damping the free motion dies out, so
    where the forced orbit with every contact stuck keeps every contact force inside its band that is the steady
    state's first harmonic (steady._held_forever, jenkins_steady's rule): the stuck linear structure's X, taken
    about the relaxed sliders (max|x| = |X|, the 1-DoF kernels' convention), in one period. Elsewhere (w 1.3) the
    march decides, and a contact slips. Jenkins contacts on m0 and the forced m2; rigid ones hold m0 and m2
    while the forcing on m1 between them shakes it (its free vibration never dies out, so the march alone never
    settles; without the rule Newton's shot found the same first harmonic after 8 to 112 periods)."""
    w = np.array([0.3, 0.6, 1.3])
    d = chain(3, contacts=2, kt=kt, damping=0.0, friction=1.0)
    if kt is None:
        d = dataclasses.replace(d, forcing={"m1": 1.0})
    got = solve_points(assemble(d), w, np.ones(w.size))
    M = np.diag([1.0, 1.05, 1.1])
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.1, -1.1], [0.0, -1.1, 1.1]])
    Wc = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    if kt is not None:
        f = np.array([0.0, 0.0, 1.0])
        X = np.array([np.linalg.solve(K + kt * Wc.T @ Wc - x * x * M, f) for x in w])
        force = kt * X @ Wc.T
    else:
        # m0 and m2 held: m1 alone on its springs, the contacts carrying what the springs pull on m0 and m2
        f = np.array([0.0, 1.0, 0.0])
        X = np.array([[0.0, 1.0 / (K[1, 1] - x * x * M[1, 1]), 0.0] for x in w])
        force = np.array([np.linalg.lstsq(Wc.T, f - (K - x * x * M) @ xx, rcond=None)[0] for x, xx in zip(w, X, strict=True)])
    held = (np.abs(force) / np.array([1.0, 1.1]) < 1.0).all(axis=1)
    np.testing.assert_array_equal(held, [True, True, False])
    assert (got["steady_state"][held] == SteadyState.CONVERGED).all()
    assert (got["regime"][held] == Regime.STUCK).all() and (got["periods"][held] == 1).all()
    np.testing.assert_allclose(got["amplitude"][held], np.abs(X[held]), rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(got["peak_amplitude"][held], np.abs(X[held]), rtol=1e-12, atol=1e-14)
    np.testing.assert_array_equal(got["stops_per_period"][held], 0.0)
    assert not (got["regime"][2] == Regime.STUCK).all()


@pytest.mark.parametrize("scene, r", [("force", 2.123076923076923), ("joined", 1.3192307692307693)])
def test_a_slider_that_never_slips_never_stops(scene, r):
    """Undamped, beta 2, kappa 10: the slider never slips (stuck), and so the contact never stops, as the 1-DoF
    kernels count it (the engine's measurement once counted a stop a period there)."""
    from friction_sweep.kernels.jenkins_steady import JOUT_SLIPS

    a = assemble(one_mass(scene, 1.0, kappa=10.0))
    got = solve_points(a, [r], [2.0])
    ref = event.solve_flat("base" if scene == "force" else scene, np.array([r]), np.array([2.0]),
                           {"contact_stiffness": 10.0})
    assert ref[0, JOUT_SLIPS] == 0.0 and ref[0, one_dof.OUT_STOPS_PER_PERIOD] == 0.0
    assert got["regime"][0, 0] == Regime.STUCK and got["slips_per_period"][0, 0] == 0.0
    assert got["stops_per_period"][0, 0] == 0.0
    np.testing.assert_allclose(got["amplitude"][0, 0], ref[0, one_dof.OUT_TRANSMISSIBILITY], atol=1e-10)


@pytest.mark.parametrize("zeta", [0.0, 0.05])
def test_one_mass_jenkins_stuck_fraction_is_the_1dof_kernels(zeta):
    """stuck_fraction of a Jenkins contact is the 1-DoF Jenkins kernel's: the time the contact holds the mass,
    and 1 where its slider never slips (beta = 1.5 > A: stuck all period), regime exactly."""
    r = np.array([0.3, 0.5, 0.6, 0.8, 0.9, 1.3, 1.5, 2.0])
    for beta in (0.2, 0.6, 1.5):
        a = assemble(one_mass("force", 1.0, zeta=zeta, kappa=10.0))
        got = solve_points(a, r, np.full(r.size, beta))
        ref = event.solve_flat("base", r, np.full(r.size, beta), _effects(zeta, 10.0, 1.0, "force"))
        assert (ref[:, one_dof.OUT_STEADY_STATE] == SteadyState.CONVERGED).all()
        np.testing.assert_array_equal(got["regime"][:, 0], ref[:, one_dof.OUT_REGIME].astype(np.int8))
        np.testing.assert_allclose(got["stuck_fraction"][:, 0], ref[:, one_dof.OUT_STUCK_FRACTION], rtol=0,
                                   atol=1e-10, err_msg=f"{beta=}")
    assert (got["stuck_fraction"] == 1.0).all() and (got["regime"] == Regime.STUCK).all()


def test_period_k_orbits_are_shot_on_the_k_period_map():
    """Static above kinetic friction (base, ratio 1.5, beta 0.1) locks onto period-7 and period-16 orbits at
    r = 0.315 and 0.325, which the 1-DoF kernel marches onto within 300 and 269 periods. Marching 30 periods
    at most, shooting every period from the 10th, the engine finds them by Newton on P^k, k the lag at which
    the march repeats best: the 1-DoF kernel's k, amplitude, stops and regime."""
    r = np.array([0.315, 0.325])
    beta = np.full(r.size, 0.1)
    ref = event.solve_flat("base", r, beta, {"static_friction_ratio": 1.5})
    assert (ref[:, one_dof.OUT_STEADY_STATE] == SteadyState.CONVERGED).all()
    np.testing.assert_array_equal(ref[:, one_dof.OUT_ORBIT_PERIOD], [7, 16])
    got = solve_points(assemble(one_mass("base", 1.0, ratio=1.5)), r, beta,
                       settings={"max_periods": 30, "shoot_after": 10, "shoot_every": 1})
    assert (got["steady_state"] == SteadyState.CONVERGED).all() and (got["periods"] < 30).all()
    np.testing.assert_array_equal(got["orbit_period"], ref[:, one_dof.OUT_ORBIT_PERIOD])
    np.testing.assert_allclose(got["amplitude"][:, 0], ref[:, one_dof.OUT_TRANSMISSIBILITY], rtol=0, atol=1e-10)
    np.testing.assert_array_equal(got["stops_per_period"][:, 0], ref[:, one_dof.OUT_STOPS_PER_PERIOD])
    np.testing.assert_array_equal(got["regime"][:, 0], ref[:, one_dof.OUT_REGIME].astype(np.int8))


def chain(n: int, contacts: int = 0, kt: float | None = None, damping: float = 0.02, friction: float = 0.3,
          excitation: str = "force") -> StructureDef:
    """n masses in a chain from the ground (or the base), contacts from every other mass to the ground
    and one between two masses."""
    names = [f"m{i}" for i in range(n)]
    first = "base" if excitation == "base" else "ground"
    springs = tuple([(first, names[0], 1.0)] + [(names[i], names[i + 1], 1.0 + 0.1 * i) for i in range(n - 1)])
    dampers = tuple((first if i == 0 else names[i - 1], names[i], damping) for i in range(n))
    cs = []
    for j in range(contacts):
        ends = (names[(2 * j) % n], "ground") if j % 3 != 2 or n < 2 else (names[j % n], names[(j + 1) % n])
        cs.append(ContactDef(f"c{j}", ends, friction * (1 + 0.1 * j), kt))
    masses = {name: 1.0 + 0.05 * i for i, name in enumerate(names)}
    forcing = {names[-1]: 1.0} if excitation == "force" else {}
    return StructureDef(excitation, masses, springs, dampers, tuple(cs), forcing)


def _linear(M, C, K, F):
    return lambda w: np.linalg.solve(K - w * w * M + 1j * w * C, F(w))


@pytest.mark.parametrize("excitation", ["force", "base"])
def test_zero_friction_is_the_linear_response(excitation):
    d = chain(3, contacts=2, excitation=excitation)
    a = assemble(d)
    w = np.array([0.3, 0.7, 1.1, 1.9])
    got = solve_points(a, w, np.zeros(w.size))
    assert np.all(got["steady_state"] == SteadyState.CONVERGED)
    Y = 1.0
    Kb = np.array([1.0, 0.0, 0.0]) if excitation == "base" else np.zeros(3)
    Cb = np.array([0.02, 0.0, 0.0]) if excitation == "base" else np.zeros(3)
    f = np.array([0.0, 0.0, 1.0]) if excitation == "force" else np.zeros(3)
    M = np.diag([1.0, 1.05, 1.1])
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.1, -1.1], [0.0, -1.1, 1.1]])
    C = np.array([[0.04, -0.02, 0.0], [-0.02, 0.04, -0.02], [0.0, -0.02, 0.02]])
    X = np.array([np.linalg.solve(K - x * x * M + 1j * x * C, f + Y * (Kb + 1j * x * Cb)) for x in w])
    np.testing.assert_allclose(got["amplitude"], np.abs(X), rtol=1e-12, atol=1e-13)
    lag = (got["phase"] + np.degrees(np.angle(X)) + 180) % 360 - 180
    assert np.max(np.abs(lag)) < 1e-9


@pytest.mark.parametrize("kt", [None, 5.0])
def test_very_large_friction_is_the_stuck_linear_structure(kt):
    d = chain(3, contacts=2, kt=kt, friction=1e6)
    a = assemble(d)
    w = np.array([0.4, 0.9, 1.6])
    got = solve_points(a, w, np.ones(w.size))
    assert np.all(got["regime"] == Regime.STUCK)
    M = np.diag([1.0, 1.05, 1.1])
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.1, -1.1], [0.0, -1.1, 1.1]])
    C = np.array([[0.04, -0.02, 0.0], [-0.02, 0.04, -0.02], [0.0, -0.02, 0.02]])
    f = np.array([0.0, 0.0, 1.0])
    Wc = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # contacts of m0 and m2 to the ground
    if kt is None:
        _, _, vt = np.linalg.svd(Wc)
        N = vt[2:].T
        X = np.array([N @ np.linalg.solve(N.T @ (K - x * x * M + 1j * x * C) @ N, N.T @ f) for x in w])
    else:
        Kj = K + kt * Wc.T @ Wc
        X = np.array([np.linalg.solve(Kj - x * x * M + 1j * x * C, f) for x in w])
    np.testing.assert_allclose(got["amplitude"], np.abs(X), rtol=1e-10, atol=1e-12)
    # from rest no contact ever slips: every slider and stuck position stays where it started (a stuck orbit is
    # one of a family of stuck positions; the motion from rest settles on this member, not another). A rigid
    # contact holds its rest position: the orbit is the harmonic one about rest, max|x| = |X|. A Jenkins slider
    # starts loaded with the force its contact carries as a rigid link holding the structure at rest (the
    # 1-DoF kernels' start), lambda = (W M^-1 W^T)^-1 W M^-1 f at t = 0: the orbit is the harmonic one about the
    # static position of those loaded springs, K_J c = -W^T lambda, and max|x| = |c| + |X|. (The load is the start's
    # definition, so c checks the engine against the rule, not against physics; the one-mass tests check the rule
    # against the 1-DoF kernels, and tests/independent_structure.py's rest, written apart, against the engine.)
    centre = np.zeros(3)
    if kt is not None:
        Minv = np.linalg.inv(M)
        lam = np.linalg.solve(Wc @ Minv @ Wc.T, Wc @ Minv @ f)
        centre = np.linalg.solve(Kj, -Wc.T @ lam)
        assert np.abs(centre).max() > 0.1 * np.abs(X).max()
    np.testing.assert_allclose(got["peak_amplitude"], np.abs(centre) + np.abs(X), rtol=1e-9, atol=1e-12)
    # the masses a stuck rigid contact holds to the ground stand still: amplitude exactly 0 and no phase (the
    # engine's harmonic of their constant position is rounding, 1e-16 of it, with a phase of rounding)
    # (rigid: the forced mass m2 is held, and so is all the chain)
    still = np.abs(X) == 0.0
    assert still.all() if kt is None else not still.any()
    np.testing.assert_array_equal(got["amplitude"][still], 0.0)
    assert np.all(np.isnan(got["phase"][still]))
    lag = (got["phase"][~still] + np.degrees(np.angle(X[~still])) + 180) % 360 - 180
    assert np.all(np.abs(lag) < 1e-8)


def test_a_mass_held_still_has_no_phase_beside_one_that_moves():
    """The blade and its damper with the platform contact stuck (friction far above any force): the damper
    stands still (amplitude 0, phase NaN) at its rest position, the blade moves as one mass on both springs,
    X = 1 / (3 - w^2 + 0.004 i w)."""
    d = StructureDef("force", {"blade": 1.0, "damper": 0.1}, (("ground", "blade", 1.0), ("blade", "damper", 2.0)),
                     (("ground", "blade", 0.004),), (ContactDef("platform", ("damper", "ground"), 1e6),),
                     {"blade": 1.0})
    w = np.array([0.5, 1.5, 2.5])
    got = solve_points(assemble(d), w, np.ones(w.size))
    assert np.all(got["regime"] == Regime.STUCK)
    X = 1.0 / (3.0 - w * w + 0.004j * w)
    np.testing.assert_allclose(got["amplitude"][:, 0], np.abs(X), rtol=1e-10)
    lag = (got["phase"][:, 0] + np.degrees(np.angle(X)) + 180) % 360 - 180
    assert np.all(np.abs(lag) < 1e-8)
    np.testing.assert_array_equal(got["amplitude"][:, 1], 0.0)
    assert np.all(np.isnan(got["phase"][:, 1]))
    # held from rest, the damper never leaves it: its peak is 0, the blade's the harmonic one's
    np.testing.assert_array_equal(got["peak_amplitude"][:, 1], 0.0)
    np.testing.assert_allclose(got["peak_amplitude"][:, 0], np.abs(X), rtol=1e-9)


def test_natural_frequencies_of_one_mass():
    a = assemble(one_mass("base", kappa=3.0))
    np.testing.assert_allclose(natural_frequencies(a, "free"), [1.0])
    np.testing.assert_allclose(natural_frequencies(a, "stuck"), [2.0])
    assert natural_frequencies(assemble(one_mass("base")), "stuck").size == 0


def test_sizes_up_to_20_masses_and_8_contacts_run_on_one_compilation():
    from friction_sweep.kernels.structure.steady import solve_batch

    for n, m, kt, w in ((1, 1, None, (0.5, 1.3)), (2, 1, None, (0.5, 1.3)), (10, 2, 4.0, (0.5, 1.3)),
                        (20, 8, None, (0.5,))):
        a = assemble(chain(n, contacts=m, kt=kt))
        got = solve_points(a, np.array(w), np.ones(len(w)))
        assert np.all(got["steady_state"] == SteadyState.CONVERGED), (n, m)
        assert np.all(np.isfinite(got["amplitude"]))
    assert len(solve_batch.signatures) == 1


def test_a_structure_nothing_holds_is_refused():
    d = StructureDef("force", {"a": 1.0, "b": 1.0}, (("a", "b", 1.0),), (), (), {"a": 1.0})
    with pytest.raises(ValueError, match="unrestrained"):
        assemble(d)


def test_floquet_multiplier_of_one_mass_is_the_1dof_kernels():
    """The saltation monodromy's largest multiplier against the 1-DoF event kernel's (its own monodromy)."""
    a = assemble(one_mass("base", 1.0, zeta=0.05))
    r = np.array([0.5, 0.9, 1.5, 2.5])
    beta = np.full(r.size, 0.4)
    got = solve_points(a, r, beta, outputs=("amplitude", "stability"))
    ref = event.solve_flat("base", r, beta, _effects(0.05, None, 1.0, "base"), stability=1)
    np.testing.assert_allclose(got["floquet_multiplier"], ref[:, one_dof.OUT["floquet_multiplier"]], rtol=1e-8)
    plain = solve_points(a, r, beta)
    assert np.isnan(plain["floquet_multiplier"]).all()


@pytest.mark.parametrize("scene, kappa, beta", [("force", None, 2.0), ("base", None, 2.0), ("force", 10.0, 2.0),
                                                ("joined", 10.0, 1.0), ("force", 10.0, 0.3)])
def test_floquet_multiplier_is_nan_where_the_1dof_kernels_find_a_continuum_of_orbits(scene, kappa, beta):
    """Stuck (a rigid contact, a Jenkins slider that never slips) the orbit is one of a continuum of stuck
    positions: no multiplier, NaN, as the 1-DoF kernels report; elsewhere theirs."""
    a = assemble(one_mass(scene, 1.0, 0.05, kappa))
    r = np.array([0.3, 0.5, 0.8, 1.5, 2.5])
    got = solve_points(a, r, np.full(r.size, beta), outputs=("amplitude", "regime", "stability"))
    ref = event.solve_flat("base" if scene == "force" else scene, r, np.full(r.size, beta),
                           _effects(0.05, kappa, 1.0, scene), stability=1)
    stuck = ref[:, one_dof.OUT_REGIME] == Regime.STUCK
    assert np.isnan(ref[stuck, one_dof.OUT["floquet_multiplier"]]).all()
    np.testing.assert_allclose(got["floquet_multiplier"], ref[:, one_dof.OUT["floquet_multiplier"]], rtol=1e-8)


def test_node_matrices_are_the_matrix_exponential_at_each_node():
    """flow.expm_nodes (the measurement's exp(A x_q h) at the Gauss nodes, one Taylor series for all) against
    SciPy's Pade expm, on a random matrix scaled to one step (|A| h = 1/2)."""
    import scipy.linalg

    from friction_sweep.kernels.structure.flow import expm_nodes, expm_taylor
    from friction_sweep.kernels.structure.period import GAUSS_X

    rng = np.random.default_rng(3)
    A = rng.normal(size=(7, 7))
    h = 0.5 / np.abs(A).sum(axis=1).max()
    G = np.empty((GAUSS_X.size, 7, 7))
    expm_nodes(A, h, GAUSS_X, G)
    for q, x in enumerate(GAUSS_X):
        np.testing.assert_allclose(G[q], scipy.linalg.expm(A * x * h), rtol=0, atol=1e-15)
    E = np.empty((7, 7))
    expm_taylor(A, h, E)
    np.testing.assert_allclose(E, scipy.linalg.expm(A * h), rtol=0, atol=1e-15)
