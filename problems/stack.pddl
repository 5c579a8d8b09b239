; Stack block a on block b.
(define (problem stack-two-blocks)
  (:domain mech-basis)
  (:objects table a b - item)
  (:init (handempty) (fixed table) (support a table) (support b table))
  (:goal (and (support a b) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (a :asset "block/0" :position (0.45 0.2 0.026) :rpy-deg (0 0 30) :on table :color (0.8 0.2 0.2 1))
    (b :asset "block/0" :position (0.5 -0.15 0.026) :on table :color (0.2 0.4 0.8 1))))
