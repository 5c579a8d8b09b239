; Move a block from the table onto a plate, and let go of it.
(define (problem pick-place-block)
  (:domain mech-basis)
  (:objects table block plate - item)
  (:init (handempty) (fixed table) (support block table) (support plate table))
  (:goal (and (support block plate) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (block :asset "block/0" :position (0.45 -0.2 0.026) :on table)
    (plate :asset "plate/0" :position (0.55 0.2 0.0057) :on table)))
