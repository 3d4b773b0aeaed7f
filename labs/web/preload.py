"""What the reductions' forkserver imports once, so that every child starts warm: the labs,
the measurement boundary and the report engine (numpy, scipy, pint, matplotlib, OpenCV)."""
import processing.reporting.pdf  # noqa: F401
import processing.reporting.render  # noqa: F401
from labs.registry import LABS
from labs.web import worker  # noqa: F401

MODULES = [LABS[lab] for lab in LABS]
"""Every lab's module, imported."""
