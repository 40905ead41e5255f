"""friction_sweep: a 1-DoF mass-spring oscillator with Coulomb friction, swept over (r, beta).

Two ways to the same outputs: Den Hartog's closed-form theory (continuous motion only) and,
in later layers, numerical simulation with exact stick-slip.
"""

__version__ = "0.1.0"
