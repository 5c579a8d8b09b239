; Mechanism tip-gap: extracted from the demonstration tip-gap (tip-gap, instance tip-gap) by
;   python -m pdsketch_mech.learn extract problems/tricks/tip-gap/tip-gap.npz --name tip-gap --out problems/tricks/tip-gap/tip-gap.mech.pddl
; Do not edit by hand: re-extract. Generic samplers fill its parameters until `learn train` names a
; learned sampler (:sampler); re-extracting keeps that name.
; Steps (demonstration time):
;   1. (transit-cont brick table) at 2.70 s
; Variables (role: why):
;   ?target = brick: moved by the robot, named by the goal
;   ?support = table: supports the target at the start
;   ?object = platform: named by the goal
(define (domain tip-gap)
  (:extends "basis")
  (:requirements :mechanisms)
  (:mechanism tip-gap
    :parameters (?target ?support ?object - item ?c - contact ?t - traj)
    :precondition (and (handempty) (support ?target ?support))
    :certified (support ?target ?object)
    :actions (
      (transit-cont ?target ?support ?c ?t))
    :sampler "tip-gap.samplers.safetensors"))
