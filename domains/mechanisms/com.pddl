; Mechanism com: extracted from the demonstration com (Center-of-Mass, instance com-canonical) by
;   python -m pdsketch_mech.learn extract domains/mechanisms/demos/com.npz --name com
; Do not edit by hand: re-extract. Generic samplers fill its parameters until `learn train` names a
; learned sampler (:sampler); re-extracting keeps that name.
; Steps (demonstration time):
;   1. (grasp flat table) at 1.70 s
;   2. (place flat pedestal) at 3.33 s
; Variables (role: why):
;   ?target = flat: moved by the robot, named by the goal
;   ?support = table: supports the target at the start
;   ?surface = pedestal: something is put down on it
(define (domain com)
  (:extends "../basis.pddl")
  (:requirements :mechanisms)
  (:mechanism com
    :parameters (?target ?support ?surface - item ?g - grasp ?t1 - traj ?p - placement ?t2 - traj)
    :precondition (and (handempty) (support ?target ?support) (support ?surface ?support))
    :certified (and (support ?target ?surface) (not (support ?target ?support)) (handempty))
    :actions (
      (grasp ?target ?support ?g ?t1)
      (place ?target ?surface ?p ?t2))
    :sampler "com.samplers.safetensors"))
