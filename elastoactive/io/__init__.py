"""Files and processes: atomic outputs with their provenance (outputs), JSON of numpy values (jsonio), the
process pool (executor), progress bars (progress)."""
