"""The sweep spec: a YAML file naming the scene, the (r, beta) grid, the method and the outputs."""

from .errors import SpecError, SpecProblem
from .model import EFFECTS, EXCITATIONS, METHOD_EFFECTS, METHOD_SETTINGS, METHODS_AVAILABLE, OUTPUTS, Spec
from .parse import load_spec, parse_spec_text

__all__ = [
    "EFFECTS",
    "METHOD_EFFECTS",
    "METHOD_SETTINGS",
    "EXCITATIONS",
    "METHODS_AVAILABLE",
    "OUTPUTS",
    "Spec",
    "SpecError",
    "SpecProblem",
    "load_spec",
    "parse_spec_text",
]
