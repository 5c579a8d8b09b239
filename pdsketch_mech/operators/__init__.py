"""The six basis operators of the paper (Table 1), executed in a simulated world."""
