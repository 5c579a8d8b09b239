; The paper's Edge task: a plate lies flat in the middle of the table, too flat to grasp
; from the top; pushed until it overhangs the table's edge, it can be grasped by its rim.
(define (problem edge-plate)
  (:domain mech-basis)
  (:objects table plate - item)
  (:init (handempty) (fixed table) (support plate table))
  (:goal (holding plate))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (plate :asset "plate/0" :position (0.5 0.35 0.0057) :on table)))
