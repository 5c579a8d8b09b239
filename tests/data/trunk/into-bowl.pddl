; Pick and place into a bowl: the block must end up supported by the bowl, hand empty.
(define (problem block-into-bowl)
  (:domain mech-basis)
  (:objects table block bowl - item)
  (:init (handempty) (fixed table) (support block table) (support bowl table))
  (:goal (and (support block bowl) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (block :asset "small-block/0" :position (0.42 0.18 0.016) :on table)
    (bowl :asset "bowl/0" :position (0.55 -0.15 0.031) :on table)))
