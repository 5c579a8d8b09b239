; Slide down a ramp: a block lies on the table within reach; the goal is that it rests on a
; platform beyond the arm's reach. A fixed ramp (30 degrees) falls away from the robot from
; its high end at x = 0.72 to the table's far edge (x = 1.0), where the platform begins.
(define (problem ramp-slide)
  (:domain mech-basis)
  (:objects table platform ramp block - item)
  (:init (handempty) (fixed table) (fixed platform) (fixed ramp) (support block table))
  (:goal (and (support block platform) (handempty)))
  (:scene
    (table :asset "table/1" :position (0.6 0.0 0.0) :fixed)
    (platform :asset "table/1" :position (1.40 0.0 0.0) :fixed)
    (ramp :asset "slope/2" :position (0.866 0.0 0.0) :rpy-deg (0 0 180) :fixed)
    (block :asset "block/0" :position (0.45 -0.15) :on table)))
