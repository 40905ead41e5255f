"""An integrator of friction structures for the tests that shares no code with the engine or the kernels: a
hybrid automaton, SciPy's DOP853 on each mode's equations in the original time and variables, the mode
changes as events.

    M x'' + C x' + K x = F cos(w t) + kb y + cb y' - sum_j w_j lambda_j,     y = Y cos(w t)
    u_j = w_j . x + g_j y   (the contact's relative coordinate; g_j = +-1 where an end is the base)

- rigid contact slipping in direction s: lambda_j = s mu_j; it stops where u_j' = 0;
- rigid contact stuck: u_j' = 0 held as a constraint. Its force comes, at every right-hand-side call, from
  the constrained accelerations: with f the other forces, the stuck set S solves
  (W_S M^-1 W_S^T) lambda_S = W_S M^-1 f + g_S y'' (so that u_S'' = 0); it breaks away where |lambda_j|
  reaches mu_s_j, slipping towards lambda_j;
- Jenkins contact (stiffness kt, slider at p_j): lambda_j = kt (u_j - p_j) while the slider sticks, until
  |lambda_j| reaches mu_s_j (then it slips that way, p_j jumping to u_j - s mu_j / kt); slipping,
  lambda_j = s mu_j, p_j' = u_j', until u_j' = 0 (the slider sticks).

The rule for the rigid contacts at rest after any event (written here, not taken from the engine): the
contacts at rest (stuck ones, slipping ones whose relative velocity is within VTOL of zero, the one that
just stopped) are assigned stuck / slipping +1 / slipping -1 by enumeration; an assignment is consistent
when every stuck force is within its static band and every released contact accelerates away in its
direction (s u'' > 0, with kinetic friction); among consistent ones the one with the most contacts stuck
wins (ties: the first in enumeration order). A contact whose break-away fired must slip.

Labels per contact, over the measured periods: a stop is a rigid stick of positive duration (> STICK_MIN of
a period) that begins within them; for a Jenkins contact, as docs/equations.md §7 defines it in one
degree of freedom with u_j for q: a stick of the slider during which u_j' returns to zero (held), a creep
(a slip from a held stick during which s u_j'' <= 0 throughout) not ending the hold. slips: Jenkins
break-aways. Regime: stuck (never slips), stick_slip (stops), continuous.

The steady state: march periods from rest, then Newton shooting on the period map with forward differences
(the state projected onto the mode at the section), accepted where the period map repeats the state; the
first harmonic of every mass by Gauss-Legendre quadrature of the dense output over the last period.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

RTOL, ATOL = 1e-11, 1e-15
#: a rigid stick shorter than this fraction of a period is a grazing touch, not a stop
STICK_MIN = 1e-10
#: relative velocity (of the structure's velocity scale) below which a slipping contact counts as at rest
VTOL = 1e-9
_GL_X, _GL_W = np.polynomial.legendre.leggauss(12)


def gauss_nodes(plo, phi, sol):
    """12-point Gauss-Legendre on each solver step of a dense piece (sol, a solve_ivp dense output) within
    [plo, phi]: (nodes, weights, the state at the nodes) per step."""
    ts = np.asarray(sol.ts)
    for s0, s1 in zip(ts[:-1], ts[1:], strict=True):
        s0, s1 = max(s0, plo), min(s1, phi)
        if s1 <= s0:
            continue
        tt = 0.5 * (s1 - s0) * _GL_X + 0.5 * (s0 + s1)
        yield tt, 0.5 * (s1 - s0) * _GL_W, sol(tt)


@dataclass
class Model:
    """The structure assembled from its description (any object with the fields of StructureDef)."""

    names: list
    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    kb: np.ndarray
    cb: np.ndarray
    F: np.ndarray
    Y: float
    W: np.ndarray
    g: np.ndarray
    mu: np.ndarray
    mus: np.ndarray
    kt: np.ndarray  # 0 for a rigid contact
    Kf: np.ndarray  # stiffness and damping over (x_1..x_n, y)
    Cf: np.ndarray
    dashpots: list = field(default_factory=list)  # (c, coefficient vector over (x, y)) for the viscous loss
    contact_names: list = field(default_factory=list)

    @property
    def n(self):
        return self.M.shape[0]

    @property
    def m(self):
        return self.W.shape[0]


def _coefficients(a, b, index, n):
    """The element's relative coordinate a - b as coefficients over (x_1..x_n, y)."""
    c = np.zeros(n + 1)
    for end, sign in ((a, 1.0), (b, -1.0)):
        if end == "ground":
            continue
        c[n if end == "base" else index[end]] += sign
    return c


def model(d, friction_scale=1.0):
    """Assemble M, C, K, the base coupling, the forcing and the contacts from a structure description."""
    names = list(d.masses)
    n = len(names)
    index = {name: i for i, name in enumerate(names)}
    M = np.diag([float(d.masses[k]) for k in names])
    Kf, Cf = np.zeros((n + 1, n + 1)), np.zeros((n + 1, n + 1))
    dashpots = []
    for a, b, k in d.springs:
        c = _coefficients(a, b, index, n)
        Kf += float(k) * np.outer(c, c)
    for a, b, k in d.dampers:
        c = _coefficients(a, b, index, n)
        Cf += float(k) * np.outer(c, c)
        dashpots.append((float(k), c))
    base = d.excitation == "base"
    F = np.zeros(n)
    if not base:
        for k, v in (d.forcing or {}).items():
            F[index[k]] = float(v)
    W, g, mu, mus, kt, cnames = [], [], [], [], [], []
    for c in d.contacts:
        co = _coefficients(c.between[0], c.between[1], index, n)
        W.append(co[:n])
        g.append(co[n])
        mu.append(float(c.friction) * friction_scale)
        mus.append(float(c.friction) * friction_scale * float(c.static_friction_ratio))
        kt.append(0.0 if c.stiffness is None else float(c.stiffness))
        cnames.append(c.name)
    return Model(names, M, Cf[:n, :n], Kf[:n, :n], -Kf[:n, n], -Cf[:n, n], F,
                 float(d.base_amplitude) if base else 0.0, np.array(W).reshape(-1, n), np.array(g), np.array(mu),
                 np.array(mus), np.array(kt), Kf, Cf, dashpots, cnames)


def _peaks(pieces, n):
    """max |x_i| over the pieces' dense output: at the pieces' ends and where the velocity v_i = x_i' is zero
    (bracketed on 16 samples of each solver step, then brentq)."""
    peak = np.zeros(n)
    for plo, phi, sol, _ in pieces:
        if phi <= plo:
            continue
        ts = np.clip(np.asarray(sol.ts), plo, phi)
        for s0, s1 in zip(ts[:-1], ts[1:], strict=True):
            if s1 <= s0:
                continue
            tt = np.linspace(s0, s1, 17)
            S = sol(tt)
            peak = np.maximum(peak, np.abs(S[:n]).max(axis=1))
            for i in range(n):
                v = S[n + i]
                for q in np.flatnonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0):
                    tq = brentq(lambda t, i=i, sol=sol: sol(t)[n + i], tt[q], tt[q + 1], xtol=1e-15, rtol=1e-15)
                    peak[i] = max(peak[i], abs(sol(tq)[i]))
    return peak


class Automaton:
    """The hybrid automaton of a model at one angular frequency w."""

    def __init__(self, mdl: Model, w: float):
        self.md, self.w = mdl, float(w)
        self.T = 2 * np.pi / self.w
        self.minv = 1.0 / np.diag(mdl.M)
        self.rigid = mdl.kt == 0.0
        self.vscale = 1.0
        self._cache = {}
        self.periods = 0  # periods integrated (a cost count)
        # steps no longer than 1/64 of the forcing period or of the fastest linear mode (contacts free or
        # Jenkins sliders stuck), so that no event function crosses its level and returns between two steps
        Kt = mdl.K + (mdl.W.T * mdl.kt) @ mdl.W
        top = float(np.sqrt(max(np.max(np.linalg.eigvals(Kt * self.minv[:, None]).real), 0.0)))
        self.max_step = min(self.T, 2 * np.pi / top if top > 0 else np.inf) / 64

    # ---- forces -------------------------------------------------------------------------------------------
    def base(self, t):
        c, s = np.cos(self.w * t), np.sin(self.w * t)
        Y = self.md.Y
        return Y * c, -Y * self.w * s, -Y * self.w ** 2 * c

    def _mode(self, modes):
        """A mode's constant data: the forces f = F cos wt + kb y + cb y' - K x - C v + P p + f0 (the slipping
        contacts' constant forces in f0, the stuck sliders' springs in K, kb and P), and the acceleration
        a = Q f - q y'' with the stuck rigid contacts' constraint forces eliminated."""
        key = tuple(int(s) for s in modes)
        c = self._cache.get(key)
        if c is None:
            md = self.md
            mo = np.array(key)
            S = self.rigid & (mo == 0)
            J = (~self.rigid) & (mo == 0)
            slip = mo != 0
            WJk = md.W[J].T * md.kt[J]
            c = {"S": S, "J": J, "K": md.K + WJk @ md.W[J], "kb": md.kb - WJk @ md.g[J], "P": WJk,
                 "f0": -md.W[slip].T @ (mo[slip] * md.mu[slip]), "Q": np.diag(self.minv), "q": np.zeros(md.n),
                 "lam0": np.where(slip, mo * md.mu, 0.0)}
            if S.any():
                WS = md.W[S]
                R = WS * self.minv  # W_S M^-1
                Ginv = np.linalg.inv(R @ WS.T)
                c["Q"] = np.diag(self.minv) - R.T @ Ginv @ R
                c["q"] = R.T @ Ginv @ md.g[S]
                c["R"], c["Ginv"] = R, Ginv
            self._cache[key] = c
        return c

    def accel(self, t, x, v, p, c):
        md = self.md
        cw, sw = np.cos(self.w * t), np.sin(self.w * t)
        y, yd, ydd = md.Y * cw, -md.Y * self.w * sw, -md.Y * self.w ** 2 * cw
        f = md.F * cw + c["kb"] * y + md.cb * yd - c["K"] @ x - md.C @ v + c["P"] @ p[c["J"]] + c["f0"]
        return c["Q"] @ f - c["q"] * ydd, f

    def forces(self, t, x, v, p, modes):
        """(acceleration, lambda, u, u') of the state in a mode."""
        md = self.md
        c = self._mode(modes)
        a, f = self.accel(t, x, v, p, c)
        y, yd, ydd = self.base(t)
        u = md.W @ x + md.g * y
        ud = md.W @ v + md.g * yd
        lam = c["lam0"].copy()
        J, S = c["J"], c["S"]
        lam[J] = md.kt[J] * (u[J] - p[J])
        if S.any():
            lam[S] = c["Ginv"] @ (c["R"] @ f + md.g[S] * ydd)
        return a, lam, u, ud

    def udd(self, t, x, v, p, modes):
        """u'' of every contact."""
        a = self.forces(t, x, v, p, modes)[0]
        return self.md.W @ a + self.md.g * self.base(t)[2]

    def project(self, t, x, v, p, modes, hold=None):
        """The state on the mode's manifold: stuck rigid contacts at zero relative velocity (an impulse
        through their directions) and, given hold (u_j of every contact, used where stuck), back where they
        stuck (the integration's drift along a constraint removed); slipping sliders at their edge."""
        md = self.md
        S = self.rigid & (modes == 0)
        v = v.copy()
        if S.any():
            y, yd, _ = self.base(t)
            WS = md.W[S]
            G = (WS * self.minv) @ WS.T
            v -= self.minv * (WS.T @ np.linalg.solve(G, WS @ v + md.g[S] * yd))
            if hold is not None:
                x = x - self.minv * (WS.T @ np.linalg.solve(G, WS @ x + md.g[S] * y - hold[S]))
        p = p.copy()
        js = (~self.rigid) & (modes != 0)
        u = md.W @ x + md.g * self.base(t)[0]
        p[js] = u[js] - modes[js] * md.mu[js] / md.kt[js]
        return x, v, p

    # ---- the rule at rest ------------------------------------------------------------------------------------
    def decide(self, t, x, v, p, modes, forced=None):
        """New modes of the rigid contacts at rest (see the module's docstring); forced: (j, s) a break-away."""
        md = self.md
        ud = md.W @ v + md.g * self.base(t)[1]
        rest = [j for j in range(md.m) if self.rigid[j] and (modes[j] == 0 or abs(ud[j]) <= VTOL * self.vscale
                                                             or (forced and forced[0] == j))]
        if not rest:
            return modes, v
        best = None
        edge = {}
        if forced:
            # a break-away releases every stuck contact whose force is at its band's edge at that instant (two
            # of a symmetric structure together), towards its force, whatever its acceleration (zero at first)
            edge[forced[0]] = forced[1]
            lam = self.forces(t, x, v, p, modes)[1]
            for j in rest:
                if modes[j] == 0 and abs(lam[j]) >= md.mus[j] * (1 - 1e-9):
                    edge[j] = int(np.sign(lam[j]))
        options = [(edge[j],) if j in edge else (0, 1, -1) for j in rest]
        for combo in itertools.product(*options):
            trial = modes.copy()
            for j, s in zip(rest, combo, strict=True):
                trial[j] = s
            # the released ones start from rest: zero their relative velocity with the stuck ones'
            rest_modes = trial.copy()
            rest_modes[rest] = 0
            _, v0, _ = self.project(t, x, v, p, rest_modes)
            a, lam, _, _ = self.forces(t, x, v0, p, trial)
            udd = md.W @ a + md.g * self.base(t)[2]
            ok = True
            for j, s in zip(rest, combo, strict=True):
                if s == 0:
                    ok &= abs(lam[j]) <= md.mus[j] * (1 + 1e-12)
                elif j in edge:
                    pass  # the force reached the band: it leaves it (the acceleration may start at zero)
                else:
                    ok &= s * udd[j] > 0
            if ok and (best is None or sum(s == 0 for s in combo) > best[0]):
                best = (sum(s == 0 for s in combo), trial, v0)
        if best is None:
            raise AssertionError(f"no consistent stick/slip assignment at t={t}")
        return best[1], best[2]

    # ---- integration of one window ------------------------------------------------------------------------
    def run(self, t0, z, modes, t1, log=None):
        """Integrate from (t0, z, modes) to t1; log: a dict collecting pieces and labels (see measure)."""
        md = self.md
        n, m = md.n, md.m
        t = t0
        modes = modes.copy()
        x, v, p = z[:n], z[n:2 * n], z[2 * n:]
        x, v, p = self.project(t, x, v, p, modes)
        hold = md.W @ x + md.g * self.base(t)[0]  # where each rigid contact sticks (kept where stuck)
        skip = set()
        while t < t1 - 1e-13 * self.T:
            mo = modes.copy()

            cm = self._mode(mo)
            slider = np.flatnonzero((~self.rigid) & (mo != 0))

            def rhs(tt, s, cm=cm, slider=slider):
                out = np.empty_like(s)
                out[:n] = s[n:2 * n]
                out[n:2 * n] = self.accel(tt, s[:n], s[n:2 * n], s[2 * n:], cm)[0]
                out[2 * n:] = 0.0
                if slider.size:
                    out[2 * n + slider] = md.W[slider] @ s[n:2 * n] + md.g[slider] * self.base(tt)[1]
                return out

            if log is not None:
                udd0 = self.udd(t, x, v, p, mo)
                for j in range(m):
                    if not self.rigid[j] and mo[j] != 0 and log["anchor"][j] and mo[j] * udd0[j] > 0:
                        log["anchor"][j] = False  # the load drives the slip from its start: no creep
            events, kinds = [], []
            for j in range(m):
                if mo[j] != 0:
                    if (j, 0) in skip:
                        continue

                    def ev(tt, s, j=j):
                        return md.W[j] @ s[n:2 * n] + md.g[j] * self.base(tt)[1]
                    ev.terminal, ev.direction = True, -mo[j]
                    events.append(ev)
                    kinds.append(("stop", j, 0))
                else:
                    for e in (1, -1):
                        if (j, e) in skip:
                            continue

                        def ev(tt, s, j=j, e=e, mo=mo):
                            lam = self.forces(tt, s[:n], s[n:2 * n], s[2 * n:], mo)[1]
                            return e * lam[j] - md.mus[j]
                        ev.terminal, ev.direction = True, 1
                        events.append(ev)
                        kinds.append(("break", j, e))
                    if not self.rigid[j] and log is not None and log["state"][j] == 0:
                        def ev(tt, s, j=j):  # the mass's return to zero within the stick: a stop
                            return md.W[j] @ s[n:2 * n] + md.g[j] * self.base(tt)[1]
                        ud0 = md.W[j] @ v + md.g[j] * self.base(t)[1]
                        a0 = self.udd(t, x, v, p, mo)[j]
                        # the return to zero, not the zero it starts from (a stick begun at a stop)
                        ev.terminal = True
                        ev.direction = -np.sign(ud0 if abs(ud0) > VTOL * self.vscale else a0)
                        events.append(ev)
                        kinds.append(("turn", j, 0))
            for j in range(m):
                if log is not None and not self.rigid[j] and mo[j] != 0 and log["anchor"][j]:
                    def ev(tt, s, j=j, sj=mo[j], mo=mo):  # the load driving the slip: not a creep
                        return sj * self.udd(tt, s[:n], s[n:2 * n], s[2 * n:], mo)[j]
                    ev.terminal, ev.direction = True, 1
                    events.append(ev)
                    kinds.append(("driven", j, 0))
            t_end = t1
            if skip:
                t_end = min(t1, t + 1e-7 * self.T)
            sol = solve_ivp(rhs, (t, t_end), np.concatenate([x, v, p]), method="DOP853", events=events, rtol=RTOL,
                            atol=ATOL * self.vscale, dense_output=True, first_step=1e-10 * self.T,
                            max_step=self.max_step)
            tn = sol.t[-1]
            if log is not None:
                log["pieces"].append((t, tn, sol.sol, mo))
                self._account(log, t, tn, mo)
            s = sol.y[:, -1]
            x, v, p = s[:n].copy(), s[n:2 * n].copy(), s[2 * n:].copy()
            t = tn
            x, v, p = self.project(t, x, v, p, mo, hold)
            self.vscale = max(self.vscale, float(np.max(np.abs(v))))
            skip = set()
            if sol.status != 1:
                continue
            k = next(i for i, te in enumerate(sol.t_events) if te.size)
            kind, j, e = kinds[k]
            if kind == "driven":
                log["anchor"][j] = False
                continue
            if kind == "turn":
                if tn - sol.t[0] <= 1e-12 * self.T:
                    continue  # the zero the stick began from, seen again through rounding
                log["state"][j] = 2  # held
                log["stops"][j] += log["window"](t)
                if log["window"](t):
                    log["times"][j].append(t)
                continue
            if kind == "stop" and not self.rigid[j]:
                modes[j] = 0
                if log is not None:
                    log["state"][j] = 2 if log["anchor"][j] else 0
                    log["anchor"][j] = False
                v = v.copy()
                x, v, p = self.project(t, x, v, p, modes)
            elif kind == "break" and not self.rigid[j]:
                u = md.W[j] @ x + md.g[j] * self.base(t)[0]
                if log is not None:
                    log["slips"][j] += log["window"](t)
                    log["anchor"][j] = log["state"][j] == 2
                    log["jump"][j] += log["window"](t) * 0.5 * (md.mus[j] ** 2 - md.mu[j] ** 2) / md.kt[j]
                modes[j] = e
                p[j] = u - e * md.mu[j] / md.kt[j]
            old = modes.copy()
            modes, v = self.decide(t, x, v, p, modes, forced=(j, e) if kind == "break" and self.rigid[j] else None)
            x, v, p = self.project(t, x, v, p, modes)
            u = md.W @ x + md.g * self.base(t)[0]
            hold = np.where(self.rigid & (old != 0) & (modes == 0), u, hold)
            if log is not None:
                for i in range(m):
                    if self.rigid[i] and old[i] == 0 and modes[i] != 0:
                        self._unstick(log, i, t)
                    if self.rigid[i] and old[i] != 0 and modes[i] == 0:
                        log["since"][i] = t
            ud = md.W @ v + md.g * self.base(t)[1]
            for i in range(m):
                if self.rigid[i] and modes[i] != 0 and abs(ud[i]) <= VTOL * self.vscale:
                    # released from rest, maybe tangentially (the force just reached the band): its velocity
                    # is rounding at first, so its stop event waits a moment
                    skip.add((i, 0))
            if kind == "stop" and not self.rigid[j]:
                # the slider just stuck on the edge it slipped against: the first moments without that event
                lam = self.forces(t, x, v, p, modes)[1]
                if abs(abs(lam[j]) - md.mus[j]) <= 1e-9 * md.mus[j]:
                    skip.add((j, int(np.sign(lam[j]))))
        return t, np.concatenate([x, v, p]), modes

    def _account(self, log, lo, hi, mo):
        a, b = max(lo, log["lo"]), min(hi, log["hi"])
        if b > a:
            for j in range(self.md.m):
                if mo[j] == 0 and (self.rigid[j] or log["state"][j] == 2):
                    log["stuck"][j] += b - a

    def _unstick(self, log, i, t):
        start = log["since"][i]
        if start is not None and t - start > STICK_MIN * self.T:
            log["stops"][i] += log["window"](start)
            if log["window"](start):
                log["times"][i].append(start)
        log["since"][i] = None

    # ---- periods, steady state, measurement ----------------------------------------------------------------
    def rest_start(self):
        """From rest at t = 0 (v = 0): every contact unstretched (u = 0) and, in the directions the contacts
        leave free, the springs at their least energy under the base's y(0) (the least-norm such x); each
        Jenkins slider loaded with the force its contact would carry as a rigid link, every contact with
        friction held so (u'' = 0 for all of them: (W M^-1 W^T) lambda = W M^-1 f + g y'', least-norm where the
        links are dependent), within its static band (1e-12 inside: a start on the edge is a tie), beyond it
        slipping at once; the rigid contacts decided."""
        md = self.md
        n, m = md.n, md.m
        y, _, ydd = self.base(0.0)
        kkt = np.block([[md.K, md.W.T], [md.W, np.zeros((m, m))]])
        x = np.linalg.lstsq(kkt, np.concatenate([md.kb * y, -md.g * y]), rcond=None)[0][:n]
        v = np.zeros(n)
        u = md.W @ x + md.g * y
        held = md.mu > 0.0
        WH = md.W[held]
        f = md.F + md.kb * y - md.K @ x
        lam = np.zeros(m)
        if held.any():
            lam[held] = np.linalg.lstsq((WH * self.minv) @ WH.T, (WH * self.minv) @ f + md.g[held] * ydd,
                                        rcond=None)[0]
        load = np.clip(lam, -md.mus * (1.0 - 1e-12), md.mus * (1.0 - 1e-12))
        p = np.where(self.rigid, u, u - load / np.where(self.rigid, 1.0, md.kt))
        modes = np.zeros(m, dtype=int)
        for j in range(m):
            if not self.rigid[j] and held[j] and abs(lam[j]) > md.mus[j]:
                modes[j] = int(np.sign(lam[j]))
        modes, v = self.decide(0.0, x, v, p, modes)
        x, v, p = self.project(0.0, x, v, p, modes)
        return np.concatenate([x, v, p]), modes

    def period_map(self, z, modes, k=1):
        self.periods += k
        t, z1, m1 = self.run(0.0, z, modes, k * self.T)
        return z1, m1

    def scale(self, z):
        n = self.md.n
        return max(1e-300, float(np.max(np.abs(z[:n]))), float(np.max(np.abs(z[n:2 * n]))) / self.w)

    def steady(self, march=80, kmax=4, tol=1e-12, z=None, modes=None):
        """The steady orbit's section state, modes and period k: march from rest (or z, modes) until the
        state repeats k <= kmax periods back; from the 5th period on, Newton shooting (k = 1) from any state
        whose section modes repeated, every 8th period."""
        if z is None:
            z, modes = self.rest_start()
        hist = [(z, modes)]
        for i in range(march):
            z, modes = self.period_map(z, modes)
            hist.append((z, modes))
            for k in range(1, min(kmax, i) + 1):
                zh, mh = hist[-1 - k]
                if np.array_equal(mh, modes) and np.max(np.abs(z - zh)) <= tol * self.scale(z):
                    return z, modes, k
            if i >= 4 and i % 8 == 4 and np.array_equal(modes, hist[-2][1]):
                found = self.shoot(z, modes, tol)
                if found is not None:
                    return found[0], found[1], 1
        raise AssertionError("no steady state")

    def jacobian(self, z, modes, h, central=False):
        d = z.size
        J = np.empty((d, d))
        f0 = None if central else self.period_map(z, modes)[0]
        for i in range(d):
            dz = np.zeros(d)
            dz[i] = h
            fp = self.period_map(z + dz, modes)[0]
            if central:
                J[:, i] = (fp - self.period_map(z - dz, modes)[0]) / (2 * h)
            else:
                J[:, i] = (fp - f0) / h
        return J

    def shoot(self, z, modes, tol, jacobians=3, iters=10):
        """Newton (chord) shooting for a fixed point of the period map with the section modes given: the
        Jacobian by forward differences, reused while the residual shrinks fast."""
        n = self.md.n
        for _ in range(jacobians):
            J = self.jacobian(z, modes, 1e-7 * self.scale(z))
            # neutral directions (a continuum of orbits: a mass held by a slipping contact only, stuck positions)
            # are left alone rather than followed by a huge step
            lu = np.linalg.pinv(J - np.eye(z.size), rcond=1e-8)
            last = np.inf
            for _ in range(iters):
                z1, m1 = self.period_map(z, modes)
                if not np.array_equal(m1, modes):
                    return None
                r = z1 - z
                size = np.max(np.abs(r))
                if size <= tol * self.scale(z):
                    return z, modes
                if size > 0.3 * last:
                    break
                last = size
                z = z - lu @ r
                x, v, p = self.project(0.0, z[:n], z[n:2 * n], z[2 * n:], modes)
                z = np.concatenate([x, v, p])
        return None

    def measure(self, z, modes, k=1):
        """Labels and first harmonics over k periods of the orbit through (z, modes) at t = 0."""
        md = self.md
        n, m = md.n, md.m
        lo, hi = 0.0, k * self.T
        # one period before the window sets the Jenkins hold labels and the rigid sticks in progress
        log = {"pieces": [], "lo": lo, "hi": hi, "stuck": np.zeros(m), "stops": np.zeros(m), "slips": np.zeros(m),
               "jump": np.zeros(m), "since": [None] * m, "state": np.zeros(m, dtype=int),
               "anchor": np.zeros(m, dtype=bool), "window": lambda t: 0, "times": [[] for _ in range(m)]}
        for j in range(m):
            if modes[j] == 0:
                log["since"][j] = -np.inf if self.rigid[j] else None
        t, zp, mp = self.run(-k * self.T, z, modes, 0.0, log)  # the orbit's previous k periods, not measured
        log.update({"pieces": [], "window": lambda t: 1 if lo <= t < hi else 0, "times": [[] for _ in range(m)]})
        log["stops"][:] = log["slips"][:] = log["jump"][:] = log["stuck"][:] = 0
        for j in range(m):
            if self.rigid[j] and mp[j] == 0 and log["since"][j] is not None and log["since"][j] < lo:
                log["since"][j] = -np.inf  # a stick in progress, begun before the window: not this window's
        t, z1, m1 = self.run(0.0, zp, mp, hi, log)
        for j in range(m):
            if self.rigid[j] and m1[j] == 0:
                self._unstick(log, j, hi)
        # first harmonic, forcing work, viscous and friction losses by Gauss-Legendre on every solver step
        a, b = np.zeros(n), np.zeros(n)
        work = viscous = 0.0
        fric = np.zeros(m)
        slide = np.zeros(m)  # the distance each slipping contact slides (u is monotone within a slip piece)
        for plo, phi, sol, mo in log["pieces"]:
            if phi > plo:
                du = md.W @ (sol(phi)[:n] - sol(plo)[:n]) + md.g * (self.base(phi)[0] - self.base(plo)[0])
                slide += np.where(mo != 0, np.abs(du), 0.0)
            for tt, wq, S in gauss_nodes(plo, phi, sol):
                X, V, P = S[:n], S[n:2 * n], S[2 * n:]
                y = md.Y * np.cos(self.w * tt)
                yd = -md.Y * self.w * np.sin(self.w * tt)
                a += (X * np.cos(self.w * tt)) @ wq
                b += (X * np.sin(self.w * tt)) @ wq
                for c, co in md.dashpots:
                    rel = co[:n] @ V + co[n] * yd
                    viscous += c * (rel ** 2) @ wq
                lam = np.array([self.forces(ti, X[:, q], V[:, q], P[:, q], mo)[1] for q, ti in enumerate(tt)]).T
                ud = md.W @ V + md.g[:, None] * yd
                fric += (lam * ud) @ wq
                # the power the excitation delivers: the applied force on the masses, the base through every
                # element attached to it (spring k (y - x), dashpot c (y' - x'), contact g lambda)
                pw = (md.F[:, None] * np.cos(self.w * tt) * V).sum(0)
                if md.Y:
                    pw = pw - self._base_force(X, V, y, yd, lam) * yd
                work += pw @ wq
        amplitude = 2 / hi * np.hypot(a, b)
        peak = _peaks(log["pieces"], n)
        if md.Y:
            amplitude = amplitude / md.Y
            peak = peak / md.Y
        lag = (np.degrees(np.arctan2(b, a)) + 90.0) % 360.0 - 90.0
        stops = log["stops"] / k
        slips = np.where(self.rigid, np.nan, log["slips"] / k)
        moved = np.array([any(plo < phi and mo[j] != 0 for plo, phi, _, mo in log["pieces"]) for j in range(m)])
        regime = np.where(~moved, 0, np.where(stops > 0, 1, 2))
        return {"amplitude": amplitude, "peak_amplitude": peak, "phase": lag, "stops_per_period": stops,
                "slips_per_period": slips, "stuck_fraction": log["stuck"] / hi, "regime": regime,
                "friction_energy": fric / k,
                "work": work / k, "viscous": viscous / k, "slide": slide / k, "stop_times": log["times"],
                "orbit_period": k, "end": (z1, m1), "pieces": log["pieces"]}

    def _base_force(self, X, V, y, yd, lam):
        """Q_y, the elements' generalized force on the base coordinate y: springs -dE/dy, dashpots, contacts
        (-g lambda); the base puts in the power -Q_y y'."""
        md, n = self.md, self.md.n
        return -(md.Kf[n, :n] @ X + md.Kf[n, n] * y) - (md.Cf[n, :n] @ V + md.Cf[n, n] * yd) - md.g @ lam
