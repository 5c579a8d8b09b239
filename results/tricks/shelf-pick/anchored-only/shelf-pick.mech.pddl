; Mechanism shelf-pick: extracted from the demonstration shelf-pick (shelf-pick, instance shelf-pick) by
;   python -m pdsketch_mech.learn extract problems/tricks/shelf-pick/shelf-pick.npz --name shelf-pick --out problems/tricks/shelf-pick/shelf-pick.mech.pddl
; Do not edit by hand: re-extract. Generic samplers fill its parameters until `learn train` names a
; learned sampler (:sampler); re-extracting keeps that name.
; Steps (demonstration time):
;   1. (grasp hook table) at 2.43 s
;   2. (move-cont hook block shelf) at 4.50 s
;      then physics: (support block table), no longer (support block shelf)
;   3. (place hook table) at 9.53 s
;   4. (grasp block table) at 14.10 s
; Variables (role: why):
;   ?tool = hook: held while it pushes another object
;   ?target = block: moved by the robot, named by the goal
;   ?support = table: supports the tool at the start
;   ?target-support = shelf: supports the target at the start
(define (domain shelf-pick)
  (:extends "basis")
  (:requirements :mechanisms)
  (:mechanism shelf-pick
    :parameters (?tool ?target ?support ?target-support - item ?g1 - grasp ?t1 - traj ?c - contact ?t2 - traj ?p - placement ?t3 - traj ?g2 - grasp ?t4 - traj)
    :precondition (and
      (handempty)
      (support ?tool ?support)
      (support ?target ?target-support)
      (not (= ?tool ?target))
      (not (= ?support ?target-support)))
    :certified (holding ?target)
    :actions (
      (grasp ?tool ?support ?g1 ?t1)
      (move-cont ?tool ?target ?target-support ?c ?t2)
        :then (and (support ?target ?support) (not (support ?target ?target-support)))
      (place ?tool ?support ?p ?t3)
      (grasp ?target ?support ?g2 ?t4))))
