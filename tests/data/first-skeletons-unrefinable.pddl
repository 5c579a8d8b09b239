; The first three ways to the goal put block a on a block beyond the arm's reach: each grasp
; of a works, each placement finds nothing. The fourth stacks b on a, within reach.
(define (problem first-skeletons-unrefinable)
  (:domain mech-basis)
  (:objects table far1 far2 far3 a b - item)
  (:init (handempty) (fixed table) (support far1 table) (support far2 table) (support far3 table)
         (support a table) (support b table))
  (:goal (or (support a far1) (support a far2) (support a far3) (support b a)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (far1 :asset "block/0" :position (1.05 0.3 0.026) :on table)
    (far2 :asset "block/0" :position (1.05 0.0 0.026) :on table)
    (far3 :asset "block/0" :position (1.05 -0.3 0.026) :on table)
    (a :asset "block/0" :position (0.45 0.1 0.026) :on table)
    (b :asset "block/0" :position (0.45 -0.1 0.026) :on table)))
