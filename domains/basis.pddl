; The basis domain of "Learning Reusable Manipulation Strategies" (CoRL 2023), Table 1.
;
; The symbolic state is the contact-mode graph: what the hand holds and what supports what.
; Continuous parameters (grasps, placements, contacts, trajectories) are values produced by
; the streams below; each stream names the generic sampler that implements it. Samplers run
; in the simulated state reached by the plan so far, so they see the current object poses.
; After every operator the simulator settles and the contact graph is read back from it:
; the effects below are what the operator is *meant* to achieve, and a step whose simulated
; outcome differs fails (or is recorded as it happened) during continuous search.
(define (domain mech-basis)
  (:requirements :strips :typing :negative-preconditions :equality :streams)
  ; What the planner reads of this basis (observed predicates, support, fixed, free motions,
  ; how each operator executes): pdsketch_mech/operators/vocabulary.py, under this name.
  (:vocabulary basis)
  (:types item - object)                  ; every physical body: objects, tools, table, furniture
  (:value-types
    grasp                                 ; gripper pose relative to the object, SE(3)
    placement                             ; object pose in the support's frame, SE(3)
    contact                               ; a surface pair and a push: pose of the pusher relative to the pushed
    conf                                  ; a robot arm configuration
    traj)                                 ; a joint-space trajectory

  (:predicates
    ; contact-mode graph
    (handempty)
    (holding ?x - item)
    (support ?x - item ?y - item)         ; ?y supports ?x (contact force on ?x points up)
    (touching ?x - item ?y - item)        ; ?x touches ?y without supporting it
    (fixed ?x - item)                     ; static scene furniture: never grasped or pushed
    ; facts certified by streams
    (valid-grasp ?x - item ?g - grasp)
    (valid-placement ?x - item ?s - item ?p - placement)
    (hand-contact ?y - item ?s - item ?c - contact)
    (valid-contact ?x - item ?y - item ?s - item ?c - contact)
    (free-motion ?q - conf ?t - traj)
    (grasp-motion ?x - item ?g - grasp ?t - traj)
    (place-motion ?x - item ?s - item ?p - placement ?t - traj)
    (held-motion ?x - item ?q - conf ?t - traj)
    (push-motion ?c - contact ?t - traj))

  ; Move the empty hand to ?q without touching anything.
  (:action transit
    :parameters (?q - conf ?t - traj)
    :precondition (and (handempty) (free-motion ?q ?t)))

  ; Push ?x, which ?s supports, with the bare gripper.
  (:action transit-cont
    :parameters (?x - item ?s - item ?c - contact ?t - traj)
    :precondition (and (handempty) (support ?x ?s) (not (fixed ?x))
                       (hand-contact ?x ?s ?c) (push-motion ?c ?t)))

  ; Grasp ?x from its support ?s.
  (:action grasp
    :parameters (?x - item ?s - item ?g - grasp ?t - traj)
    :precondition (and (handempty) (support ?x ?s) (not (fixed ?x))
                       (valid-grasp ?x ?g) (grasp-motion ?x ?g ?t))
    :effect (and (holding ?x) (not (handempty)) (not (support ?x ?s))))

  ; Place the held ?x onto ?s and release it.
  (:action place
    :parameters (?x - item ?s - item ?p - placement ?t - traj)
    :precondition (and (holding ?x) (not (= ?x ?s))
                       (valid-placement ?x ?s ?p) (place-motion ?x ?s ?p ?t))
    :effect (and (support ?x ?s) (handempty) (not (holding ?x))))

  ; Move while holding ?x, touching nothing else.
  (:action move
    :parameters (?x - item ?q - conf ?t - traj)
    :precondition (and (holding ?x) (held-motion ?x ?q ?t)))

  ; Move while holding ?x so that ?x pushes ?y, which ?s supports.
  (:action move-cont
    :parameters (?x - item ?y - item ?s - item ?c - contact ?t - traj)
    :precondition (and (holding ?x) (support ?y ?s) (not (= ?x ?y)) (not (fixed ?y))
                       (valid-contact ?x ?y ?s ?c) (push-motion ?c ?t)))

  ; Generic samplers (paper Appendix A.4): G, P, C and T.
  (:stream sample-grasp
    :inputs (?x - item)
    :outputs (?g - grasp)
    :certified (valid-grasp ?x ?g)
    :sampler "grasp")
  (:stream sample-placement
    :inputs (?x - item ?s - item)
    :outputs (?p - placement)
    :certified (valid-placement ?x ?s ?p)
    :sampler "placement")
  (:stream sample-hand-contact
    :inputs (?y - item ?s - item)
    :outputs (?c - contact)
    :certified (hand-contact ?y ?s ?c)
    :sampler "contact")
  (:stream sample-contact
    :inputs (?x - item ?y - item ?s - item)
    :outputs (?c - contact)
    :certified (valid-contact ?x ?y ?s ?c)
    :sampler "contact")
  (:stream plan-free-motion
    :inputs ()
    :outputs (?q - conf ?t - traj)
    :certified (free-motion ?q ?t)
    :sampler "free-motion")
  (:stream plan-grasp-motion
    :inputs (?x - item ?g - grasp)
    :domain (valid-grasp ?x ?g)
    :outputs (?t - traj)
    :certified (grasp-motion ?x ?g ?t)
    :sampler "grasp-motion")
  (:stream plan-place-motion
    :inputs (?x - item ?s - item ?p - placement)
    :domain (valid-placement ?x ?s ?p)
    :outputs (?t - traj)
    :certified (place-motion ?x ?s ?p ?t)
    :sampler "place-motion")
  (:stream plan-held-motion
    :inputs (?x - item)
    :outputs (?q - conf ?t - traj)
    :certified (held-motion ?x ?q ?t)
    :sampler "held-motion")
  (:stream plan-push-motion
    :inputs (?c - contact)
    :outputs (?t - traj)
    :certified (push-motion ?c ?t)
    :sampler "push-motion"))
