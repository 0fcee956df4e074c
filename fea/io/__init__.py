"""File formats of other solvers and viewers: LS-DYNA keyword decks, CalculiX, VTU."""
