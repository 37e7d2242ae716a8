"""Pure functions of results: stability, spectra, fits, observables (numpy and scipy; the reduced engine's
mathematics, where an analysis needs it, from elastoactive.reduced)."""
