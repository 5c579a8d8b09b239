; The paper's Hook scene: an L-shaped stick within reach, a box beyond the arm's reach.
; The robot's base is at the origin; the table's top is at z = 0 in front of it.
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
    (table :asset "table" :position (0.6 0.0 0.0) :fixed)
    (hook :asset "l-stick/0" :position (0.5 0.15 0.011) :on table)
    (box :asset "box/0" :position (0.95 0.0 0.031) :rpy-deg (0 0 90) :on table :mass 0.2 :friction 0.6)))
