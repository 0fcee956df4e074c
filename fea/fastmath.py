"""The LLVM fast-math flags every numba kernel of ccedi is compiled with."""

FASTMATH = {"nsz", "arcp", "contract", "afn", "reassoc"}
"""LLVM fast-math flags for the hot loops: every flag except ``nnan`` and ``ninf``, so that
the NaN / inverted-element checks are not optimised away."""
