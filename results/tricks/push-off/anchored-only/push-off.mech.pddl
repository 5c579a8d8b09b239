; Mechanism push-off: extracted from the demonstration push-off (push-off, instance push-off) by
;   python -m pdsketch_mech.learn extract problems/tricks/push-off/push-off.npz --name push-off --out problems/tricks/push-off/push-off.mech.pddl
; Do not edit by hand: re-extract. Generic samplers fill its parameters until `learn train` names a
; learned sampler (:sampler); re-extracting keeps that name.
; Steps (demonstration time):
;   1. (transit-cont box block) at 1.93 s
; Variables (role: why):
;   ?target = box: moved by the robot, named by the goal
;   ?support = block: supports the target at the start
;   ?object = plate: named by the goal
(define (domain push-off)
  (:extends "basis")
  (:requirements :mechanisms)
  (:mechanism push-off
    :parameters (?target ?support ?object - item ?c - contact ?t - traj)
    :precondition (and (handempty) (support ?target ?support))
    :certified (support ?target ?object)
    :actions (
      (transit-cont ?target ?support ?c ?t))))
