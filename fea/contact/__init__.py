"""Contact: penalty contact, Coulomb friction, and the rotating-drum test."""
