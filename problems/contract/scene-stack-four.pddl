; Fresh contract scene: four blocks, d on c on b on a, a where it lies.
(define (problem fresh-stack-four)
  (:domain mech-basis)
  (:objects table a b c d - item)
  (:init (handempty) (fixed table) (support a table) (support b table) (support c table) (support d table))
  (:goal (and (support d c) (support c b) (support b a) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (a :asset "block/0" :position (0.5 0.0) :rpy-deg (0 0 10) :on table)
    (b :asset "block/0" :position (0.38 0.25) :rpy-deg (0 0 -30) :on table)
    (c :asset "block/1" :position (0.62 -0.22) :rpy-deg (0 0 45) :on table)
    (d :asset "block/1" :position (0.35 -0.3) :on table)))
