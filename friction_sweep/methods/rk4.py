"""method: rk4 -- the same steady-state search and measurements as `event`, but each forcing period
is integrated by classical fixed-step Runge-Kutta (`steps_per_period`) with a real stick mode
(kernels/rk4.py). Fourth order in the step; a baseline that shows what the closed forms buy. With the
effect contact_stiffness the Jenkins contact's periods are integrated the same way (kernels/jenkins_rk4.py,
sticks sub-stepped ceil(sqrt(1 + kappa)) times), driven by event's Jenkins path.
"""

from __future__ import annotations

from friction_sweep import catalogue
from friction_sweep.kernels.settings import KERNEL_RK4
from friction_sweep.methods import event

CATALOGUE = catalogue.method("rk4")

variables_for = event.variables_for


def compute_tile(excitation: str, r, beta, outputs, effects=None, settings=None):
    settings = {**(settings or {}), "kernel": KERNEL_RK4}
    return event.compute_tile(excitation, r, beta, outputs, effects, settings)


def compute_sweep_tile(excitation: str, r, beta, outputs, effects=None, settings=None, direction: str = "up"):
    settings = {**(settings or {}), "kernel": KERNEL_RK4}
    return event.compute_sweep_tile(excitation, r, beta, outputs, effects, settings, direction)
