; Mechanism edge: extracted from the demonstration edge (Edge, instance edge-canonical) by
;   python -m pdsketch_mech.learn extract domains/mechanisms/demos/edge.npz --name edge
; Do not edit by hand: re-extract. Generic samplers fill its parameters until `learn train` names a
; learned sampler (:sampler); re-extracting keeps that name.
; Steps (demonstration time):
;   1. (transit-cont flat table) at 1.93 s
;   2. (grasp flat table) at 5.95 s
; Variables (role: why):
;   ?target = flat: moved by the robot, named by the goal
;   ?support = table: supports the target at the start
(define (domain edge)
  (:extends "../basis.pddl")
  (:requirements :mechanisms)
  (:mechanism edge
    :parameters (?target ?support - item ?c - contact ?t1 - traj ?g - grasp ?t2 - traj)
    :precondition (and (handempty) (support ?target ?support))
    :certified (holding ?target)
    :actions (
      (transit-cont ?target ?support ?c ?t1)
      (grasp ?target ?support ?g ?t2))
    :sampler "edge.samplers.safetensors"))
