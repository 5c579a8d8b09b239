; Mechanism gap-push: extracted from the demonstration gap-push (gap-push, instance gap-push) by
;   python -m pdsketch_mech.learn extract domains/mechanisms/demos/gap-push.npz --name gap-push
; Do not edit by hand: re-extract. Generic samplers fill its parameters until `learn train` names a
; learned sampler (:sampler); re-extracting keeps that name.
; Steps (demonstration time):
;   1. (grasp stick table) at 1.40 s
;   2. (move-cont stick target table) at 2.77 s
;   3. (place stick table) at 5.95 s
; Variables (role: why):
;   ?tool = stick: held while it pushes another object
;   ?target = target: moved by the robot, named by the goal
;   ?support = table: supports the target, tool at the start
;   ?landing = platform: a moved object comes to rest on it by itself (the goal)
(define (domain gap-push)
  (:extends "../basis.pddl")
  (:requirements :mechanisms)
  (:mechanism gap-push
    :parameters (?tool ?target ?support ?landing - item ?g - grasp ?t1 - traj ?c - contact ?t2 - traj ?p - placement ?t3 - traj)
    :precondition (and
      (handempty)
      (support ?tool ?support)
      (support ?target ?support)
      (not (= ?tool ?target))
      (fixed ?landing)
      (not (= ?landing ?tool))
      (not (= ?landing ?target))
      (not (= ?landing ?support)))
    :certified (and (support ?target ?landing) (handempty))
    :actions (
      (grasp ?tool ?support ?g ?t1)
      (move-cont ?tool ?target ?support ?c ?t2)
      (place ?tool ?support ?p ?t3))
    :sampler "gap-push.samplers.safetensors"))
