; New contract scene (session 77): a small block onto a box, with a ledge and a hammer nearby.
(define (problem s77-block-box-ledge)
  (:domain mech-basis)
  (:objects table ledge box blk hammer - item)
  (:init (handempty) (fixed table) (fixed ledge) (support box table) (support blk table) (support hammer table))
  (:goal (and (support blk box) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (ledge :asset "ledge/0" :position (0.7 -0.3 0) :fixed :on table)
    (box :asset "box/1" :position (0.45 0.2) :rpy-deg (0 0 15) :on table)
    (blk :asset "small-block/0" :position (0.55 -0.05) :rpy-deg (0 0 -25) :on table)
    (hammer :asset "hammer/0" :position (0.38 -0.2) :rpy-deg (0 0 60) :on table)))
