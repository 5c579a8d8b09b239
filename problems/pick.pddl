; Pick up a block from the table.
(define (problem pick-block)
  (:domain mech-basis)
  (:objects table block - item)
  (:init (handempty) (fixed table) (support block table))
  (:goal (holding block))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (block :asset "block/0" :position (0.5 0.1 0.026) :rpy-deg (0 0 20) :on table)))
