"""Benchmarks that reduce whole labs (topics of ``python -m processing.bench``)."""
