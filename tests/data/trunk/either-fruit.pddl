; A disjunctive goal: hold the apple or the banana, whichever works.
(define (problem either-fruit)
  (:domain mech-basis)
  (:objects table apple banana - item)
  (:init (handempty) (fixed table) (support apple table) (support banana table))
  (:goal (or (holding apple) (holding banana)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (apple :asset "apple/0" :position (0.55 0.1 0.04) :on table)
    (banana :asset "banana/0" :position (0.45 -0.15 0.017) :on table)))
