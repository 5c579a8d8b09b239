; Unchock: a slippery cube rests high on a 10-degree slope, beyond the arm's reach, held from
; sliding only by a grippy chock (a box) just below it. Take the chock away and the cube slides
; down onto the table, within reach; then put the cube on the plate.
(define (problem unchock)
  (:domain mech-basis)
  (:objects table slope chock target plate - item)
  (:init (handempty) (fixed table) (fixed slope)
         (support chock slope) (support target slope) (support plate table))
  (:goal (and (support target plate) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (slope :asset "slope/0" :position (0.84 0 0) :fixed)
    (chock :asset "box/0" :position (0.87 0.0) :rpy-deg (0 -10 0) :on slope :friction 1.5 :color (0.85 0.2 0.2 1))
    (target :asset "block/0" :position (0.955 0.0) :rpy-deg (0 -10 0) :on slope :friction 0.2)
    (plate :asset "plate/0" :position (0.45 -0.25) :on table)))
