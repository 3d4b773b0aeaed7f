"""dynlab's shared reduction primitives: units, uncertainty, measurement files, reports."""
from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("dynlab")
except PackageNotFoundError:
    __version__ = "0.0.0+unknown"
