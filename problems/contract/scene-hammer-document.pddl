; Contract set (a): a hammer onto a stack of paper lying flat.
(define (problem contract-hammer-document)
  (:domain mech-basis)
  (:objects table hammer paper - item)
  (:init (handempty) (fixed table) (support hammer table) (support paper table))
  (:goal (and (support hammer paper) (handempty)))
  (:scene
    (table :asset "table" :position (0.6 0 0) :fixed)
    (hammer :asset "hammer/1" :position (0.45 0.22) :rpy-deg (0 0 -30) :on table)
    (paper :asset "document/0" :position (0.5 -0.2) :rpy-deg (0 0 90) :on table)))
