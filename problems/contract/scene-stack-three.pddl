; Contract set (a): stack three blocks, a on b on c, c where it lies.
(define (problem contract-stack-three)
  (:domain mech-basis)
  (:objects table a b c - item)
  (:init (handempty) (fixed table) (support a table) (support b table) (support c table))
  (:goal (and (support a b) (support b c) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (a :asset "block/1" :position (0.4 0.22) :rpy-deg (0 0 15) :on table :color (0.8 0.2 0.2 1))
    (b :asset "block/0" :position (0.55 0.05) :rpy-deg (0 0 -25) :on table :color (0.2 0.7 0.2 1))
    (c :asset "block/0" :position (0.45 -0.2) :on table :color (0.2 0.4 0.8 1))))
