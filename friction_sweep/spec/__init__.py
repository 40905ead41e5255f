"""The sweep spec: a YAML file naming the scene, the (r, beta) grid, the method and the outputs.

What each method accepts (excitations, effects, settings, outputs) is friction_sweep.catalogue's.
"""

from .errors import SpecError, SpecProblem
from .model import Spec
from .parse import load_spec, parse_spec_text

__all__ = ["Spec", "SpecError", "SpecProblem", "load_spec", "parse_spec_text"]
