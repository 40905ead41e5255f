"""friction_sweep: a 1-DoF mass-spring oscillator with Coulomb friction, swept over (r, beta).

Two ways to the same outputs: Den Hartog's closed-form theory (continuous motion only) and numerical
simulation with exact stick-slip (every regime). Layers, each importing only those before it:
catalogue, codes, ties, exits (what methods can do; stored codes; tie tolerances; exit codes) · spec · theory · kernels
(numba) · storage (schema, cubes, atomic writes) · methods · bench, quicklook (fsweep plot's drawings) · sweep
(tiles, executors, checkpoint; `sweep.pipeline.run_spec(spec) -> Dataset` is the Python API) · cli.
"""

__version__ = "0.1.0"
