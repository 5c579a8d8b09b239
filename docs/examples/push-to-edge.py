"""Push a flat object over the table's edge with the closed fingers, then pinch the overhang.

The same demonstration as push-to-edge.demo.json, written against the demonstration API
(docs/demonstrations.md): `demonstrate(hand)` is called with the robot's hand in the scene of
PROBLEM, and every call is simulated step by step.
"""
PROBLEM = "push-to-edge.pddl"


def demonstrate(hand):
    hand.close()                                   # push with the fingertips
    start = hand.point("flat", at="right bottom", offset={"right": 0.03, "up": 0.012})
    hand.move_to(start, closing=[1, 0, 0])
    edge = hand.point("table", at="left top", offset={"right": 0.09})
    hand.line([0, 1, 0], hand.distance_to(edge, [0, 1, 0]))
    hand.line([0, -1, 0], 0.03)
    hand.lift(0.08)
    hand.open()
    overhang = hand.point("flat", at="left", offset={"right": 0.015})
    hand.move_to(overhang, approach=[1, 0, -1], closing=[0, 0, 1], back=0.06)
    hand.grasp("flat")
    hand.lift(0.1)
