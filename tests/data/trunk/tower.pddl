; A tower of three: c on the table, b on c, a on b.
(define (problem tower-of-three)
  (:domain mech-basis)
  (:objects table a b c - item)
  (:init (handempty) (fixed table) (support a table) (support b table) (support c table))
  (:goal (and (support a b) (support b c) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (a :asset "small-block/0" :position (0.40 -0.20 0.016) :on table)
    (b :asset "block/0" :position (0.45 0.20 0.026) :rpy-deg (0 0 30) :on table)
    (c :asset "box/0" :position (0.60 0.0 0.05) :on table)))
