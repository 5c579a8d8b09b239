; Contract set (a): a tall block onto a box, with an L-stick and a wooden stick lying within
; reach (the tool mechanisms' preconditions hold; the goal needs none of them).
(define (problem contract-tools-around)
  (:domain mech-basis)
  (:objects table tall box hook stick - item)
  (:init (handempty) (fixed table) (support tall table) (support box table) (support hook table)
         (support stick table))
  (:goal (and (support tall box) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (tall :asset "block/2" :position (0.4 -0.22) :rpy-deg (0 0 10) :on table :color (0.8 0.2 0.2 1))
    (box :asset "box/2" :position (0.6 0.15) :rpy-deg (0 0 90) :on table)
    (hook :asset "l-stick/0" :position (0.4 -0.01) :on table)
    (stick :asset "wooden-stick/1" :position (0.62 -0.18) :rpy-deg (0 0 70) :on table)))
