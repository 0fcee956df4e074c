"""Set-ups of the paper's cases: the impulse studies, the steel rod, the drum contact study."""
