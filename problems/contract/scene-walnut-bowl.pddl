; Contract set (a): a walnut into a bowl; a fork and a spoon lie beside them.
(define (problem contract-walnut-bowl)
  (:domain mech-basis)
  (:objects table walnut bowl fork spoon - item)
  (:init (handempty) (fixed table) (support walnut table) (support bowl table) (support fork table)
         (support spoon table))
  (:goal (and (support walnut bowl) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (walnut :asset "walnut/2" :position (0.38 -0.2) :on table)
    (bowl :asset "bowl/0" :position (0.55 0.18) :on table)
    (fork :asset "fork/0" :position (0.5 -0.02) :rpy-deg (0 0 90) :on table)
    (spoon :asset "spoon/1" :position (0.62 -0.15) :rpy-deg (0 0 10) :on table)))
