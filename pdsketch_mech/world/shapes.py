"""The procedural category models: every category's builder (`shape_builders.py`), physical
constants and size variants, and `build`, which makes a variant's convex parts.

Variants are indexed per category; which index each split of a task may draw is decided in
`envs/` (train, dev and test-only variants), never here.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Dict, List, Optional, Tuple

import trimesh

from . import shape_builders as parts
from .shape_builders import Parts

RGBA = Tuple[float, float, float, float]


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


def _v(description: str, **params: object) -> Variant:
    return Variant(dict(params), description)


CATEGORIES: Dict[str, Category] = {c.name: c for c in [
    Category("block", parts.block, (_v("5 cm cube", size=(0.05, 0.05, 0.05)),
                               _v("4.5 cm cube", size=(0.045, 0.045, 0.045)),
                               _v("5 x 5 x 7 cm tall block", size=(0.05, 0.05, 0.07)),
                               _v("5.5 x 4.8 x 6 cm block", size=(0.055, 0.048, 0.06)),
                               _v("4 x 4.6 x 5.8 cm block", size=(0.04, 0.046, 0.058))),
             600.0, 0.6, (0.2, 0.4, 0.85, 1.0)),
    Category("brick", parts.block, (_v("20 x 10 x 6 cm brick", size=(0.2, 0.1, 0.06)),
                               _v("18 x 9 x 5 cm brick", size=(0.18, 0.09, 0.05)),
                               _v("22 x 10 x 7 cm brick", size=(0.22, 0.1, 0.07)),
                               _v("19 x 9.5 x 6.5 cm brick", size=(0.19, 0.095, 0.065)),
                               _v("21 x 8.5 x 5.5 cm brick", size=(0.21, 0.085, 0.055))),
             700.0, 0.8, (0.55, 0.3, 0.15, 1.0)),
    Category("box", parts.block, (_v("12 x 6 x 6 cm box, graspable across its width", size=(0.12, 0.06, 0.06)),
                             _v("10 x 6 x 5 cm box", size=(0.10, 0.06, 0.05)),
                             _v("14 x 6.5 x 8 cm box", size=(0.14, 0.065, 0.08)),
                             _v("13 x 5.5 x 7 cm box", size=(0.13, 0.055, 0.07)),
                             _v("11 x 6.2 x 6.5 cm box", size=(0.11, 0.062, 0.065))),
             600.0, 0.6, (0.75, 0.6, 0.4, 1.0)),
    Category("small-block", parts.block, (_v("3 cm cube", size=(0.03, 0.03, 0.03)),
                                     _v("2.5 cm cube", size=(0.025, 0.025, 0.025)),
                                     _v("3.5 x 3.5 x 3 cm block", size=(0.035, 0.035, 0.03)),
                                     _v("3.2 x 2.8 x 3.4 cm block", size=(0.032, 0.028, 0.034)),
                                     _v("2.7 x 2.7 x 3.2 cm block", size=(0.027, 0.027, 0.032))),
             600.0, 0.6, (1.0, 0.55, 0.1, 1.0)),
    Category("bowl", parts.bowl, (_v("15 cm bowl, 6 cm deep", r_bottom=0.045, r_top=0.075, height=0.06, wall=0.006),
                             _v("12 cm bowl, 5 cm deep", r_bottom=0.04, r_top=0.06, height=0.05, wall=0.005),
                             _v("18 cm shallow bowl", r_bottom=0.05, r_top=0.09, height=0.045, wall=0.006)),
             1500.0, 0.6, (0.8, 0.85, 0.95, 1.0)),
    Category("plate", parts.plate, (_v("22 cm plate with a 1.5 cm rim", diameter=0.22),
                               _v("20 cm plate", diameter=0.20), _v("24 cm plate", diameter=0.24),
                               _v("21 cm plate, low 1.2 cm rim flaring 1 cm", diameter=0.21, rim=0.012, flare=0.01),
                               _v("23 cm plate, high 1.8 cm rim flaring 0.7 cm", diameter=0.23, rim=0.018, flare=0.007)),
             700.0, 0.5, (0.95, 0.95, 0.92, 1.0)),
    Category("document", parts.block, (_v("A4 sheet stack", size=(0.297, 0.21, 0.003)),
                                  _v("US letter stack", size=(0.279, 0.216, 0.003)),
                                  _v("thin folder", size=(0.31, 0.22, 0.006)),
                                  _v("30 x 20 cm pad, 4 mm", size=(0.30, 0.20, 0.004)),
                                  _v("28.5 x 22.5 cm folder, 5 mm", size=(0.285, 0.225, 0.005))),
             800.0, 0.5, (0.96, 0.93, 0.75, 1.0)),
    Category("calculator", parts.calculator, (
        _v("15 x 8 x 1.5 cm calculator", length=0.15, width=0.08, front=0.015, back=0.015),
        _v("14 x 7.5 x 1.2 cm calculator", length=0.14, width=0.075, front=0.012, back=0.012),
        _v("16 x 8.5 cm desk calculator, wedge 1-2 cm", length=0.16, width=0.085, front=0.01, back=0.02),
        _v("14.5 x 7 cm steep calculator, wedge 0.8-1.8 cm", length=0.145, width=0.07, front=0.008, back=0.018),
        _v("15.5 x 9 x 1.4 cm calculator", length=0.155, width=0.09, front=0.014, back=0.014)),
        900.0, 0.7, (0.2, 0.2, 0.22, 1.0)),
    Category("caliper", parts.caliper, (_v("25 cm caliper, jaws 3 cm apart", length=0.25, opening=0.03, jaw=0.04),
                                   _v("20 cm caliper", length=0.2, opening=0.025, jaw=0.035),
                                   _v("30 cm caliper", length=0.3, opening=0.04, jaw=0.05),
                                   _v("27 cm caliper, short jaws", length=0.27, opening=0.035, jaw=0.03),
                                   _v("24 cm caliper, long jaws", length=0.24, opening=0.022, jaw=0.055)),
             7800.0, 0.5, (0.7, 0.72, 0.75, 1.0)),
    Category("spoon", parts.spoon, (_v("20 cm spoon", handle=0.13, head=(0.035, 0.022), depth=0.015),
                               _v("17 cm spoon", handle=0.11, head=(0.03, 0.019), depth=0.013),
                               _v("26 cm serving spoon", handle=0.17, head=(0.045, 0.03), depth=0.02),
                               _v("23 cm spoon, wide head", handle=0.15, head=(0.04, 0.026), depth=0.016),
                               _v("19 cm spoon, round head", handle=0.12, head=(0.033, 0.027), depth=0.012)),
             2500.0, 0.5, (0.75, 0.75, 0.8, 1.0)),
    Category("fork", parts.fork, (_v("19 cm fork, 4 tines", handle=0.13, tine=0.04),
                             _v("17 cm fork", handle=0.115, tine=0.035),
                             _v("22 cm fork", handle=0.15, tine=0.045)),
             2500.0, 0.5, (0.65, 0.68, 0.72, 1.0)),
    Category("soup-ladle", parts.ladle, (_v("31 cm ladle, 9 cm cup", handle=0.22, radius=0.045, depth=0.045),
                                    _v("27 cm ladle, 8 cm cup", handle=0.19, radius=0.04, depth=0.04),
                                    _v("36 cm ladle, 10 cm cup", handle=0.26, radius=0.05, depth=0.05),
                                    _v("32 cm ladle, shallow 8.4 cm cup", handle=0.24, radius=0.042, depth=0.038),
                                    _v("30 cm ladle, deep 9.6 cm cup", handle=0.2, radius=0.048, depth=0.05)),
             1500.0, 0.6, (0.55, 0.55, 0.62, 1.0)),
    Category("dipper", parts.dipper, (_v("25 cm dipper, 9 cm cylindrical cup", handle=0.16, radius=0.045, height=0.07),
                                 _v("22 cm dipper", handle=0.14, radius=0.04, height=0.06),
                                 _v("29 cm dipper", handle=0.18, radius=0.05, height=0.08),
                                 _v("21 cm dipper, tall narrow cup", handle=0.13, radius=0.04, height=0.075),
                                 _v("30 cm dipper, tall cup", handle=0.2, radius=0.048, height=0.075)),
             1500.0, 0.6, (0.6, 0.45, 0.3, 1.0)),
    Category("spatula", parts.spatula, (_v("27 cm spatula", handle=0.16, blade=0.08, width=0.06),
                                   _v("23 cm spatula", handle=0.13, blade=0.07, width=0.05),
                                   _v("31 cm spatula", handle=0.19, blade=0.09, width=0.07),
                                   _v("28.5 cm spatula, wide blade", handle=0.18, blade=0.075, width=0.065),
                                   _v("26 cm spatula, long narrow blade", handle=0.145, blade=0.085, width=0.055)),
             1200.0, 0.6, (0.2, 0.6, 0.6, 1.0)),
    Category("hairbrush", parts.hairbrush, (_v("22 cm hairbrush", handle=0.12, a=0.05, b=0.035),
                                       _v("19 cm hairbrush", handle=0.1, a=0.045, b=0.03),
                                       _v("25 cm hairbrush", handle=0.14, a=0.06, b=0.04)),
             900.0, 0.7, (0.55, 0.3, 0.6, 1.0)),
    Category("hammer", parts.hammer, (_v("28 cm hammer, 10 cm head", handle=0.25, head=0.1),
                                 _v("23 cm hammer, 8 cm head", handle=0.2, head=0.08),
                                 _v("33 cm hammer, 12 cm head", handle=0.3, head=0.12),
                                 _v("30 cm hammer, 9 cm head", handle=0.27, head=0.09),
                                 _v("25 cm hammer, 11 cm head", handle=0.22, head=0.11)),
             2000.0, 0.6, (0.35, 0.4, 0.5, 1.0)),
    Category("wooden-stick", parts.block, (_v("35 cm stick, 2 cm square", size=(0.35, 0.02, 0.02)),
                                      _v("30 cm stick", size=(0.3, 0.02, 0.02)),
                                      _v("40 cm stick, 2.5 cm square", size=(0.4, 0.025, 0.025)),
                                      _v("33 cm stick, 2.2 x 1.8 cm", size=(0.33, 0.022, 0.018)),
                                      _v("37 cm stick, 1.8 x 2.4 cm", size=(0.37, 0.018, 0.024))),
             600.0, 0.6, (0.8, 0.65, 0.4, 1.0)),
    Category("l-stick", parts.l_stick, (_v("40 cm L-hook, 10 cm crook", handle=0.4, crook=0.1),
                                   _v("35 cm L-hook, 8 cm crook", handle=0.35, crook=0.08),
                                   _v("45 cm L-hook, 12 cm crook", handle=0.45, crook=0.12),
                                   _v("42 cm L-hook, 9 cm crook", handle=0.42, crook=0.09),
                                   _v("38 cm L-hook, 11 cm crook", handle=0.38, crook=0.11)),
             600.0, 0.6, (0.65, 0.45, 0.25, 1.0)),
    # Weighted to 0.1 kg: the paper's Lever task uses a walnut as the counterweight on a plate.
    Category("walnut", parts.ellipsoid_body, (_v("4 cm walnut", radii=(0.02, 0.017, 0.017)),
                                    _v("3.4 cm walnut", radii=(0.017, 0.015, 0.015)),
                                    _v("4.4 cm walnut", radii=(0.022, 0.019, 0.019)),
                                    _v("3.8 cm walnut, flattened", radii=(0.019, 0.018, 0.016)),
                                    _v("4.2 cm walnut, tall", radii=(0.021, 0.016, 0.018))),
             1000.0, 0.7, (0.5, 0.35, 0.2, 1.0), mass=0.1),
    Category("banana", parts.banana, (_v("21 cm banana", radius=0.16, span_deg=75.0, thickness=0.017),
                                 _v("17 cm banana", radius=0.14, span_deg=70.0, thickness=0.015),
                                 _v("25 cm banana", radius=0.18, span_deg=80.0, thickness=0.019)),
             950.0, 0.7, (0.95, 0.85, 0.2, 1.0)),
    # Apples stay under 7.5 cm across so that the 8 cm gripper can take one once hooked in.
    Category("apple", parts.apple, (_v("7 cm apple", radius=0.035, height=0.066),
                               _v("6.5 cm apple", radius=0.0325, height=0.06),
                               _v("7.2 cm apple", radius=0.036, height=0.07)),
             800.0, 0.7, (0.75, 0.1, 0.1, 1.0)),
    Category("ball", parts.ellipsoid_body, (_v("6 cm ball", radii=(0.03, 0.03, 0.03)),
                                  _v("5 cm ball", radii=(0.025, 0.025, 0.025)),
                                  _v("7 cm ball", radii=(0.035, 0.035, 0.035))),
             350.0, 0.7, (0.2, 0.7, 0.3, 1.0)),
    Category("table", parts.table, (_v("1.0 x 1.2 m table, top surface at z = 0, 0.75 m high", depth=1.0, width=1.2),
                               _v("0.8 x 1.0 m table", depth=0.8, width=1.0),
                               _v("1.2 x 1.6 m table", depth=1.2, width=1.6)),
             0.0, 0.6, (0.8, 0.7, 0.55, 1.0), fixed=True),
    Category("slope", parts.slope, (_v("10 degree slope, 30 x 20 cm board", angle_deg=10.0),
                               _v("20 degree slope", angle_deg=20.0), _v("30 degree slope", angle_deg=30.0),
                               _v("25 degree slope, 28 x 22 cm board", angle_deg=25.0, length=0.28, width=0.22)),
             0.0, 0.5, (0.45, 0.6, 0.45, 1.0), fixed=True),
    Category("tunnel", parts.tunnel, (_v("tunnel, inside 10 cm wide x 8 cm high x 25 cm long",
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
    Category("ledge", parts.ledge, (_v("ledge cradling a 22 cm plate: 2 cm platform, pit, curved wall and curb", radius=0.11),
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
