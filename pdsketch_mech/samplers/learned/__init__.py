"""Learned samplers: classifiers that rank a generic sampler's proposals (paper Sec. 3.2).

Torch is imported only here, and only when a mechanism's checkpoint is used."""
