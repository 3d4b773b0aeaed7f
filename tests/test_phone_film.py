"""The phone family of synthetic films (:mod:`processing.synth.phone_film`) is reproducible:
a scene and its seed make the same file on every run, whatever was encoded before it."""
from __future__ import annotations

import hashlib
import math

from processing.synth.phone_film import Phone, Swinger, render


def _digest(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_a_scene_is_the_same_file_before_and_after_another_is_encoded(tmp_path):
    swinger = Swinger(amplitude=math.radians(8.0), period0=0.8)
    phone = Phone(size=(480, 270), fps=30.0, hands=1)
    first = render(swinger, phone, tmp_path / "a.mp4", oscillations=2.0, seed=2).path
    render(Swinger(amplitude=math.radians(12.0), period0=1.1), Phone(size=(320, 180), fps=60.0),
           tmp_path / "b.mp4", oscillations=2.0, seed=3)
    again = render(swinger, phone, tmp_path / "c.mp4", oscillations=2.0, seed=2).path
    assert _digest(first) == _digest(again)
