; Fresh contract scene: a box on one plate and a ball on another; the goal swaps them.
(define (problem fresh-swap-plates)
  (:domain mech-basis)
  (:objects table box ball p1 p2 - item)
  (:init (handempty) (fixed table) (support p1 table) (support p2 table) (support box p1) (support ball p2))
  (:goal (and (support box p2) (support ball p1) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (p1 :asset "plate/0" :position (0.45 0.25) :on table)
    (p2 :asset "plate/1" :position (0.5 -0.25) :on table)
    (box :asset "box/0" :position (0.45 0.25) :rpy-deg (0 0 30) :on p1)
    (ball :asset "apple/1" :position (0.5 -0.25) :on p2)))
