"""Torsional vibration: the equivalent chain, torsiograph records, orders, resonances."""
