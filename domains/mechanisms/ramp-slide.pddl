; Mechanism ramp-slide: extracted from the demonstration ramp-slide (ramp-slide, instance ramp-slide) by
;   python -m pdsketch_mech.learn extract domains/mechanisms/demos/ramp-slide.npz --name ramp-slide
; Do not edit by hand: re-extract. Generic samplers fill its parameters until `learn train` names a
; learned sampler (:sampler); re-extracting keeps that name.
; Steps (demonstration time):
;   1. (grasp block table) at 2.42 s
;   2. (place block ramp) at 4.67 s
; Variables (role: why):
;   ?target = block: moved by the robot, named by the goal
;   ?support = table: supports the target at the start
;   ?surface = ramp: something is put down on it
;   ?landing = platform: a moved object comes to rest on it by itself (the goal)
(define (domain ramp-slide)
  (:extends "../basis.pddl")
  (:requirements :mechanisms)
  (:mechanism ramp-slide
    :parameters (?target ?support ?surface ?landing - item ?g - grasp ?t1 - traj ?p - placement ?t2 - traj)
    :precondition (and
      (handempty)
      (support ?target ?support)
      (fixed ?surface)
      (not (= ?surface ?target))
      (not (= ?surface ?support))
      (not (= ?surface ?landing))
      (fixed ?landing)
      (not (= ?landing ?target))
      (not (= ?landing ?support))
      (not (= ?landing ?surface)))
    :certified (and (support ?target ?landing) (handempty))
    :actions (
      (grasp ?target ?support ?g ?t1)
      (place ?target ?surface ?p ?t2))
    :sampler "ramp-slide.samplers.safetensors"))
