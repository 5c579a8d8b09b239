"""The task distributions of the paper: six mechanisms (Sec. 4.1, appendix "Mechanism
Learning Setup") and the two compositional tasks of Table 2.

The robot's base is at the origin, the table (1.0 x 1.2 m) at (0.6, 0): its top spans
x 0.1..1.1, y -0.6..0.6 at z = 0. Every movable object is perturbed by up to +-5 cm and
+-15 degrees about its canonical pose and scaled by up to +-15 % (less where the mechanism
needs a tight fit); the test split holds out asset instances (variant 2 of most categories)
and, for Edge, Hook and Poking, a whole category never seen in training.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Dict

from .spec import Align, Assets, Distractors, ObjectSpec, TaskSpec

TABLE_EDGE_Y = 0.6
SMALL_TABLE_EDGE_Y = 0.5   # table/1 (0.8 x 1.0 m) at (0.6, 0): Edge and CoM use its +y edge, within easy reach
SCALE = (0.85, 1.15)
LEDGE_HEIGHT = 0.02  # the ledge's platform top (world/shape_builders.py `ledge`)

TABLE = ObjectSpec("table", Assets(("table",), ("table",)), xy=(0.6, 0.0), on=None, fixed=True,
                   noise_xy=(0.0, 0.0), noise_yaw=0.0, role="the table, top at z = 0")

SMALL_TABLE = ObjectSpec("table", Assets(("table/1",), ("table/1",)), xy=(0.6, 0.0), on=None, fixed=True,
                         noise_xy=(0.0, 0.0), noise_yaw=0.0, role="a smaller table, top at z = 0, +y edge at y = 0.5")

# The Hook tasks' light box beyond the arm's reach (the shipped problems/hook-use.pddl scene).
OUT_OF_REACH_BOX = ObjectSpec("target", Assets(("box/0", "box/1"), ("box/2",), ("box/3", "box/4")), xy=(0.9, 0.0), yaw=90.0, mass=0.2,
                              friction=0.6, scale=(0.9, 1.1), role="the box out of reach")

# Small household objects that stay where they are put (no balls: they roll).
CLUTTER = ("apple/0", "apple/1", "banana/0", "banana/1", "fork/0", "fork/1", "block/1", "walnut/0", "hairbrush/1")

EDGE = TaskSpec(
    "edge", "Edge",
    "a flat object lies on the table, too flat for the fingers to get around; pushed until it "
    "overhangs the table's edge, it can be pinched by the overhang",
    objects=(
        SMALL_TABLE,
        ObjectSpec("flat", Assets(("plate/0", "plate/1", "calculator/0", "calculator/1", "document/0", "document/1"),
                                  ("caliper/0", "caliper/1", "caliper/2", "plate/2", "calculator/2", "document/2"),
                                  ("caliper/3", "caliper/4", "plate/3", "plate/4", "calculator/3", "calculator/4",
                                   "document/3", "document/4")),
                   xy=(0.48, 0.2), yaw_by_category=(("calculator", 90.0), ("document", 90.0), ("caliper", 90.0)),
                   scale=(0.9, 1.1), role="the flat object to pick up"),
    ),
    goal="(holding flat)",
    distractors=Distractors(CLUTTER, (0, 2), ((0.3, 0.7), (-0.4, -0.1))),
    demo="push the flat object with the closed fingers towards +y until 35 % of it overhangs the "
         "table's edge, then grasp the overhang (a plate by its rim at its outermost point, where the "
         "outer finger has room now) and lift it",
)

HOOK = TaskSpec(
    "hook", "Hook",
    "a tool lies within reach and a box beyond it; the tool pulls the box closer",
    objects=(
        TABLE,
        ObjectSpec("tool", Assets(("l-stick/0", "l-stick/1", "soup-ladle/0", "soup-ladle/1", "hammer/0", "hammer/1",
                                   "spoon/0", "spoon/1"),
                                  # Held out: the spatula. Not the caliper: lying flat it cannot be
                                  # pinched (the Edge premise), so it is a hook only after a push over
                                  # the edge -- the push-pick-hook task.
                                  ("spatula/0", "spatula/1", "spatula/2", "l-stick/2", "soup-ladle/2", "hammer/2",
                                   "spoon/2"),
                                  ("spatula/3", "spatula/4", "l-stick/3", "l-stick/4", "soup-ladle/3", "hammer/3",
                                   "spoon/3")),
                   xy=(0.5, 0.15), scale=(0.9, 1.15), role="the hook"),
        OUT_OF_REACH_BOX,
    ),
    goal="(holding target)",
    distractors=Distractors(CLUTTER, (0, 2), ((0.3, 0.55), (-0.45, -0.2))),
    demo="grasp the tool by its handle, put its crook behind the box, pull the box towards the robot, "
         "put the tool down, grasp the box",
)

LEVER = TaskSpec(
    "lever", "Lever",
    "a plate lies flat on a ledge, its far side over a pit hemmed in by a curved wall, its near side "
    "in a curb it cannot be pushed over: no finger gets under or around its rim until a heavy "
    "object on the overhang tips the near side up",
    objects=(
        TABLE,
        ObjectSpec("ledge", Assets(("ledge/0", "ledge/1"), ("ledge/2",), ("ledge/3", "ledge/4")), xy=(0.55, -0.12),
                   fixed=True,
                   role="the fulcrum: platform, pit, wall and curb"),
        # Paired with the ledge (ledge/i cradles plate/i) and centred in its cradle.
        ObjectSpec("plate", Assets(("plate/0", "plate/1"), ("plate/2",), ("plate/3", "plate/4")), on="ledge",
                   frame="ledge",
                   surface=LEDGE_HEIGHT, match="ledge", noise_xy=(0.0, 0.0), role="the plate to pick up"),
        ObjectSpec("weight", Assets(("box/0", "box/1", "dipper/0", "dipper/1", "walnut/0", "walnut/1"),
                                    ("box/2", "dipper/2", "walnut/2", "spoon/0", "spoon/1", "spoon/2"),
                                    ("box/3", "dipper/3", "dipper/4", "walnut/3", "walnut/4", "spoon/3")),
                   xy=(0.42, 0.22), mass=0.5, friction=0.8, role="the heavy object"),
    ),
    goal="(holding plate)",
    distractors=Distractors(CLUTTER, (0, 2), ((0.25, 0.45), (0.35, 0.5))),
    demo="place the heavy object on the plate's overhang, which tips into the pit and lifts the near "
         "side, then grasp the plate by its raised rim",
)

POKING = TaskSpec(
    "poking", "Poking",
    "a block sits in the middle of a short tunnel, out of the fingers' reach from either end; a long "
    "tool pushed through the tunnel pokes it out",
    objects=(
        TABLE,
        ObjectSpec("tunnel", Assets(("tunnel/3",), ("tunnel/4",), ("tunnel/5", "tunnel/6")), xy=(0.52, 0.02),
                   yaw=90.0, fixed=True,
                   noise_yaw=10.0, role="the tunnel, across the table (along y)"),
        ObjectSpec("target", Assets(("block/0", "block/1"), ("block/2", "small-block/2"), ("block/3", "small-block/3")),
                   frame="tunnel",
                   noise_xy=(0.01, 0.01), role="the block in the tunnel"),
        ObjectSpec("tool", Assets(("wooden-stick/0", "wooden-stick/1", "spatula/0", "spatula/2"),
                                  ("spoon/2", "wooden-stick/2"), ("spoon/3", "wooden-stick/3")),
                   xy=(0.34, -0.28), yaw=90.0, scale=(1.0, 1.15), role="the poking tool"),
    ),
    goal="(holding target)",
    overlaps_ok=(("target", "tunnel"),),
    distractors=Distractors(CLUTTER, (0, 2), ((0.3, 0.55), (0.2, 0.45))),
    demo="grasp the tool by its end, push it through the tunnel until the block comes out of the far "
         "end, pull it back, put it down, grasp the block",
)

COM = TaskSpec(
    "com", "Center-of-Mass",
    "a plate overhangs the table's edge (so the fingers can get around its rim); it must end up "
    "resting on a small block alone, which only a placement with its centre of mass over the block achieves",
    objects=(
        SMALL_TABLE,
        ObjectSpec("flat", Assets(("plate/0", "plate/1", "calculator/1"), ("plate/2",), ("plate/3", "plate/4")),
                   xy=(0.42, 0.0),
                   yaw_by_category=(("calculator", 90.0),), scale=(0.9, 1.1),
                   align=Align("+y", SMALL_TABLE_EDGE_Y, 0.38), role="the object to place"),
        ObjectSpec("pedestal", Assets(("small-block/0", "small-block/1"), ("small-block/2",),
                                      ("small-block/3", "small-block/4")), xy=(0.58, 0.0),
                   mass=1.0, role="the small block"),
    ),
    goal="(and (support flat pedestal) (not (support flat table)) (handempty))",
    distractors=Distractors(CLUTTER, (0, 2), ((0.3, 0.55), (-0.4, -0.2))),
    demo="grasp the plate's rim where it overhangs, carry it over the small block with its centre of "
         "mass above the block's centre, lower it onto the block and let go",
)

SLOPE = TaskSpec(
    "slope-blocker", "Slope-and-Blocker",
    "a block slides down a slope (friction 0.6 x 0.5 < tan 20 deg); a grippy blocker laid across "
    "the slope below it holds it there",
    objects=(
        TABLE,
        ObjectSpec("slope", Assets(("slope/1",), ("slope/2",), ("slope/3",)), xy=(0.6, 0.25), fixed=True,
                   noise_yaw=10.0,
                   role="the slope, rising towards +x"),
        ObjectSpec("blocker", Assets(("wooden-stick/0", "wooden-stick/1", "l-stick/0", "l-stick/1"),
                                     ("spoon/0", "spoon/2", "wooden-stick/2", "l-stick/2"),
                                     ("spoon/3", "wooden-stick/3", "l-stick/3", "l-stick/4")),
                   xy=(0.42, -0.15), yaw=90.0, friction=1.5, role="the blocker (rubbery: it stays on the slope)"),
        ObjectSpec("block", Assets(("block/0",), ("block/1",), ("block/3", "block/4")), xy=(0.42, -0.38),
                   role="the block to leave on the slope"),
    ),
    # On the slope and off the table: a block set at the slope's foot rests on both, and
    # "on the slope" alone would count that.
    goal="(and (support block slope) (not (support block table)) (handempty))",
    distractors=Distractors(CLUTTER, (0, 1), ((0.25, 0.35), (-0.5, -0.3))),
    demo="lay the blocker across the slope, then put the block on the slope just above it; it slides "
         "onto the blocker and stays",
)

# The paper's two compositional tasks (Table 2): solved by chaining the mechanisms above,
# without training of their own.
PUSH_PICK_HOOK = TaskSpec(
    "push-pick-hook", "Push-then-Pick-then-Hook",
    "a thin caliper lies flat (push it over the table's edge to pick it up), and a box lies out of "
    "reach: the caliper, once held, is the hook that pulls the box closer",
    objects=(
        SMALL_TABLE,
        ObjectSpec("tool", Assets(("caliper/0", "caliper/1"), ("caliper/2",), ("caliper/3", "caliper/4")),
                   xy=(0.42, 0.22), yaw=90.0,
                   scale=(0.95, 1.1), role="the caliper: flat, then a hook"),
        replace(OUT_OF_REACH_BOX, xy=(0.92, -0.05)),  # the smaller table ends at x = 1.0
    ),
    goal="(holding target)",
    distractors=Distractors(CLUTTER, (0, 1), ((0.3, 0.5), (-0.4, -0.25))),
    demo="push the caliper over the +y edge, pinch its overhang, use it as a hook to pull the box "
         "closer, put it down, grasp the box",
)

HOOK_SLOPE = TaskSpec(
    "hook-slope", "Hook-then-Place-on-Slope",
    "a soup ladle reaches a box out of reach, which must then rest on a slope where it slides "
    "unless something (the ladle, or a brick) blocks it below",
    objects=(
        TABLE,
        ObjectSpec("tool", Assets(("soup-ladle/0", "soup-ladle/1"), ("soup-ladle/2",), ("soup-ladle/3", "soup-ladle/4")),
                   xy=(0.5, 0.15),
                   scale=(0.9, 1.1), friction=1.5, role="the ladle: a hook, then a blocker"),
        replace(OUT_OF_REACH_BOX, role="the box out of reach, to leave on the slope"),
        ObjectSpec("slope", Assets(("slope/1",), ("slope/2",), ("slope/3",)), xy=(0.6, -0.3), fixed=True,
                   noise_yaw=10.0,
                   role="the slope, rising towards +x"),
        ObjectSpec("brick", Assets(("brick/0", "brick/1"), ("brick/2",), ("brick/3", "brick/4")), xy=(0.36, -0.08),
                   yaw=90.0,
                   role="another possible blocker"),
    ),
    goal="(and (support target slope) (not (support target table)) (handempty))",
    demo="pull the box closer with the ladle, lay the ladle (or the brick) across the slope, put the "
         "box on the slope just above it",
)

TASKS: Dict[str, TaskSpec] = {t.name: t for t in (EDGE, HOOK, LEVER, POKING, COM, SLOPE, PUSH_PICK_HOOK,
                                                  HOOK_SLOPE)}


def get_task(name: str) -> TaskSpec:
    if name not in TASKS:
        raise KeyError(f"unknown task {name!r}; tasks: {', '.join(TASKS)}")
    return TASKS[name]
