; Contract set (a): a box from the far left onto a plate at the far right, past a row of a
; brick, a tall block and an apple standing between them.
(define (problem contract-move-past)
  (:domain mech-basis)
  (:objects table box plate brick tall apple - item)
  (:init (handempty) (fixed table) (support box table) (support plate table) (support brick table)
         (support tall table) (support apple table))
  (:goal (and (support box plate) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (box :asset "box/1" :position (0.48 0.32) :rpy-deg (0 0 90) :on table)
    (plate :asset "plate/0" :position (0.48 -0.3) :on table)
    (brick :asset "brick/0" :position (0.58 0.02) :rpy-deg (0 0 90) :on table)
    (tall :asset "block/2" :position (0.42 0.0) :on table)
    (apple :asset "apple/2" :position (0.34 0.05) :on table)))
