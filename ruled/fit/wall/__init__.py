"""A part's wall, on plain arrays: its faces checked to be a ring and ordered round it (ring), each as a
four-sided patch (join; patch where it is no exact one) joined into one closed surface, fitted as one closed
ruled surface in pieces between its corners (fit), and the result cut into one piece per face (pieces)."""
