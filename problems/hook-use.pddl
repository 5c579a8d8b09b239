; The paper's Hook scene: an L-shaped stick within reach, a box beyond the arm's reach.
(define (problem hook-use-box)
  (:domain mech-basis)
  (:objects table hook box - item)
  (:init
    (handempty)
    (fixed table)
    (support hook table)
    (support box table))
  (:goal (holding box))
  (:scene
    (table :asset "table" :position (0.0 0.0 0.0) :fixed)
    (hook :asset "l-stick/0" :position (0.45 0.15 0.02) :rpy-deg (0 0 90) :on table)
    (box :asset "block/0" :position (0.95 0.0 0.025) :on table :mass 0.2 :friction 0.6)))
