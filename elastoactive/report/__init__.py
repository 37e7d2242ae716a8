"""The paper reproduced: the claims table (claims), the paper's numbers (paper), the whole run (reproduce)."""
