; A calculator lies flat on the table: too flat for the fingers to get around it. Pushed
; over the table's +y edge (y = 0.5), it can be pinched by the part that overhangs.
(define (problem push-to-edge)
  (:domain mech-basis)
  (:objects table flat - item)
  (:init (handempty) (fixed table) (support flat table))
  (:goal (holding flat))
  (:scene
    (table :asset "table/1" :position (0.6 0.0 0.0) :fixed)
    (flat :asset "calculator/0" :position (0.48 0.22) :rpy-deg (0 0 90) :on table)))
