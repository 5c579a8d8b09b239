; Contract set (c), the user's mechanism shelf-pull: a box on a low shelf (a fixed brick) must go
; onto a plate on the table; a soup ladle lies beside. shelf-pull's precondition holds (its pull
; could bring the box down first); a pick and place does it.
(define (problem contract-user-shelf-plate)
  (:domain mech-basis)
  (:objects table shelf ladle box plate - item)
  (:init (handempty) (fixed table) (fixed shelf) (support ladle table) (support box shelf) (support plate table))
  (:goal (and (support box plate) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0.0 0.0) :fixed)
    (shelf :asset "brick/1" :position (0.55 0.22 0.0375) :scale 1.5 :fixed)
    (ladle :asset "soup-ladle/0" :position (0.62 -0.05) :on table)
    (box :asset "box/1" :position (0.55 0.22) :on shelf)
    (plate :asset "plate/0" :position (0.45 -0.25) :on table)))
