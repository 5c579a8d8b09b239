; New contract scene (session 77): a calculator onto a plate; a slope and a spatula stand by
; (slope and tool mechanisms look applicable; the goal needs none of them).
(define (problem s77-calc-plate-slope)
  (:domain mech-basis)
  (:objects table slope plate calc spat - item)
  (:init (handempty) (fixed table) (fixed slope) (support plate table) (support calc table) (support spat table))
  (:goal (and (support calc plate) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (slope :asset "slope/1" :position (0.62 0.26 0) :rpy-deg (0 0 10) :fixed :on table)
    (plate :asset "plate/2" :position (0.42 -0.28) :on table)
    (calc :asset "calculator/0" :position (0.5 0.02) :rpy-deg (0 0 40) :on table)
    (spat :asset "spatula/0" :position (0.33 0.16) :rpy-deg (0 0 -20) :on table)))
