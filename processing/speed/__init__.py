"""The pulse-train speed chain: tooth edges, teeth, angular speed and its irregularity δ."""
