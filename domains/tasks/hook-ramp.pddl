; Hook-then-Ramp: a box lies beyond reach at the table's far right; it must end on a platform
; beyond reach behind the table's far left, below a ramp that falls away from the robot. No
; push reaches the platform from where the box starts: a tool pulls it within reach first,
; then it is let go on the ramp.
(define (problem hook-ramp)
  (:domain mech-basis)
  (:objects table platform ramp tool target - item)
  (:init (handempty) (fixed table) (fixed platform) (fixed ramp) (support tool table) (support target table))
  (:goal (and (support target platform) (handempty)))
  (:scene
    (table :asset "table/1" :position (0.6 0.0 0.0) :fixed)
    (platform :asset "table/1" :position (1.52 0.35 0.0) :rpy-deg (0 0 90) :fixed)
    (ramp :asset "slope/2" :position (0.866 0.2 0.0) :rpy-deg (0 0 180) :fixed)
    (tool :asset "l-stick/0" :position (0.45 -0.1) :on table)
    (target :asset "box/0" :position (0.88 -0.35) :rpy-deg (0 0 90) :on table :mass 0.2 :friction 0.6)))
