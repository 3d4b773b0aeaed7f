"""Free oscillations and loops: periods, free decay, smoothing, load–deflection loops."""
