; A three-block tower: c on b on a.
(define (problem tower-three)
  (:domain mech-basis)
  (:objects table a b c - item)
  (:init (handempty) (fixed table) (support a table) (support b table) (support c table))
  (:goal (and (support b a) (support c b) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (a :asset "block/0" :position (0.5 0.15 0.026) :rpy-deg (0 0 10) :on table)
    (b :asset "block/0" :position (0.45 -0.1 0.026) :rpy-deg (0 0 -20) :on table)
    (c :asset "block/0" :position (0.6 -0.25 0.026) :on table)))
