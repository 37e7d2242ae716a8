"""The shared records every layer uses: the error types, the models' constants, the one registry type (table), the
systems of units, the parameter and observable specs, the scene registry's table, the cases of a run, Physics and
Numerics (params), and the Trajectory record.

A leaf package: its modules import one another and nothing else of elastoactive at import time, so that the engines,
builders, scenes, terms and analysis can all stand on it. The registries it holds are filled by the packages above it
(scenes and terms register themselves when imported).
"""
