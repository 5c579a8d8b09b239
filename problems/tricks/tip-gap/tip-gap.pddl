; A brick stands on its end at the table's far edge, too wide to grasp (8 x 12 cm across); a
; second table (the platform) stands 10 cm beyond, out of reach. Pushed near its top, the brick
; tips over across the gap and comes to rest on the platform.
(define (problem tip-gap)
  (:domain mech-basis)
  (:objects table platform brick - item)
  (:init (handempty) (fixed table) (fixed platform) (support brick table))
  (:goal (support brick platform))
  (:scene
    (table :asset "table/1" :position (0.40 0.0 0.0) :fixed)
    (platform :asset "table/1" :position (1.30 0.0 0.0) :fixed)
    (brick :asset "brick/2" :position (0.755 0.0) :rpy-deg (0 90 0) :scale 1.2 :on table)))
