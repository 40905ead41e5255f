"""Write a coarse copy of a sweep spec, for `make figures-quick` (CI): the same scene, method,
outputs, time histories and range of r, on at most --num frequency ratios (default 100) and at most
--max-force-ratios force ratios (default 16; line figures keep their force ratios, only the regime
map's axis gets coarser); of a structure spec, at most --num frequencies and --max-force-ratios
friction scales. The copy is validated before it is written, and written atomically.

    python figures/quick_spec.py configs/fig07_base_transmissibility.yaml results/quick/fig07_base_transmissibility.yaml
"""

from __future__ import annotations

import argparse
import io
import os
import sys
from pathlib import Path

from ruamel.yaml import YAML
from ruamel.yaml.comments import CommentedMap

from friction_sweep.spec import SpecError, load_spec, parse_spec_text
from friction_sweep.spec.structure import StructureSpec


def _coarse_axis(values, limit: int):
    """A {start, stop, num} range over the same span with at most `limit` points, or None to keep."""
    if values.size <= limit:
        return None
    axis = CommentedMap(start=float(values.min()), stop=float(values.max()), num=int(limit))
    axis.fa.set_flow_style()
    return axis


def coarse_text(src: Path, dst: Path, num: int = 100, max_force_ratios: int = 16) -> str:
    spec = load_spec(src)  # validated: the values below are the spec's own grid
    yaml = YAML()  # round trip: comments and layout survive
    yaml.width = 4096
    data = yaml.load(spec.text)
    grid = data["grid"]
    # a structure's plane is (frequency, friction_scale): its friction scales take the force ratios' limit
    axes = (("frequency", spec.frequency, num), ("friction_scale", spec.friction_scale, max_force_ratios)) \
        if isinstance(spec, StructureSpec) else (("frequency_ratio", spec.frequency_ratio, num),
                                                 ("force_ratio", spec.force_ratio, max_force_ratios))
    for key, values, limit in axes:
        axis = _coarse_axis(values, limit)
        if axis is not None:
            grid[key] = axis
    data["output"] = str(dst.with_suffix(".nc"))
    buf = io.StringIO()
    buf.write(f"# coarse copy of {src} for `make figures-quick`, written by figures/quick_spec.py\n")
    yaml.dump(data, buf)
    text = buf.getvalue()
    parse_spec_text(text, source=str(dst))  # never write a spec fsweep would refuse
    return text


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("src", type=Path)
    parser.add_argument("dst", type=Path)
    parser.add_argument("--num", type=int, default=100, help="frequency ratios at most (default 100)")
    parser.add_argument("--max-force-ratios", type=int, default=16, help="force ratios at most (default 16)")
    args = parser.parse_args(argv)
    if args.num < 2 or args.max_force_ratios < 2:
        parser.error("--num and --max-force-ratios must be at least 2")
    try:
        text = coarse_text(args.src, args.dst, args.num, args.max_force_ratios)
    except SpecError as err:
        print(f"quick_spec: {err}", file=sys.stderr)
        return 2
    args.dst.parent.mkdir(parents=True, exist_ok=True)
    tmp = args.dst.with_name(f".{args.dst.name}.{os.getpid()}.tmp")
    tmp.write_text(text)
    os.replace(tmp, args.dst)
    return 0


if __name__ == "__main__":
    sys.exit(main())
