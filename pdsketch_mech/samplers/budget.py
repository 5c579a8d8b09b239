"""How much work the samplers may do: every search budget of the generic and learned samplers.

A sampler is built with a `SamplerBudget` (`GENERIC_SAMPLERS[name](budget)`, or a keyword with
this default) and reads its budgets from it, never from module constants, so that one object
says how hard a plan tries. A budget bounds work (proposals verified per visit, IK restarts,
collision checks, batch and pool sizes) or steers how the learned samplers spend it; what a
valid grasp, placement or contact *is* (gripper sizes, gaps, clearances, angle thresholds) is
geometry and stays beside the code that tests it.

The defaults are the values the samplers were tuned with (results/HISTORY.md records the
measurements behind several: IK restarts, batch sizes, refills); the same budget and seed
give the same plan.
"""
from __future__ import annotations

from dataclasses import dataclass, fields


@dataclass(frozen=True)
class SamplerBudget:
    """Search budgets of the samplers (counts unless a unit is given)."""

    # --- every generic sampler -----------------------------------------------------------
    # Proposals one visit of a step verifies at most, for a sampler with no field of its own
    # below: the placement sampler's (and a sampler written outside this package). The
    # adaptive planner revisits steps, so a modest budget that fails fast beats an exhaustive one.
    proposals: int = 120
    # Proposals one direct call of sample_grasps / sample_placements / sample_contacts
    # examines when its caller gives no `max_attempts` (tests and scripts; the planner draws
    # through the samplers' own visit budgets).
    sample_attempts: int = 300

    # --- grasps (grasp.py) ------------------------------------------------------------------
    # Proposals a visit verifies: fewer than `proposals`, as proposals have already passed
    # the cheap geometric tests.
    grasp_proposals: int = 60
    # Surface points examined per allowed proposal, however few of them pass the cheap tests
    # (a shape with no feasible grasp ends the proposer after this many times the budget).
    grasp_points_per_proposal: int = 6
    # Surface points drawn from the pool per batch of the cheap tests (one ray cast each).
    grasp_batch: int = 32
    # Surface points of a shape whose antipodal partners are found once and shared by every
    # proposal of the process (drawn with seed 0; a partner's ray is cast when first drawn).
    grasp_pool_points: int = 4096
    # Approach angles about the closing axis examined per antipodal pair (random offset).
    grasp_angles: int = 12
    # IK restarts for a grasp and for its pre-grasp: a hard pose is dropped, drawing another
    # candidate is cheaper (10 restarts keep ~92 % of the poses IK's default 30 finds, in
    # about half the time).
    grasp_ik_restarts: int = 10

    # --- placements (placement.py) ----------------------------------------------------------
    # IK restarts for the arm holding the object at a placement (the pre-place pose is then
    # solved seeded from it, with IK's default).
    placement_ik_restarts: int = 10
    # Times a placement sinking into relief (a dish's rim, a bowl's wall) is raised before it
    # is given up (each raise by the depth found; at most placement.RISE metres in all).
    placement_rise_steps: int = 6

    # --- contacts (contact.py) --------------------------------------------------------------
    # Proposals a visit verifies.
    contact_proposals: int = 60
    # Target surface points drawn at a time (the scene is re-read between batches).
    contact_batch: int = 32
    # Surface points of a held tool drawn once per proposer call, the tool points contacts
    # are made with.
    contact_tool_points: int = 2048
    # Turns of a held tool about the support normal examined per (tool point, target point)
    # pair (random offset).
    contact_yaws: int = 16
    # Tool poses kept per point pair, of those passing the cheap tests (verification tries
    # them in turn).
    contact_poses_per_point: int = 2
    # How much likelier (1 + this, at most) a pull towards the robot is drawn than a push away,
    # for a target the hand cannot reach from above: only pulls bring it within reach. Reads
    # reach, not what the object is (results/HISTORY.md, session 71: Hook needs it on dev).
    contact_pull_bias: float = 3.0
    # IK restarts for the arm at a contact: fewer than IK's default 30, since a failure costs
    # ~70 ms at 30 and most failures are out of reach (the pre-contact pose is solved seeded,
    # with IK's default).
    contact_ik_restarts: int = 10

    # --- trajectories (trajectory.py) -------------------------------------------------------
    # Push distances proposed per visit of a push (each one planned and verified).
    push_proposals: int = 1
    # Random target poses a visit of a free or held move tries (IK, then RRT, each).
    free_motion_proposals: int = 20
    # Collision checks one RRT query to a grasp's, placement's or push's pre-pose may use
    # (~1 s; world/motion.py keeps the same default, MAX_CHECKS, for its other callers).
    motion_checks: int = 8000
    # Collision checks one RRT query of a free or held move may use: half of `motion_checks`,
    # as its target is one of many random ones a visit tries, and a hard one is given up sooner.
    free_motion_checks: int = 4000

    # --- learned samplers (learned/ranked.py, learned/walk.py) ------------------------------
    # Proposals scored together. Not more: the best of many proposals by a classifier's score
    # is the one it overrates most (the optimizer's curse).
    learned_batch: int = 16
    # Verified values scored together by a classifier trained on values only (checkpoint
    # schema /1): grasps, contacts and placements are verified in the generic order until
    # this many are found.
    learned_pool: int = 8
    # Probability (0..1) that the next proposal verified is a random one of the batch rather
    # than the best left, while the plan has no evidence that random picks do better (the
    # floor of learned/trust.py's adaptive chance).
    learned_explore: float = 0.2
    # Further calls of a generic proposer that ran dry before a batch was full.
    learned_refills: int = 8
    # Fresh batches a walk may add when the best left of its batch is hopeless.
    learned_top_ups: int = 3
    # Nats: a learned pick this far below the best score the walk has seen is hopeless (the
    # walk tops the batch up before verifying it).
    learned_top_up_gap: float = 5.0
    # Yielded values kept awaiting their step's outcome (for the adaptive chance), at most;
    # the oldest are forgotten beyond it.
    learned_pending: int = 1024
    # Standard deviations (x or y) a fixed object the classifier reads may stand from the
    # mean of its training inputs before the step draws from the generic sampler instead.
    learned_extrapolation_z: float = 10.0

    # --- demonstration anchors (anchored.py) -------------------------------------------------
    # Proposals spread around a mechanism's demonstrated values a visit mixes in with the
    # generic ones at most (a contact: this many in each of its two frames).
    anchor_proposals: int = 6
    # Chance: after the demonstrated values (proposed once per situation), that a proposal is
    # spread around them rather than drawn from the generic sampler.
    anchor_share: float = 0.5
    # Factor: the most a demonstrated offset is stretched (or shrunk, by its inverse) to
    # another object's bounding box, per axis.
    anchor_max_scale: float = 2.0
    # Radians: the spread of a transferred grasp's turn about its approach axis, or a contact's
    # about the vertical through the contact point (standard deviation).
    anchor_turn: float = 0.15
    # Metres: the spread of a transferred grasp's or contact's position (standard deviation).
    anchor_shift: float = 0.01
    # Ratio: the spread of a transferred push distance, relative (standard deviation).
    anchor_distance_spread: float = 0.2

    def __post_init__(self) -> None:
        # A negative count would silently mean "none"; a chance outside 0..1 is a typo.
        for item in fields(self):
            if getattr(self, item.name) < 0:
                raise ValueError(f"SamplerBudget.{item.name} must not be negative")
        if self.learned_explore > 1.0:
            raise ValueError("SamplerBudget.learned_explore is a probability (0..1)")
