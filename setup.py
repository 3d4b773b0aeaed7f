"""Ships the top-level ``sample_data/`` inside the wheel as ``labs/sample_data`` (so that
``dynlab demo`` runs from any folder after ``pip install``); the rest is in pyproject.toml."""
from setuptools import find_namespace_packages, setup

setup(packages=find_namespace_packages(include=["labs*", "processing*"]) + ["labs.sample_data"],
      package_dir={"labs.sample_data": "sample_data"})
