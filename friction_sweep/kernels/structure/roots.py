"""The first root of an event function on one step, none missed (DESIGN §7).

On a step of length h (|A| h <= 1/2) an event function g(t) = c . exp(A t) z is its Taylor polynomial
P(s) = sum_k d_k s^k / k!, d_k = c . A^k z, k <= KT, to rounding. On a piece [a, b] of width w the bound
B = sum_k |P^(k+2)(a)| w^k / k! holds |g''| there (P is a polynomial, the sum is its exact expansion).
A piece with g(a), g(b) > 0 holds no root where any of these holds:

- min(g(a), g(b)) > B w^2 / 8 (the chord lies within B w^2 / 8 of g: no root pair between samples);
- g(a) + g'(a) w - B w^2 / 2 > 0 with g(a) >= 0 (the concave lower bound from a stays positive; this
  is how a function that starts at zero and leaves, g'(a) > 0, is passed without re-arming on it);
- g(b) - g'(b) w - B w^2 / 2 > 0 (the same from b).

Pieces that pass none are halved, left first, so the first root is the one found; a sign change on a
piece where g' < 0 throughout (g'(a) + B w < 0) is one root, refined by Newton steps kept inside the
bracket (bisection where a step leaves it). A piece narrower than MIN_WIDTH x h that still passes
nothing is a touch without crossing (a grazing contact that does not switch).
"""

from __future__ import annotations

import numpy as np

from friction_sweep.kernels.jit import jit

MIN_WIDTH = 2.0**-40
_DEPTH = 64


#: 1 / (k + 1): Horner's rule below multiplies by s / (k + 1) formed off the dependency chain, so each
#: term costs a multiply-add on it, not a division
_INV = 1.0 / np.arange(1.0, 65.0)


@jit
def derivs(d, s, out):
    """out[j] = P^(j)(s) = sum_k d[j + k] s^k / k! for every j."""
    K = d.shape[0]
    q = np.empty(K)
    for k in range(K):
        q[k] = s * _INV[k]
    for j in range(K):
        acc = 0.0
        for k in range(K - 1 - j, -1, -1):
            acc = acc * q[k] + d[j + k]
        out[j] = acc


@jit
def value(d, s):
    """P(s) by Horner's rule."""
    K = d.shape[0]
    acc = 0.0
    for k in range(K - 1, -1, -1):
        acc = acc * (s * _INV[k]) + d[k]
    return acc


@jit
def slope(d, s):
    """P'(s) by Horner's rule."""
    K = d.shape[0]
    acc = 0.0
    for k in range(K - 2, -1, -1):
        acc = acc * (s * _INV[k]) + d[k + 1]
    return acc


@jit
def bound2(da, w):
    """max |P''| on [a, a + w] from the derivatives da at a."""
    K = da.shape[0]
    acc = 0.0
    c = 1.0
    for k in range(K - 2):
        acc += abs(da[k + 2]) * c
        c *= w / (k + 1)
    return acc


#: a derivative within this fraction of the size of its terms is zero to rounding
ZERO_RTOL = 1e-10


@jit
def at_start(d, dmag):
    """At a mode's start, where g is zero to rounding: whether g leaves zero upwards, judged by its first
    derivative that is not zero to rounding (dmag[k]: the size of the terms of d[k]); the derivatives
    below that one are set to exactly zero in d (they are rounding). True also where every derivative is
    zero to rounding (the function stays at zero: nothing crosses)."""
    for j in range(1, dmag.shape[0]):
        if abs(d[j]) > ZERO_RTOL * dmag[j]:
            if d[j] < 0.0:
                return False
            for k in range(j):
                d[k] = 0.0
            return True
    for k in range(dmag.shape[0]):
        d[k] = 0.0
    return True


@jit
def refine(d, lo, hi):
    """A root of P in (lo, hi] with P(lo) > 0 >= P(hi): safeguarded Newton (bisection where a step leaves
    the bracket); returns a right end (P <= 0) within rounding of the root."""
    x = hi
    for _ in range(200):
        p = value(d, x)
        if p == 0.0:
            # the root itself, where Newton lands more often than not: the bracket's other end may be far, and
            # a Newton step from it overshoots past x, which the halving then closed on, 50 steps
            return x
        if p > 0.0:
            lo = x
        else:
            hi = x
        tol = 4e-16 * max(hi, 1e-300)
        if hi - lo <= tol:
            return hi
        dp = slope(d, x)
        xn = 0.5 * (lo + hi)
        if dp != 0.0:
            xt = x - p / dp
            if lo < xt < hi:
                xn = xt
        if abs(xn - x) <= tol:
            # converged from one side: close the bracket on the other
            probe = lo + 2.0 * tol
            if probe < hi and value(d, probe) <= 0.0:
                return probe
            if hi - xn <= 4.0 * tol:
                return hi
            xn = 0.5 * (lo + hi)
        x = xn
    return hi


@jit
def leaves_zero(da, w):
    """Whether P, with derivatives da at a mode's start (those below its first that is not zero to rounding
    set to zero by at_start), stays positive on (0, w]: with d_j its first derivative not zero,
    P(t) >= t^j (d_j / j! - B t / (j + 1)!) there, B = sum_l |d_(j+1+l)| w^l / l! >= max |P^(j+1)| on the
    piece (Taylor's remainder; P is a polynomial, the sum its exact expansion). So it holds where
    d_j > 0 and (j + 1) d_j > B w. This passes a function that leaves zero tangentially (a break-away
    with static = kinetic friction: u'' = 0 there, the slip's g = sig u' leaving with its second
    derivative) on the piece at once, where the concave bound from g' alone holds nothing and the
    halving would go down to MIN_WIDTH."""
    K = da.shape[0]
    for j in range(K - 1):
        if da[j] != 0.0:
            if da[j] < 0.0:
                return False
            B = 0.0
            c = 1.0
            for k in range(K - 1 - j):
                B += abs(da[j + 1 + k]) * c
                c *= w / (k + 1)
            return (j + 1) * da[j] > B * w
    return False


@jit
def first_root(d, dmag, h, start):
    """The first s in [0, h] where P reaches zero from above, or -1.0. `start`: s = 0 is a mode's start,
    where a function at zero (to rounding: dmag as at_start) that leaves is not an event."""
    K = d.shape[0]
    da = np.empty(K)
    los = np.empty(_DEPTH)
    his = np.empty(_DEPTH)
    if start and abs(d[0]) <= ZERO_RTOL * dmag[0]:
        if not at_start(d, dmag):
            return 0.0
    elif d[0] <= 0.0:
        return 0.0
    wmin = MIN_WIDTH * h
    top = 0
    los[0] = 0.0
    his[0] = h
    while top >= 0:
        a = los[top]
        b = his[top]
        top -= 1
        w = b - a
        derivs(d, a, da)
        ga = da[0]
        if a == 0.0 and ga <= 0.0:
            ga = 0.0
        g1a = da[1]
        B = bound2(da, w)
        gb = value(d, b)
        if gb <= 0.0:
            if (g1a + B * w < 0.0 and ga > 0.0) or w <= wmin:
                if ga <= 0.0:
                    return a
                return refine(d, a, b)
        else:
            g1b = slope(d, b)
            if ga > 0.0 and min(ga, gb) > 0.125 * B * w * w:
                continue
            if a == 0.0 and start and leaves_zero(da, w):
                continue
            if (ga > 0.0 or g1a > 0.0 or (a == 0.0 and start)) and ga + g1a * w - 0.5 * B * w * w > 0.0:
                continue
            if gb - g1b * w - 0.5 * B * w * w > 0.0 and ga > 0.0:
                continue
            if w <= wmin or top + 2 >= _DEPTH:
                continue
        mid = a + 0.5 * w
        # right half below the left: the left is taken first
        top += 1
        los[top] = mid
        his[top] = b
        top += 1
        los[top] = a
        his[top] = mid
    return -1.0
