; The paper's Center-of-Mass task: leave a long object resting on a small block. Only a
; placement with its centre of mass over the block is stable; others tip off.
(define (problem com-stick-on-block)
  (:domain mech-basis)
  (:objects table stick pedestal - item)
  (:init (handempty) (fixed table) (support stick table) (support pedestal table))
  (:goal (and (support stick pedestal) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (stick :asset "wooden-stick/0" :position (0.45 -0.2 0.011) :rpy-deg (0 0 70) :on table)
    (pedestal :asset "small-block/0" :position (0.5 0.2 0.016) :on table :mass 1.0)))
