"""Procedural category models: every object is a list of convex parts.

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
from dataclasses import dataclass
from typing import Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np
import trimesh
from trimesh import creation

Vec = Sequence[float]
Parts = List[trimesh.Trimesh]
RGBA = Tuple[float, float, float, float]


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
@dataclass(frozen=True)
class Variant:
    """One size/shape variant: keyword arguments of the category's builder, and a description."""
    params: Dict[str, object]
    description: str


@dataclass(frozen=True)
class Category:
    """A category: builder(**params) -> convex parts, physical constants, variants."""
    name: str
    builder: Callable[..., Parts]
    variants: Tuple[Variant, ...]
    density: float  # kg/m^3 of the solid model; ignored when mass is given or fixed
    friction: float
    rgba: RGBA
    fixed: bool = False
    mass: Optional[float] = None  # explicit mass (kg) overriding density, same for all variants


@dataclass(frozen=True)
class Model:
    """One built variant, ready for `urdf.write_model`."""
    category: Category
    index: int
    parts: Tuple[trimesh.Trimesh, ...]
    description: str

    @property
    def name(self) -> str:
        return f"{self.category.name}/{self.index}"


def _block(size: Vec) -> Parts:
    return [floor_box(size)]


def _calculator(length: float, width: float, front: float, back: float) -> Parts:
    # A wedge (thicker at the back, like a desk calculator) is still one convex hull.
    return [hull([(x, y, z) for x in (-length / 2, length / 2) for y in (-width / 2, width / 2)
                  for z in (0.0, front if y < 0 else back)])]


def _bowl(r_bottom: float, r_top: float, height: float, wall: float) -> Parts:
    return [prism(12, r_bottom, r_bottom, 0.0, wall)] + cup_wall(
        12, (r_bottom, r_bottom), (r_top, r_top), wall, 0.0, height)


def _plate(diameter: float, rim: float = 0.015, flare: float = 0.008) -> Parts:
    # A 6 mm base and a flared rim (15 mm high, 8 mm out): too flat for fingers to get under.
    r = diameter / 2.0
    return [prism(16, r - flare, r - flare, 0.0, 0.006)] + cup_wall(
        16, (r - flare, r - flare), (r, r), 0.01, 0.0, rim)


def _caliper(length: float, opening: float, jaw: float) -> Parts:
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


def _spoon(handle: float, head: Tuple[float, float], depth: float) -> Parts:
    a, b = head
    cx = handle + a  # the head's centre
    bottom = (0.7 * a, 0.7 * b)
    # The neck joins the handle's end to the outside of the flared wall without entering the cup.
    neck = hull([(x, s * 0.006, z) for x, z in ((handle - 0.005, 0.0), (handle - 0.005, 0.012),
                                                 (cx - bottom[0] + 0.002, 0.0), (cx - a + 0.002, depth))
                 for s in (-1, 1)])
    return ([_handle(handle, 0.02, 0.012, taper=0.6), neck, prism(12, *bottom, 0.0, 0.003, cx=cx)]
            + cup_wall(12, bottom, head, 0.003, 0.0, depth, cx=cx))


def _fork(handle: float, tine: float) -> Parts:
    parts = [_handle(handle, 0.02, 0.012, taper=0.6),
             hull([(x, s * w / 2, z) for x, w in ((handle - 0.01, 0.012), (handle + 0.02, 0.028))
                   for s in (-1, 1) for z in (0.0, 0.004)])]
    for k in range(4):  # 4 mm tines with 4 mm gaps: the gaps are the concavity
        parts.append(floor_box((tine, 0.004, 0.004), x=handle + 0.02 + tine / 2 - 0.001,
                               y=-0.012 + 0.008 * k))
    return parts


def _ladle(handle: float, radius: float, depth: float) -> Parts:
    # A deep cup at the origin; the handle leaves its rim and slopes down to rest its tip on
    # the table, so the ladle lies stably on cup bottom + handle tip, handle graspable mid-way.
    bottom = (0.75 * radius, 0.75 * radius)
    x0, x1, h = radius - 0.002, radius + handle, 0.012
    grip = hull([(x, s * 0.01, z) for x, z0 in ((x0, depth - h), (x1, 0.0)) for s in (-1, 1)
                 for z in (z0, z0 + h)])
    return ([prism(12, *bottom, 0.0, 0.003)]
            + cup_wall(12, bottom, (radius, radius), 0.003, 0.0, depth) + [grip])


def _dipper(handle: float, radius: float, height: float) -> Parts:
    # A cylindrical cup with a straight, flat handle at its base (like a saucepan).
    grip = floor_box((handle + 0.003, 0.022, 0.015), x=radius - 0.003 + (handle + 0.003) / 2)
    return ([prism(12, radius, radius, 0.0, 0.004)]
            + cup_wall(12, (radius, radius), (radius, radius), 0.004, 0.0, height) + [grip])


def _spatula(handle: float, blade: float, width: float) -> Parts:
    neck = hull([(handle - 0.005, s * 0.011, z) for s in (-1, 1) for z in (0.0, 0.015)]
                + [(handle + 0.03, s * 0.015, z) for s in (-1, 1) for z in (0.0, 0.004)])
    return [floor_box((handle, 0.022, 0.015), x=handle / 2), neck,
            floor_box((blade, width, 0.004), x=handle + 0.03 + blade / 2 - 0.002)]


def _hairbrush(handle: float, a: float, b: float) -> Parts:
    cx = handle + a - 0.005
    parts = [floor_box((handle, 0.025, 0.02), x=handle / 2), prism(16, a, b, 0.0, 0.012, cx=cx)]
    for k in range(4):  # bristle rows on the upper face, grooves between them
        y = (k - 1.5) * (b * 0.45)
        parts.append(floor_box((1.4 * a * math.sqrt(1 - (y / b) ** 2), 0.006, 0.012), x=cx, y=y, z0=0.012))
    return parts


def _hammer(handle: float, head: float) -> Parts:
    # A T: handle along +x, head across it (along y) — the head works as a hook.
    return [floor_box((handle, 0.025, 0.02), x=handle / 2),
            floor_box((0.03, head, 0.03), x=handle + 0.015)]


def _l_stick(handle: float, crook: float, side: float = 0.02) -> Parts:
    # Handle along +x at y in [0, side]; the crook at the +x end runs along +y. The corner
    # region x < handle - side, y > side is open: a small object fits inside the crook.
    return [floor_box((handle, side, side), x=handle / 2, y=side / 2),
            floor_box((side, crook, side), x=handle - side / 2, y=crook / 2)]


def _banana(radius: float, span_deg: float, thickness: float, pieces: int = 5) -> Parts:
    # Capsules along a circular arc in the table plane, all resting on the table.
    angles = np.radians(np.linspace(-span_deg / 2, span_deg / 2, pieces + 1))
    pts = [(radius * math.sin(t), radius * (math.cos(t) - 1.0), thickness) for t in angles]
    parts = [capsule(pts[i], pts[i + 1], thickness) for i in range(pieces)]
    t_end = angles[-1] + 0.02 / radius  # a thin stem continuing the arc
    stem = (radius * math.sin(t_end), radius * (math.cos(t_end) - 1.0), thickness)
    return parts + [capsule(pts[-1], stem, 0.005)]


def _apple(radius: float, height: float) -> Parts:
    return [ellipsoid((radius, radius, height / 2), (0.0, 0.0, height / 2)),
            creation.cylinder(0.003, segment=[(0, 0, height - 0.006), (0, 0, height + 0.012)], sections=8)]


def _ellipsoid(radii: Vec) -> Parts:
    return [ellipsoid(radii, (0.0, 0.0, radii[2]))]


def _table(depth: float, width: float, height: float = 0.75, top: float = 0.05) -> Parts:
    # Top surface at z = 0 in the link frame, the floor at z = -height.
    leg, ox, oy = 0.05, depth / 2 - 0.075, width / 2 - 0.075
    legs = [floor_box((leg, leg, height - top), x=sx * ox, y=sy * oy, z0=-height)
            for sx in (-1, 1) for sy in (-1, 1)]
    return [floor_box((depth, width, top), z0=-top)] + legs


def _slope(angle_deg: float, length: float = 0.3, width: float = 0.2, board: float = 0.01) -> Parts:
    # A board rising towards +x on a solid wedge; the footprint is centred on the origin.
    c, s = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))
    run, rise = length * c, length * s
    dx = -(run - board * s) / 2  # centre the footprint [-board*s, run] in x
    ys = (-width / 2, width / 2)
    wedge = hull([(x + dx, y, z) for x, z in ((0, 0), (run, 0), (run, rise)) for y in ys])
    plank = hull([(x + dx, y, z) for x, z in ((0, 0), (run, rise), (-board * s, board * c),
                                              (run - board * s, rise + board * c)) for y in ys])
    return [wedge, plank]


def _tunnel(height: float, width: float, length: float, wall: float = 0.02) -> Parts:
    walls = [floor_box((length, wall, height), y=sy * (width + wall) / 2) for sy in (-1, 1)]
    return walls + [floor_box((length, width + 2 * wall, wall), z0=height)]


def _ledge(radius: float, height: float = 0.02, margin: float = 0.02, gap: float = 0.009,
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


def _v(description: str, **params: object) -> Variant:
    return Variant(dict(params), description)


CATEGORIES: Dict[str, Category] = {c.name: c for c in [
    Category("block", _block, (_v("5 cm cube", size=(0.05, 0.05, 0.05)),
                               _v("4.5 cm cube", size=(0.045, 0.045, 0.045)),
                               _v("5 x 5 x 7 cm tall block", size=(0.05, 0.05, 0.07)),
                               _v("5.5 x 4.8 x 6 cm block", size=(0.055, 0.048, 0.06)),
                               _v("4 x 4.6 x 5.8 cm block", size=(0.04, 0.046, 0.058))),
             600.0, 0.6, (0.2, 0.4, 0.85, 1.0)),
    Category("brick", _block, (_v("20 x 10 x 6 cm brick", size=(0.2, 0.1, 0.06)),
                               _v("18 x 9 x 5 cm brick", size=(0.18, 0.09, 0.05)),
                               _v("22 x 10 x 7 cm brick", size=(0.22, 0.1, 0.07)),
                               _v("19 x 9.5 x 6.5 cm brick", size=(0.19, 0.095, 0.065)),
                               _v("21 x 8.5 x 5.5 cm brick", size=(0.21, 0.085, 0.055))),
             700.0, 0.8, (0.55, 0.3, 0.15, 1.0)),
    Category("box", _block, (_v("12 x 6 x 6 cm box, graspable across its width", size=(0.12, 0.06, 0.06)),
                             _v("10 x 6 x 5 cm box", size=(0.10, 0.06, 0.05)),
                             _v("14 x 6.5 x 8 cm box", size=(0.14, 0.065, 0.08)),
                             _v("13 x 5.5 x 7 cm box", size=(0.13, 0.055, 0.07)),
                             _v("11 x 6.2 x 6.5 cm box", size=(0.11, 0.062, 0.065))),
             600.0, 0.6, (0.75, 0.6, 0.4, 1.0)),
    Category("small-block", _block, (_v("3 cm cube", size=(0.03, 0.03, 0.03)),
                                     _v("2.5 cm cube", size=(0.025, 0.025, 0.025)),
                                     _v("3.5 x 3.5 x 3 cm block", size=(0.035, 0.035, 0.03)),
                                     _v("3.2 x 2.8 x 3.4 cm block", size=(0.032, 0.028, 0.034)),
                                     _v("2.7 x 2.7 x 3.2 cm block", size=(0.027, 0.027, 0.032))),
             600.0, 0.6, (1.0, 0.55, 0.1, 1.0)),
    Category("bowl", _bowl, (_v("15 cm bowl, 6 cm deep", r_bottom=0.045, r_top=0.075, height=0.06, wall=0.006),
                             _v("12 cm bowl, 5 cm deep", r_bottom=0.04, r_top=0.06, height=0.05, wall=0.005),
                             _v("18 cm shallow bowl", r_bottom=0.05, r_top=0.09, height=0.045, wall=0.006)),
             1500.0, 0.6, (0.8, 0.85, 0.95, 1.0)),
    Category("plate", _plate, (_v("22 cm plate with a 1.5 cm rim", diameter=0.22),
                               _v("20 cm plate", diameter=0.20), _v("24 cm plate", diameter=0.24),
                               _v("21 cm plate, low 1.2 cm rim flaring 1 cm", diameter=0.21, rim=0.012, flare=0.01),
                               _v("23 cm plate, high 1.8 cm rim flaring 0.7 cm", diameter=0.23, rim=0.018, flare=0.007)),
             700.0, 0.5, (0.95, 0.95, 0.92, 1.0)),
    Category("document", _block, (_v("A4 sheet stack", size=(0.297, 0.21, 0.003)),
                                  _v("US letter stack", size=(0.279, 0.216, 0.003)),
                                  _v("thin folder", size=(0.31, 0.22, 0.006)),
                                  _v("30 x 20 cm pad, 4 mm", size=(0.30, 0.20, 0.004)),
                                  _v("28.5 x 22.5 cm folder, 5 mm", size=(0.285, 0.225, 0.005))),
             800.0, 0.5, (0.96, 0.93, 0.75, 1.0)),
    Category("calculator", _calculator, (
        _v("15 x 8 x 1.5 cm calculator", length=0.15, width=0.08, front=0.015, back=0.015),
        _v("14 x 7.5 x 1.2 cm calculator", length=0.14, width=0.075, front=0.012, back=0.012),
        _v("16 x 8.5 cm desk calculator, wedge 1-2 cm", length=0.16, width=0.085, front=0.01, back=0.02),
        _v("14.5 x 7 cm steep calculator, wedge 0.8-1.8 cm", length=0.145, width=0.07, front=0.008, back=0.018),
        _v("15.5 x 9 x 1.4 cm calculator", length=0.155, width=0.09, front=0.014, back=0.014)),
        900.0, 0.7, (0.2, 0.2, 0.22, 1.0)),
    Category("caliper", _caliper, (_v("25 cm caliper, jaws 3 cm apart", length=0.25, opening=0.03, jaw=0.04),
                                   _v("20 cm caliper", length=0.2, opening=0.025, jaw=0.035),
                                   _v("30 cm caliper", length=0.3, opening=0.04, jaw=0.05),
                                   _v("27 cm caliper, short jaws", length=0.27, opening=0.035, jaw=0.03),
                                   _v("24 cm caliper, long jaws", length=0.24, opening=0.022, jaw=0.055)),
             7800.0, 0.5, (0.7, 0.72, 0.75, 1.0)),
    Category("spoon", _spoon, (_v("20 cm spoon", handle=0.13, head=(0.035, 0.022), depth=0.015),
                               _v("17 cm spoon", handle=0.11, head=(0.03, 0.019), depth=0.013),
                               _v("26 cm serving spoon", handle=0.17, head=(0.045, 0.03), depth=0.02),
                               _v("23 cm spoon, wide head", handle=0.15, head=(0.04, 0.026), depth=0.016),
                               _v("19 cm spoon, round head", handle=0.12, head=(0.033, 0.027), depth=0.012)),
             2500.0, 0.5, (0.75, 0.75, 0.8, 1.0)),
    Category("fork", _fork, (_v("19 cm fork, 4 tines", handle=0.13, tine=0.04),
                             _v("17 cm fork", handle=0.115, tine=0.035),
                             _v("22 cm fork", handle=0.15, tine=0.045)),
             2500.0, 0.5, (0.65, 0.68, 0.72, 1.0)),
    Category("soup-ladle", _ladle, (_v("31 cm ladle, 9 cm cup", handle=0.22, radius=0.045, depth=0.045),
                                    _v("27 cm ladle, 8 cm cup", handle=0.19, radius=0.04, depth=0.04),
                                    _v("36 cm ladle, 10 cm cup", handle=0.26, radius=0.05, depth=0.05),
                                    _v("32 cm ladle, shallow 8.4 cm cup", handle=0.24, radius=0.042, depth=0.038),
                                    _v("30 cm ladle, deep 9.6 cm cup", handle=0.2, radius=0.048, depth=0.05)),
             1500.0, 0.6, (0.55, 0.55, 0.62, 1.0)),
    Category("dipper", _dipper, (_v("25 cm dipper, 9 cm cylindrical cup", handle=0.16, radius=0.045, height=0.07),
                                 _v("22 cm dipper", handle=0.14, radius=0.04, height=0.06),
                                 _v("29 cm dipper", handle=0.18, radius=0.05, height=0.08),
                                 _v("21 cm dipper, tall narrow cup", handle=0.13, radius=0.04, height=0.075),
                                 _v("30 cm dipper, tall cup", handle=0.2, radius=0.048, height=0.075)),
             1500.0, 0.6, (0.6, 0.45, 0.3, 1.0)),
    Category("spatula", _spatula, (_v("27 cm spatula", handle=0.16, blade=0.08, width=0.06),
                                   _v("23 cm spatula", handle=0.13, blade=0.07, width=0.05),
                                   _v("31 cm spatula", handle=0.19, blade=0.09, width=0.07),
                                   _v("28.5 cm spatula, wide blade", handle=0.18, blade=0.075, width=0.065),
                                   _v("26 cm spatula, long narrow blade", handle=0.145, blade=0.085, width=0.055)),
             1200.0, 0.6, (0.2, 0.6, 0.6, 1.0)),
    Category("hairbrush", _hairbrush, (_v("22 cm hairbrush", handle=0.12, a=0.05, b=0.035),
                                       _v("19 cm hairbrush", handle=0.1, a=0.045, b=0.03),
                                       _v("25 cm hairbrush", handle=0.14, a=0.06, b=0.04)),
             900.0, 0.7, (0.55, 0.3, 0.6, 1.0)),
    Category("hammer", _hammer, (_v("28 cm hammer, 10 cm head", handle=0.25, head=0.1),
                                 _v("23 cm hammer, 8 cm head", handle=0.2, head=0.08),
                                 _v("33 cm hammer, 12 cm head", handle=0.3, head=0.12),
                                 _v("30 cm hammer, 9 cm head", handle=0.27, head=0.09),
                                 _v("25 cm hammer, 11 cm head", handle=0.22, head=0.11)),
             2000.0, 0.6, (0.35, 0.4, 0.5, 1.0)),
    Category("wooden-stick", _block, (_v("35 cm stick, 2 cm square", size=(0.35, 0.02, 0.02)),
                                      _v("30 cm stick", size=(0.3, 0.02, 0.02)),
                                      _v("40 cm stick, 2.5 cm square", size=(0.4, 0.025, 0.025)),
                                      _v("33 cm stick, 2.2 x 1.8 cm", size=(0.33, 0.022, 0.018)),
                                      _v("37 cm stick, 1.8 x 2.4 cm", size=(0.37, 0.018, 0.024))),
             600.0, 0.6, (0.8, 0.65, 0.4, 1.0)),
    Category("l-stick", _l_stick, (_v("40 cm L-hook, 10 cm crook", handle=0.4, crook=0.1),
                                   _v("35 cm L-hook, 8 cm crook", handle=0.35, crook=0.08),
                                   _v("45 cm L-hook, 12 cm crook", handle=0.45, crook=0.12),
                                   _v("42 cm L-hook, 9 cm crook", handle=0.42, crook=0.09),
                                   _v("38 cm L-hook, 11 cm crook", handle=0.38, crook=0.11)),
             600.0, 0.6, (0.65, 0.45, 0.25, 1.0)),
    # Weighted to 0.1 kg: the paper's Lever task uses a walnut as the counterweight on a plate.
    Category("walnut", _ellipsoid, (_v("4 cm walnut", radii=(0.02, 0.017, 0.017)),
                                    _v("3.4 cm walnut", radii=(0.017, 0.015, 0.015)),
                                    _v("4.4 cm walnut", radii=(0.022, 0.019, 0.019)),
                                    _v("3.8 cm walnut, flattened", radii=(0.019, 0.018, 0.016)),
                                    _v("4.2 cm walnut, tall", radii=(0.021, 0.016, 0.018))),
             1000.0, 0.7, (0.5, 0.35, 0.2, 1.0), mass=0.1),
    Category("banana", _banana, (_v("21 cm banana", radius=0.16, span_deg=75.0, thickness=0.017),
                                 _v("17 cm banana", radius=0.14, span_deg=70.0, thickness=0.015),
                                 _v("25 cm banana", radius=0.18, span_deg=80.0, thickness=0.019)),
             950.0, 0.7, (0.95, 0.85, 0.2, 1.0)),
    # Apples stay under 7.5 cm across so that the 8 cm gripper can take one once hooked in.
    Category("apple", _apple, (_v("7 cm apple", radius=0.035, height=0.066),
                               _v("6.5 cm apple", radius=0.0325, height=0.06),
                               _v("7.2 cm apple", radius=0.036, height=0.07)),
             800.0, 0.7, (0.75, 0.1, 0.1, 1.0)),
    Category("ball", _ellipsoid, (_v("6 cm ball", radii=(0.03, 0.03, 0.03)),
                                  _v("5 cm ball", radii=(0.025, 0.025, 0.025)),
                                  _v("7 cm ball", radii=(0.035, 0.035, 0.035))),
             350.0, 0.7, (0.2, 0.7, 0.3, 1.0)),
    Category("table", _table, (_v("1.0 x 1.2 m table, top surface at z = 0, 0.75 m high", depth=1.0, width=1.2),
                               _v("0.8 x 1.0 m table", depth=0.8, width=1.0),
                               _v("1.2 x 1.6 m table", depth=1.2, width=1.6)),
             0.0, 0.6, (0.8, 0.7, 0.55, 1.0), fixed=True),
    Category("slope", _slope, (_v("10 degree slope, 30 x 20 cm board", angle_deg=10.0),
                               _v("20 degree slope", angle_deg=20.0), _v("30 degree slope", angle_deg=30.0),
                               _v("25 degree slope, 28 x 22 cm board", angle_deg=25.0, length=0.28, width=0.22)),
             0.0, 0.5, (0.45, 0.6, 0.45, 1.0), fixed=True),
    Category("tunnel", _tunnel, (_v("tunnel, inside 10 cm wide x 8 cm high x 25 cm long",
                                    height=0.08, width=0.1, length=0.25),
                                 _v("narrow tunnel, inside 9 x 7 x 22 cm", height=0.07, width=0.09, length=0.22),
                                 _v("wide tunnel, inside 12 x 9 x 30 cm", height=0.09, width=0.12, length=0.3),
                                 # Short ones for the Poking task: a 22-35 cm tool pokes a block out.
                                 _v("short tunnel, inside 10 x 8 x 16 cm", height=0.08, width=0.1, length=0.16),
                                 _v("short tunnel, inside 11 x 8.5 x 18 cm", height=0.085, width=0.11,
                                    length=0.18),
                                 _v("short tunnel, inside 10.5 x 8.2 x 17 cm", height=0.082, width=0.105,
                                    length=0.17),
                                 _v("short tunnel, inside 10 x 8.8 x 15 cm", height=0.088, width=0.1, length=0.15)),
             0.0, 0.5, (0.6, 0.6, 0.6, 1.0), fixed=True),
    # The Lever task's fulcrum, one per plate size (plate/0 ... plate/4).
    Category("ledge", _ledge, (_v("ledge cradling a 22 cm plate: 2 cm platform, pit, curved wall and curb", radius=0.11),
                               _v("ledge cradling a 20 cm plate", radius=0.10),
                               _v("ledge cradling a 24 cm plate", radius=0.12),
                               _v("ledge cradling a 21 cm plate", radius=0.105),
                               _v("ledge cradling a 23 cm plate", radius=0.115)),
             0.0, 0.6, (0.5, 0.5, 0.58, 1.0), fixed=True),
]}


def build(category: str, index: int) -> Model:
    """Build variant `index` of `category`; every part is checked to be convex."""
    cat = CATEGORIES[category]
    variant = cat.variants[index]
    parts = tuple(cat.builder(**variant.params))
    for i, part in enumerate(parts):
        if not (part.is_watertight and trimesh.convex.is_convex(part)):
            raise AssertionError(f"{category}/{index}: part {i} is not a closed convex mesh")
    return Model(cat, index, parts, variant.description)


def all_models() -> List[Model]:
    """Every variant of every category, in a fixed order."""
    return [build(name, i) for name, cat in CATEGORIES.items() for i in range(len(cat.variants))]
