; Contract set (c), the user's mechanism shelf-pull: the scene of its own demonstration
; (user-mechanism/shelf-pull.pddl): a box on a raised shelf beyond reach, an L-stick on the table,
; the goal that the box rests on the table. The basis operators solve it another way: the L-stick
; pulls the box along the shelf within reach (it stays on the shelf), then a pick and place.
(define (problem contract-user-shelf-far)
  (:domain mech-basis)
  (:objects table shelf hook box - item)
  (:init (handempty) (fixed table) (fixed shelf) (support hook table) (support box shelf))
  (:goal (and (support box table) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0.0 0.0) :fixed)
    (shelf :asset "brick/0" :position (1.0 0.0 0.06) :rpy-deg (0 0 90) :scale 2 :fixed)
    (hook :asset "l-stick/0" :position (0.5 0.15) :on table)
    (box :asset "box/0" :position (1.0 0.0) :rpy-deg (0 0 90) :on shelf)))
