; Mechanism slope-blocker: extracted from the demonstration slope-blocker (Slope-and-Blocker, instance slope-blocker-canonical) by
;   python -m pdsketch_mech.learn extract domains/mechanisms/demos/slope-blocker.npz --name slope-blocker
; Do not edit by hand: re-extract. Generic samplers fill its parameters until `learn train` names a
; learned sampler (:sampler); re-extracting keeps that name.
; Steps (demonstration time):
;   1. (grasp blocker table) at 1.52 s
;   2. (place blocker slope) at 3.42 s
;   3. (grasp block table) at 7.30 s
;   4. (place block slope) at 11.27 s
; Variables (role: why):
;   ?blocker = blocker: moved, ends up touching the target without supporting it
;   ?target = block: moved by the robot, named by the goal
;   ?support = table: supports the blocker, target at the start
;   ?surface = slope: something is put down on it
(define (domain slope-blocker)
  (:extends "../basis.pddl")
  (:requirements :mechanisms)
  (:mechanism slope-blocker
    :parameters (?blocker ?target ?support ?surface - item ?g1 - grasp ?t1 - traj ?p1 - placement ?t2 - traj ?g2 - grasp ?t3 - traj ?p2 - placement ?t4 - traj)
    :precondition (and
      (handempty)
      (support ?blocker ?support)
      (support ?target ?support)
      (not (= ?blocker ?target)))
    :certified (and (support ?target ?surface) (not (support ?target ?support)) (handempty))
    :actions (
      (grasp ?blocker ?support ?g1 ?t1)
      (place ?blocker ?surface ?p1 ?t2)
      (grasp ?target ?support ?g2 ?t3)
      (place ?target ?surface ?p2 ?t4))
    :sampler "slope-blocker.samplers.safetensors"))
