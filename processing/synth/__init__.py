"""Synthetic ground truth: physical scenes modelled just enough, with their true answers."""
