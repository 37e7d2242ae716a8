"""Elastic networks as data: the geometry record and its generators (geometry), the initial state (state)."""
