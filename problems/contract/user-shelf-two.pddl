; Contract set (c), the user's mechanism shelf-pull: two blocks on a raised shelf (a fixed brick);
; one must come down onto the table, the other stay up. A pull could bring down both; a pick and
; place brings down the one.
(define (problem contract-user-shelf-two)
  (:domain mech-basis)
  (:objects table shelf hook a b - item)
  (:init (handempty) (fixed table) (fixed shelf) (support hook table) (support a shelf) (support b shelf))
  (:goal (and (support a table) (support b shelf) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0.0 0.0) :fixed)
    (shelf :asset "brick/0" :position (0.62 0.0 0.06) :rpy-deg (0 0 90) :scale 2 :fixed)
    (hook :asset "l-stick/0" :position (0.4 0.25) :on table)
    (a :asset "block/0" :position (0.62 -0.1) :on shelf :color (0.8 0.2 0.2 1))
    (b :asset "block/1" :position (0.62 0.1) :rpy-deg (0 0 30) :on shelf :color (0.2 0.4 0.8 1))))
