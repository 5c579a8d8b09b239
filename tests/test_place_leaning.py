"""A placement counts only if the object rests without the hand (operators/basis.py `place`).

The plan below was found before that check: the ladle hooks the box within reach, and the box
is let go on the slope with nothing below it. It slid after the retreating fingers and came
to rest against them; the contact graph, which leaves the robot out, said it rested on the
slope, the goal held, and the plan replayed. With the arm moved away the box slid 25 cm
off the slope."""
import glob
import os

from pdsketch_mech.commands import replay

from conftest import ROOT

DATA = os.path.join(ROOT, "tests", "data", "lean")
DOMAINS = [os.path.join(ROOT, "domains", "basis.pddl")] + sorted(glob.glob(os.path.join(ROOT, "domains", "mechanisms", "*.pddl")))


def test_a_box_that_leans_on_the_retreating_hand_is_not_placed(capsys):
    status = replay.main([os.path.join(DATA, "hook-slope-dev-0.pddl"),
                          os.path.join(DATA, "box-on-slope-held-by-the-hand.json"), *DOMAINS])
    assert status == 1
    assert "step 5 (place) failed: target leans on the hand once let go" in capsys.readouterr().err
