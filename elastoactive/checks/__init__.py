"""Is the simulator right: the engines against each other (validate), error against cost (accuracy), stiff and
extreme cases (extremes)."""
