"""The certificate of a fit: the upper bound of the distance between the surface and its ruled fit, from the
surface's side (forward) and from the result's (reverse), the grids refined cell by cell (cells), and the
bounds they share (bounds)."""
