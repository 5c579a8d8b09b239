; Contract set (c), the user's mechanism shelf-pull (user-mechanism/): its scene moved within reach.
; A box on a raised shelf (a fixed brick, 20 x 40 x 12 cm) and an L-stick on the table: shelf-pull's
; precondition holds and it certifies the goal, but a grasp of the box and a place on the table do it.
(define (problem contract-user-shelf-near)
  (:domain mech-basis)
  (:objects table shelf hook box - item)
  (:init (handempty) (fixed table) (fixed shelf) (support hook table) (support box shelf))
  (:goal (and (support box table) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0.0 0.0) :fixed)
    (shelf :asset "brick/0" :position (0.6 0.1 0.06) :rpy-deg (0 0 90) :scale 2 :fixed)
    (hook :asset "l-stick/0" :position (0.45 -0.2) :on table)
    (box :asset "box/0" :position (0.6 0.12) :rpy-deg (0 0 90) :on shelf)))
