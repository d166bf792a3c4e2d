"""Layer 1: reading and writing files. Nothing here computes on pixels."""
