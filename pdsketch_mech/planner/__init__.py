"""The adaptive bilevel planner (paper Alg. 1): symbolic skeletons, continuous refinement."""
