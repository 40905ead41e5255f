"""The structure engine's event root finder (kernels/structure/roots.first_root) at a mode's start, where the
event function leaves zero: against polynomials whose roots are known by construction.

A break-away with static = kinetic friction leaves the slip's g = sig u' at zero with g' = 0 (u'' = 0 there):
g leaves with its second derivative, or a higher one. The finder must pass such a start without an event,
and still find the first root after it, on the step or not at all.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from friction_sweep.kernels.structure.flow import KT
from friction_sweep.kernels.structure.roots import first_root


def _leaving(j: int, r: float, sign: float = 1.0) -> np.ndarray:
    """Taylor coefficients d_k (P(s) = sum_k d_k s^k / k!) of P(s) = sign s^j / j! (1 - s / r): zero at the start
    with its first j - 1 derivatives, its only other root at s = r."""
    d = np.zeros(KT + 1)
    d[j] = sign
    # -sign s^(j+1) / (j! r) = d_(j+1) s^(j+1) / (j+1)!
    d[j + 1] = -sign * (j + 1) / r
    return d


def _sizes(d: np.ndarray) -> np.ndarray:
    """The sizes of the terms of the first four derivatives (advance's dmag): here the coefficients themselves."""
    return np.abs(d[:4]).copy()


@pytest.mark.parametrize("j", [1, 2, 3])
@pytest.mark.parametrize("r", [0.013, 0.2, 0.61, 0.999])
def test_a_function_leaving_zero_is_passed_and_its_root_found(j, r):
    d = _leaving(j, r)
    s = first_root(d, _sizes(d), 1.0, True)
    assert s == pytest.approx(r, rel=1e-13)


@pytest.mark.parametrize("j", [1, 2, 3])
@pytest.mark.parametrize("r", [1.001, 1.5, 40.0])
def test_a_function_leaving_zero_with_its_root_past_the_step_has_none(j, r):
    d = _leaving(j, r)
    assert first_root(d, _sizes(d), 1.0, True) == -1.0


@pytest.mark.parametrize("j", [1, 2, 3])
def test_a_function_leaving_zero_downwards_is_an_event_at_once(j):
    d = _leaving(j, 0.5, sign=-1.0)
    assert first_root(d, _sizes(d), 1.0, True) == 0.0


@pytest.mark.parametrize("seed", range(12))
def test_a_tangential_start_against_numpy_roots(seed):
    """P(s) = s^2 / 2 q(s), q a random cubic with q(0) > 0: the first root of q in (0, h] (numpy's roots of the
    polynomial, real and simple), or none."""
    rng = np.random.default_rng(seed)
    q = np.array([1.0, *rng.normal(0.0, 3.0, 3)])  # q(s) = q0 + q1 s + q2 s^2 + q3 s^3
    d = np.zeros(KT + 1)
    for k, c in enumerate(q):
        d[k + 2] = c * math.factorial(k + 2) / 2.0  # s^2 / 2 c s^k = d_(k+2) s^(k+2) / (k+2)!
    h = 1.0
    roots = np.roots(q[::-1])
    real = np.sort([x.real for x in roots if abs(x.imag) <= 1e-12 * max(1.0, abs(x)) and 0.0 < x.real <= h])
    s = first_root(d, _sizes(d), h, True)
    if real.size == 0:
        assert s == -1.0
    else:
        assert s == pytest.approx(real[0], rel=1e-10)
