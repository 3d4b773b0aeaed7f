"""Engine vibration: a meter's band RMS, steady records by crank angle, misfire."""
