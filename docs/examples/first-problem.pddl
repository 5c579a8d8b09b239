; A first problem: put the block on the plate, then let go.
; Positions are in metres, in the robot's frame: the base at the origin, x forwards, z up.
(define (problem first-problem)
  (:domain mech-basis)
  (:objects table block plate - item)
  (:init (handempty) (fixed table) (support block table) (support plate table))
  (:goal (and (support block plate) (handempty)))
  (:scene
    ; table/0: its frame is the centre of its top surface, so at z = 0 the top is at z = 0.
    (table :asset "table" :position (0.6 0 0) :fixed)
    ; block/0: a 5 cm cube, aabb z from -0.025 to 0.025: resting z = 0 + 0.025.
    (block :asset "block/0" :position (0.45 0.15 0.025) :rpy-deg (0 0 30) :on table)
    ; plate/0: aabb z from -0.0047 to 0.0103 (its frame is at its centre of mass): z = 0 + 0.0047.
    (plate :asset "plate/0" :position (0.5 -0.15 0.0047) :on table)))
