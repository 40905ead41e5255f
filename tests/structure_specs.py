"""The issue's 2-mass structure spec (issue 30): a blade (1) and an under-platform damper (0.1), springs
ground-blade 1 and blade-damper 2, a dashpot ground-blade 0.004, a rigid contact damper-ground (platform)
and a Jenkins one (k_t 20) blade-base (root), the force on the blade. One source for the tests that write it
(test_hostile's rows, test_structure_commands' cubes), which vary the grid, the outputs and the root's
static friction around it."""

from __future__ import annotations


def two_mass(num: int, friction_scale: str, outputs: str, static_friction_ratio: float | None = None,
             output: str | None = None) -> str:
    """The spec's text: `num` frequencies over [0.2, 3.0], friction_scale and outputs as YAML flow lists."""
    static = "" if static_friction_ratio is None else f", static_friction_ratio: {static_friction_ratio}"
    tail = "" if output is None else f"output: {output}\n"
    return f"""\
scene: {{excitation: force}}
structure:
  masses: {{blade: 1.0, damper: 0.1}}
  springs: [[ground, blade, 1.0], [blade, damper, 2.0]]
  dampers: [[ground, blade, 0.004]]
  contacts:
    - {{name: platform, between: [damper, ground], friction: 0.3}}
    - {{name: root, between: [blade, base], friction: 0.2, stiffness: 20{static}}}
  forcing: {{blade: 1.0}}
grid:
  frequency: {{start: 0.2, stop: 3.0, num: {num}}}
  friction_scale: {friction_scale}
method: event
outputs: {outputs}
{tail}"""
