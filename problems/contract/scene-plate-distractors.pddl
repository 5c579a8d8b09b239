; Contract set (a): a 4.5 cm block onto a plate, past an apple, a banana and a walnut.
(define (problem contract-plate-distractors)
  (:domain mech-basis)
  (:objects table block plate apple banana walnut - item)
  (:init (handempty) (fixed table) (support block table) (support plate table) (support apple table)
         (support banana table) (support walnut table))
  (:goal (and (support block plate) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (block :asset "block/1" :position (0.42 0.25) :rpy-deg (0 0 20) :on table :color (0.8 0.2 0.2 1))
    (plate :asset "plate/1" :position (0.5 -0.22) :on table)
    (apple :asset "apple/0" :position (0.45 0.02) :on table)
    (banana :asset "banana/0" :position (0.62 0.1) :rpy-deg (0 0 60) :on table)
    (walnut :asset "walnut/0" :position (0.36 -0.06) :on table)))
