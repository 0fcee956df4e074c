"""The floating-point mode every numba kernel of ccedi is compiled with.

IEEE arithmetic, no fast-math flags. With reassociation or FMA contraction allowed, LLVM
rounds a kernel differently when it is inlined into a freshly compiled caller than when it
is linked from numba's on-disk cache, so a run's result depended on the cache state (an
impulse run's von Mises stress in its last bits; a contact run's peak force by 0.3 %,
through the amplification of the contact chatter). Measured on the SM-A 4.5-in benchmark
(benchmarks/fea_speed.py): 145 ns per element-cycle against 140 ns with the flags on a
shared machine; 207 / 192 against 208 / 210 ns in two later pairs (VM noise dominates).
tests/unit/fea/test_determinism.py checks that a cold and a warm cache give the same bits.
"""

FASTMATH = False
"""``fastmath`` argument of every ``numba.njit`` in ccedi: off, for reproducible results."""
