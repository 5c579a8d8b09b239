; Contract set (a): on the small table, a small block onto a calculator lying flat (a flat
; object an Edge push could reach for; here it is only the support).
(define (problem contract-small-table)
  (:domain mech-basis)
  (:objects table cube calc - item)
  (:init (handempty) (fixed table) (support cube table) (support calc table))
  (:goal (and (support cube calc) (handempty)))
  (:scene
    (table :asset "table/1" :position (0.6 0 0) :fixed)
    (cube :asset "small-block/0" :position (0.4 -0.2) :on table :color (0.9 0.6 0.1 1))
    (calc :asset "calculator/0" :position (0.52 0.2) :rpy-deg (0 0 90) :on table)))
