"""The paper reproduced: the claims table (claims) and the whole run (reproduce); the paper's own numbers, which the
studies set their results against, are elastoactive.studies.paper."""
