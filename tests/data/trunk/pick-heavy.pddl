; A heavy object: a 2 kg box, held and lifted.
(define (problem pick-heavy)
  (:domain mech-basis)
  (:objects table box - item)
  (:init (handempty) (fixed table) (support box table))
  (:goal (holding box))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (box :asset "block/1" :position (0.55 0.15 0.03) :rpy-deg (0 0 -25) :mass 2.0 :on table)))
