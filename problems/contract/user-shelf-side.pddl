; Contract set (c), the user's mechanism shelf-pull: a shelf (a fixed box, 28 x 13 x 16 cm) at the
; robot's right with a block on it, an L-stick and a wooden stick on the table at its left; the
; block must rest on the table. Either stick fits shelf-pull's precondition; a pick and place does it.
(define (problem contract-user-shelf-side)
  (:domain mech-basis)
  (:objects table shelf hook stick block - item)
  (:init (handempty) (fixed table) (fixed shelf) (support hook table) (support stick table) (support block shelf))
  (:goal (and (support block table) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0.0 0.0) :fixed)
    (shelf :asset "box/2" :position (0.5 -0.28 0.08) :scale 2 :fixed)
    (hook :asset "l-stick/1" :position (0.5 0.2) :rpy-deg (0 0 15) :on table)
    (stick :asset "wooden-stick/0" :position (0.45 0.0) :rpy-deg (0 0 -10) :on table)
    (block :asset "block/0" :position (0.5 -0.28) :rpy-deg (0 0 20) :on shelf :color (0.8 0.2 0.2 1))))
