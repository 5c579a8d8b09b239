"""Mechanism extraction (`learning/`): segmentation of the committed recordings by contact
modes, the basis steps they map to, lifting to fragments, and the `learn extract` command.

The expected step sequences below were written from the demo scripts (and the paper's
descriptions of the six mechanisms) before extraction was run on the recordings; steps are
grounded on the demo's objects here, which the extractor itself never reads by name."""
from __future__ import annotations

import os

import pytest

from conftest import ROOT

DEMOS_DIR = os.path.join(ROOT, "domains", "mechanisms", "demos")

# (operator, object arguments...) per committed demonstration.
EXPECTED_STEPS = {
    # push the flat object with the bare (closed) fingers towards the edge, then pinch the overhang
    "edge": [("transit-cont", "flat", "table"), ("grasp", "flat", "table")],
    # the paper's Fig. 3b: grasp the tool, pull the target with it, put the tool back, grasp the target
    "hook": [("grasp", "tool", "table"), ("move-cont", "tool", "target", "table"),
             ("place", "tool", "table"), ("grasp", "target", "table")],
    # put the heavy object on the plate's overhang (the plate tips up), grasp the plate off its ledge
    "lever": [("grasp", "weight", "table"), ("place", "weight", "plate"), ("grasp", "plate", "ledge")],
    # the same contact sequence as Hook: the held stick pushes the block out of the tunnel
    "poking": [("grasp", "tool", "table"), ("move-cont", "tool", "target", "table"),
               ("place", "tool", "table"), ("grasp", "target", "table")],
    # grasp the overhanging plate, put it on the small block
    "com": [("grasp", "flat", "table"), ("place", "flat", "pedestal")],
    # lay the blocker on the slope, then put the block on the slope (it slides onto the blocker)
    "slope-blocker": [("grasp", "blocker", "table"), ("place", "blocker", "slope"),
                      ("grasp", "block", "table"), ("place", "block", "slope")],
}
