"""Benchmarks: each estimator family timed against its accuracy on the same synthetic cases.

``python -m processing.bench [--quick] [--out DIR] [--large N]`` runs them all
(:func:`processing.bench.speed.run`). The generic harness is :mod:`processing.bench.harness`;
the pulse-train families are in :mod:`processing.bench.speed`. Nothing is imported here, so
that the command can hold numpy's thread pools to one core before numpy loads.
"""
