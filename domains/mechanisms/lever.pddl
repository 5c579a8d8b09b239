; Mechanism lever: extracted from the demonstration lever (Lever, instance lever-canonical) by
;   python -m pdsketch_mech.learn extract domains/mechanisms/demos/lever.npz --name lever
; Do not edit by hand: re-extract. Generic samplers fill its parameters until `learn train` names a
; learned sampler (:sampler); re-extracting keeps that name.
; Steps (demonstration time):
;   1. (grasp weight table) at 2.42 s
;   2. (place weight plate) at 6.17 s
;   3. (grasp plate ledge) at 9.33 s
; Variables (role: why):
;   ?weight = weight: moved, ends up resting on the target
;   ?target = plate: moved by the robot, named by the goal
;   ?support = table: supports the weight at the start
;   ?target-support = ledge: supports the target at the start
(define (domain lever)
  (:extends "../basis.pddl")
  (:requirements :mechanisms)
  (:mechanism lever
    :parameters (?weight ?target ?support ?target-support - item ?g1 - grasp ?t1 - traj ?p - placement ?t2 - traj ?g2 - grasp ?t3 - traj)
    :precondition (and
      (handempty)
      (support ?weight ?support)
      (support ?target ?target-support)
      (not (= ?weight ?target)))
    :certified (holding ?target)
    :actions (
      (grasp ?weight ?support ?g1 ?t1)
      (place ?weight ?target ?p ?t2)
      (grasp ?target ?target-support ?g2 ?t3))
    :sampler "lever.samplers.safetensors"))
