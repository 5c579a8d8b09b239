; Contract set (a): an apple into a shallow bowl at the far left.
(define (problem contract-apple-bowl)
  (:domain mech-basis)
  (:objects table apple bowl - item)
  (:init (handempty) (fixed table) (support apple table) (support bowl table))
  (:goal (and (support apple bowl) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (apple :asset "apple/1" :position (0.5 -0.25) :on table)
    (bowl :asset "bowl/2" :position (0.45 0.3) :on table)))
