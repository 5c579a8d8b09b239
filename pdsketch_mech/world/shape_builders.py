"""The parts of the procedural category models (`shapes.py` holds the catalogue): convex
primitives, and one builder per category that returns an object's list of convex parts.

PyBullet collides a dynamic mesh as its convex hull, so a concave object (an L-hook, a
ladle's cup, a fork's tines) keeps its concavity only as a compound of convex parts: each
part becomes its own `<collision>` element. All sizes are in metres.

Design frame of a model (before `urdf.py` moves the link frame to the centre of mass):
z up, the object in its natural resting pose with its lowest point at z = 0, the long axis
along +x. Furniture keeps its design frame as the link frame: the table's top surface is
at z = 0 (legs below), slopes and tunnels stand on z = 0, centred in x and y; a ledge stands
on z = 0 with the centre of the plate it cradles at the origin.
"""
from __future__ import annotations

import math
from typing import List, Sequence, Tuple

import numpy as np
import trimesh
from trimesh import creation

Vec = Sequence[float]
Parts = List[trimesh.Trimesh]

# ----------------------------------------------------------------------------- primitives
def box(size: Vec, center: Vec = (0.0, 0.0, 0.0)) -> trimesh.Trimesh:
    """An axis-aligned box."""
    return creation.box(extents=size, transform=trimesh.transformations.translation_matrix(center))


def floor_box(size: Vec, x: float = 0.0, y: float = 0.0, z0: float = 0.0) -> trimesh.Trimesh:
    """An axis-aligned box whose bottom face is at height `z0`."""
    return box(size, (x, y, z0 + size[2] / 2.0))


def hull(points: Sequence[Vec]) -> trimesh.Trimesh:
    """The convex hull of a point set."""
    return trimesh.convex.convex_hull(np.asarray(points, dtype=float))


def ellipsoid(radii: Vec, center: Vec) -> trimesh.Trimesh:
    """A low-poly ellipsoid (icosphere, 2 subdivisions, scaled)."""
    sphere = creation.icosphere(subdivisions=2)
    return trimesh.Trimesh(sphere.vertices * np.asarray(radii) + np.asarray(center), sphere.faces)


def capsule(p0: Vec, p1: Vec, radius: float) -> trimesh.Trimesh:
    """A capsule as the hull of two low-poly spheres (exactly convex, few vertices)."""
    ball = creation.icosphere(subdivisions=1, radius=radius).vertices
    return hull(np.vstack([ball + np.asarray(p0), ball + np.asarray(p1)]))


def _ellipse(n: int, a: float, b: float, cx: float = 0.0) -> np.ndarray:
    """n points on an ellipse (semi-axes a along x, b along y) around (cx, 0)."""
    t = np.arange(n) * (2.0 * math.pi / n)
    return np.stack([cx + a * np.cos(t), b * np.sin(t)], axis=1)


def prism(n: int, a: float, b: float, z0: float, z1: float, cx: float = 0.0) -> trimesh.Trimesh:
    """An n-gon (elliptic) prism between heights z0 and z1 — a disc or a cup's bottom."""
    xy = _ellipse(n, a, b, cx)
    return hull([(x, y, z) for x, y in xy for z in (z0, z1)])


def cup_wall(n: int, bottom: Tuple[float, float], top: Tuple[float, float], thickness: float,
             z0: float, z1: float, cx: float = 0.0) -> Parts:
    """The side wall of an (elliptic, possibly flared) cup as n convex segments.

    One hull for the whole wall would fill the cup, so each segment between two adjacent
    polygon corners is its own hull of 8 points (inner/outer x bottom/top).
    """
    t = thickness
    outer0, outer1 = _ellipse(n, *bottom, cx), _ellipse(n, *top, cx)
    inner0 = _ellipse(n, bottom[0] - t, bottom[1] - t, cx)
    inner1 = _ellipse(n, top[0] - t, top[1] - t, cx)
    segments = []
    for i in range(n):
        j = (i + 1) % n
        pts = [(*ring[k], z) for ring, z in ((outer0, z0), (inner0, z0), (outer1, z1), (inner1, z1))
               for k in (i, j)]
        segments.append(hull(pts))
    return segments


# ----------------------------------------------------------------------------- categories
def block(size: Vec) -> Parts:
    return [floor_box(size)]


def calculator(length: float, width: float, front: float, back: float) -> Parts:
    # A wedge (thicker at the back, like a desk calculator) is still one convex hull.
    return [hull([(x, y, z) for x in (-length / 2, length / 2) for y in (-width / 2, width / 2)
                  for z in (0.0, front if y < 0 else back)])]


def bowl(r_bottom: float, r_top: float, height: float, wall: float) -> Parts:
    return [prism(12, r_bottom, r_bottom, 0.0, wall)] + cup_wall(
        12, (r_bottom, r_bottom), (r_top, r_top), wall, 0.0, height)


def plate(diameter: float, rim: float = 0.015, flare: float = 0.008) -> Parts:
    # A 6 mm base and a flared rim (15 mm high, 8 mm out): too flat for fingers to get under.
    r = diameter / 2.0
    return [prism(16, r - flare, r - flare, 0.0, 0.006)] + cup_wall(
        16, (r - flare, r - flare), (r, r), 0.01, 0.0, rim)


def caliper(length: float, opening: float, jaw: float) -> Parts:
    # Beam along +x; the fixed jaw at x = 0 and the slider's jaw both reach `jaw` beyond the
    # beam towards +y, `opening` apart: the two jaws form a hook. The slider is thicker.
    beam_w, t = 0.016, 0.004
    slider_x = 0.01 + opening
    return [floor_box((length, beam_w, t), x=length / 2),
            floor_box((0.01, beam_w + jaw, t), x=0.005, y=jaw / 2),
            floor_box((0.045, 0.024, 0.009), x=slider_x + 0.0225),
            floor_box((0.01, beam_w + jaw, t), x=slider_x + 0.005, y=jaw / 2)]


def _handle(length: float, width: float, height: float, taper: float = 1.0) -> trimesh.Trimesh:
    """A handle from x = 0 to x = length, `width` wide at x = 0 narrowing by `taper`."""
    return hull([(x, s * w / 2, z) for x, w in ((0.0, width), (length, width * taper))
                 for s in (-1, 1) for z in (0.0, height)])


def spoon(handle: float, head: Tuple[float, float], depth: float) -> Parts:
    a, b = head
    cx = handle + a  # the head's centre
    bottom = (0.7 * a, 0.7 * b)
    # The neck joins the handle's end to the outside of the flared wall without entering the cup.
    neck = hull([(x, s * 0.006, z) for x, z in ((handle - 0.005, 0.0), (handle - 0.005, 0.012),
                                                 (cx - bottom[0] + 0.002, 0.0), (cx - a + 0.002, depth))
                 for s in (-1, 1)])
    return ([_handle(handle, 0.02, 0.012, taper=0.6), neck, prism(12, *bottom, 0.0, 0.003, cx=cx)]
            + cup_wall(12, bottom, head, 0.003, 0.0, depth, cx=cx))


def fork(handle: float, tine: float) -> Parts:
    parts = [_handle(handle, 0.02, 0.012, taper=0.6),
             hull([(x, s * w / 2, z) for x, w in ((handle - 0.01, 0.012), (handle + 0.02, 0.028))
                   for s in (-1, 1) for z in (0.0, 0.004)])]
    for k in range(4):  # 4 mm tines with 4 mm gaps: the gaps are the concavity
        parts.append(floor_box((tine, 0.004, 0.004), x=handle + 0.02 + tine / 2 - 0.001,
                               y=-0.012 + 0.008 * k))
    return parts


def ladle(handle: float, radius: float, depth: float) -> Parts:
    # A deep cup at the origin; the handle leaves its rim and slopes down to rest its tip on
    # the table, so the ladle lies stably on cup bottom + handle tip, handle graspable mid-way.
    bottom = (0.75 * radius, 0.75 * radius)
    x0, x1, h = radius - 0.002, radius + handle, 0.012
    grip = hull([(x, s * 0.01, z) for x, z0 in ((x0, depth - h), (x1, 0.0)) for s in (-1, 1)
                 for z in (z0, z0 + h)])
    return ([prism(12, *bottom, 0.0, 0.003)]
            + cup_wall(12, bottom, (radius, radius), 0.003, 0.0, depth) + [grip])


def dipper(handle: float, radius: float, height: float) -> Parts:
    # A cylindrical cup with a straight, flat handle at its base (like a saucepan).
    grip = floor_box((handle + 0.003, 0.022, 0.015), x=radius - 0.003 + (handle + 0.003) / 2)
    return ([prism(12, radius, radius, 0.0, 0.004)]
            + cup_wall(12, (radius, radius), (radius, radius), 0.004, 0.0, height) + [grip])


def spatula(handle: float, blade: float, width: float) -> Parts:
    neck = hull([(handle - 0.005, s * 0.011, z) for s in (-1, 1) for z in (0.0, 0.015)]
                + [(handle + 0.03, s * 0.015, z) for s in (-1, 1) for z in (0.0, 0.004)])
    return [floor_box((handle, 0.022, 0.015), x=handle / 2), neck,
            floor_box((blade, width, 0.004), x=handle + 0.03 + blade / 2 - 0.002)]


def hairbrush(handle: float, a: float, b: float) -> Parts:
    cx = handle + a - 0.005
    parts = [floor_box((handle, 0.025, 0.02), x=handle / 2), prism(16, a, b, 0.0, 0.012, cx=cx)]
    for k in range(4):  # bristle rows on the upper face, grooves between them
        y = (k - 1.5) * (b * 0.45)
        parts.append(floor_box((1.4 * a * math.sqrt(1 - (y / b) ** 2), 0.006, 0.012), x=cx, y=y, z0=0.012))
    return parts


def hammer(handle: float, head: float) -> Parts:
    # A T: handle along +x, head across it (along y) — the head works as a hook.
    return [floor_box((handle, 0.025, 0.02), x=handle / 2),
            floor_box((0.03, head, 0.03), x=handle + 0.015)]


def l_stick(handle: float, crook: float, side: float = 0.02) -> Parts:
    # Handle along +x at y in [0, side]; the crook at the +x end runs along +y. The corner
    # region x < handle - side, y > side is open: a small object fits inside the crook.
    return [floor_box((handle, side, side), x=handle / 2, y=side / 2),
            floor_box((side, crook, side), x=handle - side / 2, y=crook / 2)]


def banana(radius: float, span_deg: float, thickness: float, pieces: int = 5) -> Parts:
    # Capsules along a circular arc in the table plane, all resting on the table.
    angles = np.radians(np.linspace(-span_deg / 2, span_deg / 2, pieces + 1))
    pts = [(radius * math.sin(t), radius * (math.cos(t) - 1.0), thickness) for t in angles]
    parts = [capsule(pts[i], pts[i + 1], thickness) for i in range(pieces)]
    t_end = angles[-1] + 0.02 / radius  # a thin stem continuing the arc
    stem = (radius * math.sin(t_end), radius * (math.cos(t_end) - 1.0), thickness)
    return parts + [capsule(pts[-1], stem, 0.005)]


def apple(radius: float, height: float) -> Parts:
    return [ellipsoid((radius, radius, height / 2), (0.0, 0.0, height / 2)),
            creation.cylinder(0.003, segment=[(0, 0, height - 0.006), (0, 0, height + 0.012)], sections=8)]


def ellipsoid_body(radii: Vec) -> Parts:
    return [ellipsoid(radii, (0.0, 0.0, radii[2]))]


def table(depth: float, width: float, height: float = 0.75, top: float = 0.05) -> Parts:
    # Top surface at z = 0 in the link frame, the floor at z = -height.
    leg, ox, oy = 0.05, depth / 2 - 0.075, width / 2 - 0.075
    legs = [floor_box((leg, leg, height - top), x=sx * ox, y=sy * oy, z0=-height)
            for sx in (-1, 1) for sy in (-1, 1)]
    return [floor_box((depth, width, top), z0=-top)] + legs


def slope(angle_deg: float, length: float = 0.3, width: float = 0.2, board: float = 0.01) -> Parts:
    # A board rising towards +x on a solid wedge; the footprint is centred on the origin.
    c, s = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))
    run, rise = length * c, length * s
    dx = -(run - board * s) / 2  # centre the footprint [-board*s, run] in x
    ys = (-width / 2, width / 2)
    wedge = hull([(x + dx, y, z) for x, z in ((0, 0), (run, 0), (run, rise)) for y in ys])
    plank = hull([(x + dx, y, z) for x, z in ((0, 0), (run, rise), (-board * s, board * c),
                                              (run - board * s, rise + board * c)) for y in ys])
    return [wedge, plank]


def tunnel(height: float, width: float, length: float, wall: float = 0.02) -> Parts:
    walls = [floor_box((length, wall, height), y=sy * (width + wall) / 2) for sy in (-1, 1)]
    return walls + [floor_box((length, width + 2 * wall, wall), z0=height)]


def ledge(radius: float, height: float = 0.02, margin: float = 0.02, gap: float = 0.009,
           wall: float = 0.015, wall_above: float = 0.03, curb_above: float = 0.018,
           segments: int = 12) -> Parts:
    # A lever's fulcrum for a plate of `radius` (the Lever task): a `height` platform whose
    # +x edge, `margin` beyond the cradle's centre (the origin), is the fulcrum; beyond it a pit
    # down to the table, closed by a curved wall `gap` outside the plate's rim. A plate centred
    # on the origin rests flat (its centre of mass over the platform) with every rim point that
    # overhangs the pit hemmed in by the wall: no finger fits outside it, so the plate cannot be
    # grasped until a weight on the overhang tips that side into the pit and the other side up.
    # A curb hems the near half in as well, `curb_above` over the platform: 3 mm taller than
    # the plate's rim, so a push cannot ride the rim up onto it (a curb no taller than the rim
    # meets its flare, which ramps the plate up), nor push the plate off the platform's back
    # or side edge (the Edge strategy). A tipped plate's near rim rises 2 cm clear above it,
    # and moves inwards as it rises, so the fingers take the rim over the curb.
    outer = radius + gap + wall
    platform = box((margin + outer, 2 * outer, height), ((margin - outer) / 2, 0.0, height / 2))
    parts = [platform]

    def ring(top: float, start: float, stop: float) -> None:
        angles = np.radians(np.linspace(start, stop, segments + 1))
        for a, b in zip(angles, angles[1:]):
            # Inner corners on the circle radius + gap: a chord only comes closer at its middle.
            pts = [(r * math.cos(t), r * math.sin(t), z) for r in (radius + gap, outer) for t in (a, b)
                   for z in (0.0, top)]
            parts.append(hull(pts))

    ring(height + wall_above, -90.0, 90.0)   # the wall around the pit
    ring(height + curb_above, 90.0, 270.0)   # the curb around the platform
    return parts
