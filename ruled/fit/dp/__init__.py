"""The dynamic programs: the 2D table over the rails' samples (dp2d) and the 4D table with the ruling ends
lifted along the normal (dp4d, its costs in metrics4d), their numba kernels and NumPy twins, the pairing of
the rails' parameters a path gives, and the pairing that follows exact rulings."""
