"""The Panda gripper's shape in its grasp frame (panda_grasptarget: z = approach, y = the
closing axis), for samplers' cheap geometric tests. Measured from the collision shapes in
PyBullet (link AABBs in the grasp frame, less PyBullet's 4 mm margin)."""
from __future__ import annotations

FINGER_HALF_WIDTH = 0.0105   # half a finger's width, along the frame's x axis
FINGER_THICKNESS = 0.01      # a finger's thickness along y, outward from its pad
FINGER_TIP = 0.0072          # how far the fingertips reach past the frame origin along z
FINGER_ROOT = 0.045          # where the fingers leave the hand, behind the origin along z
HAND_UNDERSIDE = 0.039       # the hand's underside (between the fingers), behind the origin along z
# The hand as a box behind the fingers: x across, y along the closing axis, z along the approach.
HAND_BOX = ((-0.032, 0.032), (-0.10, 0.10), (-0.13, -HAND_UNDERSIDE))
FINGER_SPAN = (-FINGER_ROOT, FINGER_TIP)   # a finger along z
