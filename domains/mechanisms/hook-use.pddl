; Mechanism hook-use: extracted from the demonstration hook (Hook, instance hook-canonical) by
;   python -m pdsketch_mech.learn extract domains/mechanisms/demos/hook.npz --name hook-use
; Do not edit by hand: re-extract. Generic samplers fill its parameters until `learn train` names a
; learned sampler (:sampler); re-extracting keeps that name.
; Steps (demonstration time):
;   1. (grasp tool table) at 2.53 s
;   2. (move-cont tool target table) at 4.42 s
;   3. (place tool table) at 7.70 s
;   4. (grasp target table) at 11.58 s
; Variables (role: why):
;   ?tool = tool: held while it pushes another object
;   ?target = target: moved by the robot, named by the goal
;   ?support = table: supports the target, tool at the start
(define (domain hook-use)
  (:extends "../basis.pddl")
  (:requirements :mechanisms)
  (:mechanism hook-use
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
    :sampler "hook-use.samplers.safetensors"))
