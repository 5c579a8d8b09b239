; Pick and place onto a plate that sits close to a wall of other objects.
(define (problem walnut-onto-plate)
  (:domain mech-basis)
  (:objects table walnut plate box - item)
  (:init (handempty) (fixed table) (support walnut table) (support plate table) (support box table))
  (:goal (and (support walnut plate) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (walnut :asset "walnut/0" :position (0.40 -0.2 0.018) :on table)
    (plate :asset "plate/1" :position (0.58 0.1 0.006) :on table)
    (box :asset "box/0" :position (0.58 -0.08 0.05) :on table)))
