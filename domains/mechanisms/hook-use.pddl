; Hook-use (paper Fig. 3b): grasp a tool, pull the out-of-reach target closer with it,
; put the tool back, and grasp the target. Hand-written; until a sampler is learned for it
; (`:sampler "checkpoint.pt"`), the planner fills its parameters with the generic samplers.
(define (domain hook-use)
  (:extends "../basis.pddl")
  (:requirements :mechanisms)
  (:mechanism hook-use
    :parameters (?tool - item ?target - item ?support - item
                 ?g1 - grasp ?t1 - traj
                 ?c - contact ?t2 - traj
                 ?p - placement ?t3 - traj
                 ?g2 - grasp ?t4 - traj)
    :precondition (and (handempty) (support ?tool ?support) (support ?target ?support)
                       (not (= ?tool ?target)))
    :certified (holding ?target)
    :actions (
      (grasp ?tool ?support ?g1 ?t1)
      (move-cont ?tool ?target ?support ?c ?t2)
      (place ?tool ?support ?p ?t3)
      (grasp ?target ?support ?g2 ?t4))))
