"""Shared fixtures: build a lab's inputs from a plain dict, as a parsed TOML file would be."""
import pytest

from processing.diagnostics import collect_notices
from processing.measurement import load


@pytest.fixture
def make_inputs(tmp_path):
    """``make_inputs(spec, data)`` → (Inputs, notices raised while loading)."""
    def make(spec, data):
        with collect_notices() as notices:
            inputs = load(tmp_path / f"{spec.id}.toml", spec, {"lab": spec.id, **data})
        return inputs, notices
    return make
