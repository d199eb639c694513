"""The face the user selected, as bounded by its edges: its four sides' Coons map, sampled into the patch a
fit runs on (coons, sampled, patch), the rails run past the face (extend, cost, trimfit), the result trimmed
by the face's edges (trim), and the whole fit of a face (fit)."""
