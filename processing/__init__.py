"""dynlab's shared reduction primitives, by topic: the core (measurement files, units,
uncertainty, results, diagnostics, regression) at the top, one subpackage per topic."""
from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("dynlab")
except PackageNotFoundError:
    __version__ = "0.0.0+unknown"
