"""PyBullet world: assets, robot, collision checking, motion planning."""
