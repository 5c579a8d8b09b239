; A block lies on a raised shelf (a fixed brick, 20 x 40 x 12 cm) beyond the arm's reach, its
; near edge beyond reach too; an L-stick lies on the table. The crook, put behind the block,
; pulls it over the shelf's near edge: it drops onto the table, where it is within reach and
; the robot picks it up. No place on the shelf is within reach.
(define (problem shelf-pick)
  (:domain mech-basis)
  (:objects table shelf hook block - item)
  (:init (handempty) (fixed table) (fixed shelf) (support hook table) (support block shelf))
  (:goal (holding block))
  (:scene
    (table :asset "table" :position (0.6 0.0 0.0) :fixed)
    (shelf :asset "brick/0" :position (0.97 0.0 0.06) :rpy-deg (0 0 90) :scale 2 :fixed)
    (hook :asset "l-stick/0" :position (0.5 0.15) :on table)
    (block :asset "block/0" :position (0.97 0.0) :rpy-deg (0 0 90) :on shelf)))
