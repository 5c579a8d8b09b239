; Mechanism poking: extracted from the demonstration poking (Poking, instance poking-canonical) by
;   python -m pdsketch_mech.learn extract domains/mechanisms/demos/poking.npz --name poking
; Do not edit by hand: re-extract. Generic samplers fill its parameters until `learn train` names a
; learned sampler (:sampler); re-extracting keeps that name.
; Steps (demonstration time):
;   1. (grasp tool table) at 1.28 s
;   2. (move-cont tool target table) at 3.20 s
;   3. (place tool table) at 6.13 s
;   4. (grasp target table) at 8.23 s
; Variables (role: why):
;   ?tool = tool: held while it pushes another object
;   ?target = target: moved by the robot, named by the goal
;   ?support = table: supports the target, tool at the start
(define (domain poking)
  (:extends "../basis.pddl")
  (:requirements :mechanisms)
  (:mechanism poking
    :parameters (?tool ?target ?support - item ?g1 - grasp ?t1 - traj ?c - contact ?t2 - traj ?p - placement ?t3 - traj ?g2 - grasp ?t4 - traj)
    :precondition (and
      (handempty)
      (support ?tool ?support)
      (support ?target ?support)
      (not (= ?tool ?target)))
    :certified (holding ?target)
    :actions (
      (grasp ?tool ?support ?g1 ?t1)
      (move-cont ?tool ?target ?support ?c ?t2)
      (place ?tool ?support ?p ?t3)
      (grasp ?target ?support ?g2 ?t4))
    :sampler "poking.samplers.safetensors"))
