; Contract set (a): a turned hairbrush onto a plate at the other side of the table.
(define (problem contract-brush-plate)
  (:domain mech-basis)
  (:objects table brush plate - item)
  (:init (handempty) (fixed table) (support brush table) (support plate table))
  (:goal (and (support brush plate) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (brush :asset "hairbrush/0" :position (0.55 0.25) :rpy-deg (0 0 120) :on table)
    (plate :asset "plate/2" :position (0.45 -0.25) :on table)))
