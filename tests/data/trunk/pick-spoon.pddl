; A thin object: pick a spoon lying on the table (1.5 cm thick handle).
(define (problem pick-spoon)
  (:domain mech-basis)
  (:objects table spoon - item)
  (:init (handempty) (fixed table) (support spoon table))
  (:goal (holding spoon))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (spoon :asset "spoon/0" :position (0.48 -0.12 0.0085) :rpy-deg (0 0 35) :on table)))
