; Push across a gap: a box lies on the table beyond the arm's reach; the goal is that it rests on a
; second, fixed table (the platform), 2 cm beyond the first one's far edge (x = 1.0). A stick held
; by one end pushes it across.
(define (problem gap-push)
  (:domain mech-basis)
  (:objects table platform stick target - item)
  (:init (handempty) (fixed table) (fixed platform) (support stick table) (support target table))
  (:goal (and (support target platform) (handempty)))
  (:scene
    (table :asset "table/1" :position (0.6 0.0 0.0) :fixed)
    (platform :asset "table/1" :position (1.42 0.0 0.0) :fixed)
    (stick :asset "wooden-stick/0" :position (0.45 -0.2) :on table)
    (target :asset "box/0" :position (0.86 0.0) :rpy-deg (0 0 90) :on table)))
