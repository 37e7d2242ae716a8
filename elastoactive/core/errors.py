"""The package's exceptions: the bottom layer, imported by everything and importing nothing."""


class ParameterError(ValueError):
    """An invalid physical or numerical parameter, or option; the message names it."""


class SimulationDiverged(RuntimeError):
    """A run whose state became NaN or huge, or left its constraints; the message names the likely cause."""
