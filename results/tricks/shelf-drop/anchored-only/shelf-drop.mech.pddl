; Mechanism shelf-drop: extracted from the demonstration shelf-drop (shelf-drop, instance shelf-drop) by
;   python -m pdsketch_mech.learn extract problems/tricks/shelf-drop/shelf-drop.npz --name shelf-drop --out problems/tricks/shelf-drop/shelf-drop.mech.pddl
; Do not edit by hand: re-extract. Generic samplers fill its parameters until `learn train` names a
; learned sampler (:sampler); re-extracting keeps that name.
; Steps (demonstration time):
;   1. (grasp hook table) at 2.43 s
;   2. (move-cont hook box shelf) at 5.23 s
;   3. (place hook table) at 10.18 s
; Variables (role: why):
;   ?tool = hook: held while it pushes another object
;   ?target = box: moved by the robot, named by the goal
;   ?support = table: supports the tool at the start
;   ?target-support = shelf: supports the target at the start
(define (domain shelf-drop)
  (:extends "basis")
  (:requirements :mechanisms)
  (:mechanism shelf-drop
    :parameters (?tool ?target ?support ?target-support - item ?g - grasp ?t1 - traj ?c - contact ?t2 - traj ?p - placement ?t3 - traj)
    :precondition (and
      (handempty)
      (support ?tool ?support)
      (support ?target ?target-support)
      (not (= ?tool ?target)))
    :certified (and (support ?target ?support) (handempty))
    :actions (
      (grasp ?tool ?support ?g ?t1)
      (move-cont ?tool ?target ?target-support ?c ?t2)
      (place ?tool ?support ?p ?t3))))
