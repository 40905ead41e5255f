"""The output `harmonics`: exact Fourier coefficients of the steady orbit (kernels/fourier.py, kernels/harmonics.py).

Independent truths: the first-harmonic measurement (transmissibility, phase: the event kernel's projection,
another code path), Parseval against the mean square of a densely sampled time history, an FFT of that
history (its aliasing error), half-wave symmetry (even harmonics vanish), the stuck state's closed form, and
the energy balance: the friction force's work over the orbit, from the harmonics, equals friction_energy
(kinetic friction x sliding distance), and the hysteresis loop's area from the sampled friction force.
"""

from __future__ import annotations

import numpy as np
import pytest

from friction_sweep.codes import MethodUsed, Regime
from friction_sweep.kernels import steady
from friction_sweep.methods import event
from friction_sweep.spec import SpecError, parse_spec_text

H = 64

#: (excitation, r, beta, effects): continuous, stick-slip, next to resonance, period-2 stops, damping, static
POINTS = [
    ("base", 0.3, 0.1, None),
    ("base", 0.7, 0.5, None),
    ("base", 1.0, 0.9, None),
    ("base", 1.0 + 1e-9, 0.8, None),
    ("base", 0.15, 0.05, None),
    ("base", 2.5, 0.2, None),
    ("force", 0.6, 0.8, None),
    ("joined", 1.0, 0.9, None),
    ("joined", 2.5, 0.2, None),
    ("joined", 1.3, 1.2, None),
    ("base", 0.8, 0.3, {"viscous_damping": 0.1}),
    ("base", 0.8, 0.3, {"viscous_damping": {"ratio": 0.05, "to": "base"}}),
    ("base", 0.4, 0.3, {"static_friction_ratio": 1.5}),
]


def solve(excitation, r, beta, effects=None, highest=H):
    """Raw rows and the harmonics (X, F: complex, shape (highest + 1,)) of one point."""
    raw = event.solve_flat(excitation, np.array([r]), np.array([beta]), effects)
    h = event.harmonics(excitation, np.array([r]), np.array([beta]), raw, highest, effects)
    X = h["response_harmonic_real"][:, 0] + 1j * h["response_harmonic_imag"][:, 0]
    F = h["friction_harmonic_real"][:, 0] + 1j * h["friction_harmonic_imag"][:, 0]
    return raw[0], X, F


def history(excitation, r, beta, effects=None, n=4096):
    """One period of the steady orbit sampled at n points: x, q (the equation's displacement), f."""
    out = event.time_histories(excitation, [[r, beta]], n, effects)
    assert out["history_orbit_period"][0] == 1.0
    return (out["history_displacement"][0, :n], out["history_relative_displacement"][0, :n],
            out["history_friction_force"][0, :n])


@pytest.mark.parametrize(("excitation", "r", "beta", "effects"), POINTS)
def test_first_harmonic_is_the_transmissibility_and_phase(excitation, r, beta, effects):
    raw, X, _ = solve(excitation, r, beta, effects)
    assert raw[steady.OUT_REGIME] in (Regime.CONTINUOUS, Regime.STICK_SLIP)
    t = raw[steady.OUT_TRANSMISSIBILITY]
    assert abs(abs(X[1]) - t) <= 1e-14 * max(1.0, t)
    lag = event.phase.wrap_degrees(np.degrees(-np.angle(X[1])))
    assert abs(lag - raw[steady.OUT_PHASE]) <= 1e-12


@pytest.mark.parametrize(("excitation", "r", "beta", "effects"),
                         [p for p in POINTS if p[3] is None or "static_friction_ratio" not in p[3]])
def test_half_wave_symmetric_orbits_have_odd_harmonics_only(excitation, r, beta, effects):
    """With static = kinetic friction the steady state is unique and the scenes are odd (x -> -x with
    t -> t + T/2), so the orbit is half-wave symmetric: every even coefficient, the mean included, vanishes."""
    raw, X, F = solve(excitation, r, beta, effects)
    if raw[steady.OUT_ORBIT_PERIOD] != 1.0:
        pytest.skip("a period-k orbit")
    scale = np.abs(X).max()
    assert np.abs(X[0::2]).max() <= 1e-13 * scale
    # f jumps at the stops, whose times carry the stop search's rounding (~1e-13 of the period at r = 1): a
    # jump moved by dt leaves ~ beta dt / T in every harmonic, even or odd
    assert np.abs(F[0::2]).max() <= 1e-12 * np.abs(F).max()
    assert np.abs(X[1::2]).min() > 0.0


@pytest.mark.parametrize(("excitation", "r", "beta", "effects"), [
    ("base", 0.3, 0.1, None), ("base", 0.7, 0.5, None), ("joined", 2.5, 0.2, None), ("force", 0.6, 0.8, None),
    ("base", 1.0 + 1e-9, 0.8, None), ("base", 0.8, 0.3, {"viscous_damping": 0.1}),
    # the spring-parallel dashpot's forcing leads the base: harmonics and samples both against the base
    ("base", 0.8, 0.3, {"viscous_damping": {"ratio": 0.05, "to": "base"}}),
])
def test_parseval_and_fft_against_a_sampled_orbit(excitation, r, beta, effects):
    n = 4096
    raw, X, F = solve(excitation, r, beta, effects)
    x, _, f = history(excitation, r, beta, effects, n=n)
    # the mean square of x over the period: the samples' mean is its trapezoid rule, error O(n^-2) (x' has
    # kinks where friction jumps); Parseval's tail beyond H falls like H^-5 (X_k ~ k^-3)
    mean_square = np.mean(x * x)
    parseval = abs(X[0]) ** 2 + 0.5 * np.sum(np.abs(X[1:]) ** 2)
    assert abs(parseval - mean_square) <= 1e-7 * mean_square
    # ... and it converges: truncation at 8 misses more than at 64
    parseval_8 = abs(X[0]) ** 2 + 0.5 * np.sum(np.abs(X[1:9]) ** 2)
    assert abs(parseval_8 - mean_square) > abs(parseval - mean_square)
    # an FFT of the samples (numpy's exp(-2 pi i k j / n) is exp(-i k r t) at the samples): aliasing adds
    # X_{k + m n} (~ (n - k)^-3 of the orbit) to each coefficient
    fft = np.fft.rfft(x) / n
    fft[1:] *= 2.0
    assert np.abs(fft[:H + 1] - X).max() <= 1e-9 * np.abs(X).max()
    # the friction force jumps (sgn v), so its samples' FFT errs by O(1/n) of beta, its Parseval by O(1/H)
    fftf = np.fft.rfft(f) / n
    fftf[1:] *= 2.0
    assert np.abs(fftf[:H + 1] - F).max() <= 20.0 * beta / n * 2.0
    parseval_f = abs(F[0]) ** 2 + 0.5 * np.sum(np.abs(F[1:]) ** 2)
    assert parseval_f <= np.mean(f * f) * (1 + 1e-9) and np.mean(f * f) - parseval_f <= beta ** 2 * 4.0 / H


@pytest.mark.parametrize(("excitation", "r", "beta", "effects"), POINTS)
def test_friction_work_from_the_harmonics_is_the_friction_energy(excitation, r, beta, effects):
    """int f q' dt over the period = pi sum_k k Im(F_k conj(Q_k)) (Q: the equation's displacement; the terms
    fall like k^-3), against friction_energy = kinetic friction x sliding distance (kernels/measure.py)."""
    raw, X, F = solve(excitation, r, beta, effects)
    if raw[steady.OUT_ORBIT_PERIOD] != 1.0:
        pytest.skip("a period-k orbit")
    _, c, *_ = event.point_parameters(excitation, np.array([r]), np.array([beta]), effects)
    Q = X.copy()
    Q[1] -= c[0] * np.exp(1j * event.forcing_lead(excitation, np.array([r]), effects)[0])
    k = np.arange(H + 1)
    work = np.pi * np.sum(k * np.imag(F * np.conj(Q)))
    energy = raw[steady.OUT_FRICTION_ENERGY]
    assert abs(work - energy) <= 1e-4 * energy  # the tail beyond H = 64: ~ sum k^-3 / H


@pytest.mark.parametrize(("excitation", "r", "beta"), [("base", 0.7, 0.5), ("joined", 1.3, 1.2)])
def test_hysteresis_loop_area_is_the_friction_energy(excitation, r, beta):
    raw, *_ = solve(excitation, r, beta)
    _, q, f = history(excitation, r, beta, n=1 << 14)
    # the loop f(q) closed over the period: its area, by the trapezoid rule on the samples
    area = np.sum(0.5 * (f + np.roll(f, -1)) * (np.roll(q, -1) - q))
    assert abs(area - raw[steady.OUT_FRICTION_ENERGY]) <= 1e-3 * raw[steady.OUT_FRICTION_ENERGY]
    assert np.abs(f).max() <= beta * (1 + 1e-15)


def test_stuck_state_is_its_closed_form():
    """Joined above beta = r^2 moves with the wall: x = cos(r t) (X_1 = 1), z at rest at q_s, and the contact
    holds it with f = r^2 cos(r t) - q_s."""
    r, beta = 0.7, 0.6
    raw, X, F = solve("joined", r, beta, highest=4)
    assert raw[steady.OUT_REGIME] == Regime.STUCK
    qs = raw[steady.OUT_END_Q]
    np.testing.assert_array_equal(X, [qs, 1.0, 0.0, 0.0, 0.0])
    np.testing.assert_array_equal(F, [-qs, r * r, 0.0, 0.0, 0.0])


def test_no_steady_state_is_nan():
    raw, X, F = solve("base", 1.0, 0.5, highest=3)
    assert raw[steady.OUT_REGIME] == Regime.UNBOUNDED
    assert np.isnan(X).all() and np.isnan(F).all()


def test_harmonics_do_not_change_the_other_outputs():
    r = np.array([0.4, 1.0, 1.7])
    beta = np.array([0.1, 0.9])
    plain = event.compute_tile("base", r, beta, ("transmissibility", "phase", "regime"))
    with_h = event.compute_tile("base", r, beta, ("transmissibility", "phase", "regime", "harmonics"),
                                settings={"harmonics": 5})
    for name, values in plain.items():
        np.testing.assert_array_equal(values, with_h[name])
    assert with_h["response_harmonic_real"].shape == (6, 2, 3)


SPEC = """scene:
  excitation: base
  effects: {effects}
grid:
  frequency_ratio: [0.5, 1.0]
  force_ratio: [0.1, 0.3]
method: event
outputs: [transmissibility, {outputs}]
settings: {{harmonics: {h}}}
"""


@pytest.mark.parametrize(("effects", "outputs", "h", "where", "says"), [
    ("{}", "harmonics", 65, "t.yaml:9:23: settings.harmonics:", "must be between 1 and 64"),
    ("{}", "harmonics", 0, "t.yaml:9:23: settings.harmonics:", "must be between 1 and 64"),
    ("{}", "phase", 8, "t.yaml:9:23: settings.harmonics:", "harmonics is not listed in outputs"),
])
def test_spec_refuses(effects, outputs, h, where, says):
    with pytest.raises(SpecError) as info:
        parse_spec_text(SPEC.format(effects=effects, outputs=outputs, h=h), "t.yaml")
    assert str(info.value).startswith(where) and says in str(info.value)


def test_auto_takes_every_points_harmonics_from_the_simulation():
    """auto answers continuous points from the theory, which has no orbit: its harmonics are event's at every
    point, and its other variables are as without them."""
    from friction_sweep.methods import auto

    r = np.array([0.4, 1.7, 2.5])
    beta = np.array([0.1, 0.5])
    outputs = ("transmissibility", "phase", "regime")
    plain = auto.compute_tile("base", r, beta, outputs)
    with_h = auto.compute_tile("base", r, beta, (*outputs, "harmonics"), settings={"harmonics": 3})
    exact = event.compute_tile("base", r, beta, (*outputs, "harmonics"), settings={"harmonics": 3})
    assert (plain["method_used"] == MethodUsed.THEORY).any()
    for name, values in plain.items():
        np.testing.assert_array_equal(values, with_h[name])
    for name in event.HARMONIC_VARIABLES:
        np.testing.assert_array_equal(with_h[name], exact[name])


def test_spec_refuses_a_swept_run():
    text = SPEC.format(effects="{}", outputs="harmonics", h=8) + "sweep: {direction: up}\n"
    with pytest.raises(SpecError) as info:
        parse_spec_text(text, "t.yaml")
    assert str(info.value).startswith("t.yaml:10:1: sweep:") and "does not store harmonics" in str(info.value)


JENKINS = [(kappa, r, beta) for kappa in (1.0, 10.0, 1000.0) for r, beta in ((0.5, 0.3), (2.0, 0.2), (0.3, 0.9))]


@pytest.mark.parametrize(("kappa", "r", "beta"), JENKINS)
def test_jenkins_contact(kappa, r, beta):
    """The Jenkins contact (its slider stuck: a linear oscillator of stiffness 1 + kappa, integrated in its own
    time): the first harmonic is its transmissibility, the friction force's work is friction_energy (with
    static = kinetic friction the contact spring's energy returns over the period), and so is the area of its
    sampled hysteresis loop, and the FFT of its sampled orbit agrees to aliasing."""
    effects = {"contact_stiffness": kappa}
    raw, X, F = solve("base", r, beta, effects)
    t = raw[steady.OUT_TRANSMISSIBILITY]
    assert abs(abs(X[1]) - t) <= 1e-14 * max(1.0, t)
    k = np.arange(H + 1)
    work = np.pi * np.sum(k * np.imag(F * np.conj(X)))
    energy = raw[steady.OUT_FRICTION_ENERGY]
    assert abs(work - energy) <= 1e-9 * max(energy, beta * t)  # f is continuous: F_k ~ k^-2, the tail ~ H^-4
    n = 1 << 14
    x, q, f = history("base", r, beta, effects, n=n)
    # the hysteresis loop of the contact spring's force, kappa (q - w): its area is the energy the slider
    # dissipates, and the force stays within the slider's band
    area = np.sum(0.5 * (f + np.roll(f, -1)) * (np.roll(q, -1) - q))
    assert abs(area - energy) <= 1e-6 * max(energy, beta * t)
    assert np.abs(f).max() <= beta * (1 + 1e-12)
    fft = np.fft.rfft(x) / n
    fft[1:] *= 2.0
    assert np.abs(fft[:H + 1] - X).max() <= 1e-9 * np.abs(X).max()


def test_a_stiff_jenkins_contact_has_the_rigid_harmonics():
    """kappa -> infinity recovers the rigid contact (docs/equations.md §6), harmonics and all, the difference
    falling like kappa^-1/2 (the stuck mass's swing on the contact spring, frequency sqrt(1 + kappa))."""
    _, X_rigid, F_rigid = solve("base", 0.5, 0.3, highest=9)
    gaps = []
    for kappa in (1e3, 1e5):
        _, X, F = solve("base", 0.5, 0.3, {"contact_stiffness": kappa}, highest=9)
        gaps.append((np.abs(X - X_rigid).max(), np.abs(F - F_rigid)[:4].max()))
    for coarse, fine in zip(*gaps, strict=True):
        assert fine < 2e-3 and coarse / fine == pytest.approx(10.0, rel=0.05)


def test_a_resumed_run_keeps_the_harmonics_bits(runner, tmp_path, monkeypatch):
    """The harmonics' planes travel through the checkpoint's tiles (a dim before the grid's) and come back the
    same bits, whichever tiles a run computed before it was interrupted."""
    from conftest import write_spec

    from friction_sweep.cli import main
    from friction_sweep.storage import cube

    spec = write_spec(tmp_path, text="scene: {excitation: base}\n"
                      "grid: {frequency_ratio: {start: 0.1, stop: 3.0, num: 100}, force_ratio: [0.1, 0.6]}\n"
                      "method: event\noutputs: [transmissibility, harmonics]\nsettings: {harmonics: 5}\n")
    ref, out = tmp_path / "ref.h5", tmp_path / "out.h5"
    assert runner.invoke(main, ["run", str(spec), "-o", str(ref)]).exit_code == 0
    real = event.compute_tile
    calls = []

    def interrupted(*a, **k):
        calls.append(1)
        if len(calls) > 1:
            raise KeyboardInterrupt
        return real(*a, **k)

    monkeypatch.setattr(event, "compute_tile", interrupted)
    assert runner.invoke(main, ["run", str(spec), "-o", str(out), "--executor", "serial"]).exit_code == 130
    monkeypatch.setattr(event, "compute_tile", real)
    res = runner.invoke(main, ["run", str(spec), "-o", str(out), "--resume", "--executor", "serial"])
    assert res.exit_code == 0, res.output
    a, b = cube.open_cube(ref), cube.open_cube(out)
    assert a.response_harmonic_real.dims == ("harmonic", "force_ratio", "frequency_ratio")
    for name in a.data_vars:
        np.testing.assert_array_equal(a[name].values, b[name].values)
    np.testing.assert_array_equal(b.harmonic.values, np.arange(6))
