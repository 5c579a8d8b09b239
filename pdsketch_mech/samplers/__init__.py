"""Generic samplers (paper Appendix A.4): grasps, placements, contacts and trajectories.

Each sampler is a generator of small frozen dataclasses (`world/values.py`) that reads only the
geometry and poses of the bodies involved, never their names' meaning or categories.
"""
