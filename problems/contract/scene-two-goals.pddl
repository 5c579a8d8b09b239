; Contract set (a): two placements: a ball into a bowl and a block onto a plate.
(define (problem contract-two-goals)
  (:domain mech-basis)
  (:objects table ball bowl block plate - item)
  (:init (handempty) (fixed table) (support ball table) (support bowl table) (support block table)
         (support plate table))
  (:goal (and (support ball bowl) (support block plate) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (ball :asset "ball/1" :position (0.4 0.12) :on table)
    (bowl :asset "bowl/1" :position (0.55 -0.22) :on table)
    (block :asset "block/0" :position (0.58 0.22) :rpy-deg (0 0 45) :on table)
    (plate :asset "plate/0" :position (0.4 -0.05) :on table)))
