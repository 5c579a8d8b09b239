; A box too wide to grasp (8.5 cm across at its narrowest) lies on a raised block (a fixed
; brick, 20 x 40 x 12 cm); a plate lies on the table beside the block. Pushed sideways with the
; closed fingers, the box slides off the block's side and drops onto the plate.
(define (problem push-off)
  (:domain mech-basis)
  (:objects table block plate box - item)
  (:init (handempty) (fixed table) (fixed block) (support plate table) (support box block))
  (:goal (support box plate))
  (:scene
    (table :asset "table" :position (0.6 0.0 0.0) :fixed)
    (block :asset "brick/0" :position (0.55 0.0 0.06) :scale 2 :fixed)
    (plate :asset "plate/0" :position (0.55 0.235) :on table)
    (box :asset "box/2" :position (0.55 0.0) :scale 1.3 :on block)))
