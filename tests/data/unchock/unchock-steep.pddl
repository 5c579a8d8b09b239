; The unchock scene on a steeper slope (20 degrees), another cube: a held-out variation.
(define (problem unchock-steep)
  (:domain mech-basis)
  (:objects table slope chock target plate - item)
  (:init (handempty) (fixed table) (fixed slope)
         (support chock slope) (support target slope) (support plate table))
  (:goal (and (support target plate) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (slope :asset "slope/1" :position (0.855 0.0 0) :fixed)
    (chock :asset "box/0" :position (0.875 0.0) :rpy-deg (0 -20 0) :on slope :friction 1.5 :color (0.85 0.2 0.2 1))
    (target :asset "block/1" :position (0.9525 0.0) :rpy-deg (0 -20 0) :on slope :friction 0.2 )
    (plate :asset "plate/0" :position (0.45 -0.28) :on table)))
