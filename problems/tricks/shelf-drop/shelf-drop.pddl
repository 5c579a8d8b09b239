; A box lies on a raised shelf (a fixed brick, 20 x 40 x 12 cm) beyond the arm's reach, its
; near edge beyond reach too; an L-stick lies on the table. The crook, put behind the box,
; pulls it over the shelf's near edge: it drops onto the table. No place on the shelf is
; within reach, so no pull along the shelf followed by a pick and place does it.
(define (problem shelf-drop)
  (:domain mech-basis)
  (:objects table shelf hook box - item)
  (:init (handempty) (fixed table) (fixed shelf) (support hook table) (support box shelf))
  (:goal (and (support box table) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0.0 0.0) :fixed)
    (shelf :asset "brick/0" :position (1.06 0.0 0.06) :rpy-deg (0 0 90) :scale 2 :fixed)
    (hook :asset "l-stick/0" :position (0.5 0.15) :on table)
    (box :asset "box/0" :position (1.06 0.0) :rpy-deg (0 0 90) :on shelf)))
