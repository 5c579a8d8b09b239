; Poking with a 30 cm tunnel (tunnel/2) instead of the short one: the block sits deeper, so
; a poke may need two strokes (the 5-step skeleton grasp, move-cont, move-cont, place, grasp).
; Made from `python -m pdsketch_mech.envs poking --canonical` with the tunnel's asset changed.
(define (problem poking-long-tunnel)
  (:domain mech-basis)
  (:objects table tunnel target tool - item)
  (:init
    (handempty)
    (fixed table)
    (fixed tunnel)
    (support target table)
    (support tool table))
  (:goal (holding target))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (tunnel :asset "tunnel/2" :position (0.52 0.02 0) :rpy-deg (0 0 90) :fixed :on table)
    (target :asset "block/0" :position (0.52 0.02 0.026) :rpy-deg (0 0 90) :on table)
    (tool :asset "wooden-stick/0" :position (0.34 -0.28 0.011) :rpy-deg (0 0 90) :on table)))
