"""`python -m pdsketch_mech.render PROBLEM [DOMAIN ...] --out scene.png`: a picture of a
problem's scene as the simulator builds it (optionally after letting it settle), the camera
framing its objects (`--yaw`, `--pitch`, `--distance` move it).

Exit 0 on success, 2 on bad input (one `FILE:LINE:COL: error:` line).
"""
from __future__ import annotations

import sys
from typing import Optional, Sequence

from ..lang.errors import PddlError
from ..lang.loader import load_domain, load_problem
from ..learning.paths import resolve_domain, resolve_problem
from ..world.build import build_world
from ..world.contacts import read_contacts
from ..world.render import render, save_png, scene_camera
from .common import (
    EXIT_BAD_INPUT, EXIT_OK, ArgumentParser, camera_options, camera_view, output_error, print_error, print_warning,
)


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = ArgumentParser(prog="python -m pdsketch_mech.render", description=__doc__.split("\n\n")[0])
    parser.add_argument("problem", metavar="PROBLEM", help="problem file with a :scene, or a shipped example's name")
    parser.add_argument("domains", nargs="*", metavar="DOMAIN", help="its domain: a file, `basis`, or a shipped mechanism's name (default: found beside the problem)")
    parser.add_argument("--out", default="scene.png", metavar="FILE.png", help="image to write (default scene.png)")
    parser.add_argument("--settle", action="store_true", help="simulate until objects come to rest first")
    camera_options(parser)
    args = parser.parse_args(argv)
    error = output_error(args.out, "--out", [args.problem, *args.domains], (".png",))
    if error is not None:
        print_error(error)
        return EXIT_BAD_INPUT
    try:
        args.problem = resolve_problem(args.problem)
        args.domains = [resolve_domain(d) for d in args.domains]
        domains = [load_domain([d], samplers_required=False) for d in args.domains]  # no checkpoint is loaded
        for warning in (w for d in domains for w in d.warnings):
            print_warning(warning)
        _, problem = load_problem(args.problem, domains, samplers_required=False)
        if problem.scene is None:
            raise PddlError(f"problem '{problem.name}' has no :scene to render", problem.loc)
        with build_world(problem) as world:
            if args.settle:
                world.settle()
            save_png(render(world, scene_camera(world, camera_view(args))), args.out)
            graph = read_contacts(world)
    except PddlError as error:
        print_error(error)
        return EXIT_BAD_INPUT
    facts = " ".join("(" + " ".join(f) + ")" for f in graph.facts())
    print(f"wrote {args.out}; contacts: {facts}", file=sys.stderr)
    return EXIT_OK
