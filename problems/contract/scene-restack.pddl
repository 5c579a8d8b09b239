; Contract set (a): a block starts on a brick; it must stand on the other block instead.
(define (problem contract-restack)
  (:domain mech-basis)
  (:objects table brick a b - item)
  (:init (handempty) (fixed table) (support brick table) (support a brick) (support b table))
  (:goal (and (support a b) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (brick :asset "brick/1" :position (0.5 0.15) :rpy-deg (0 0 80) :on table)
    (a :asset "block/0" :position (0.5 0.15) :rpy-deg (0 0 35) :on brick :color (0.8 0.2 0.2 1))
    (b :asset "block/2" :position (0.42 -0.18) :on table :color (0.2 0.4 0.8 1))))
