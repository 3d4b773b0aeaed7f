"""A record's measures (:func:`processing.inputs.record_quality.assess`): its resolution step
and flatness, whose sort is left to the records that need it."""
import numpy as np
import pytest

from processing.inputs.record_quality import FLAT_STEPS, assess, clipped_mask


def test_step_is_the_least_gap_of_the_head_and_a_varied_record_is_not_sorted_for_it():
    x = np.random.default_rng(3).standard_normal(70000)
    q = assess(x, 1000.0)
    assert not q.flat and "step" not in q.__dict__       # decided without the sort
    head = np.sort(x[:1 << 16])
    gaps = np.diff(head)
    assert q.step == gaps[gaps > 0].min()
    assert list(q.to_dict()) == ["samples", "duration", "clipped", "spread", "step",
                                 "roughness"]
    assert q.to_dict()["step"] == q.step


@pytest.mark.parametrize("codes, flat", [
    ([2.0], True),
    ([2.0, 2.5], True),                    # two codes: one step
    ([2.0, 2.5, 3.0], True),               # three codes a step apart: FLAT_STEPS
    ([2.0, 2.25, 3.0], False),             # the least step a quarter of the spread
    ([2.0, 2.5, 3.0, 3.5], False),         # more codes than FLAT_STEPS + 1
])
def test_a_record_of_a_few_codes_is_flat_when_its_spread_is_within_two_steps(codes, flat):
    assert FLAT_STEPS == 2
    x = np.resize(np.array(codes), 999)
    q = assess(x, 100.0)
    assert q.flat is flat
    assert q.step == (np.diff(codes).min() if len(codes) > 1 else 0.0)


def test_assess_keeps_its_own_copy_of_the_head():
    x = np.arange(10.0)
    q = assess(x, 10.0)
    x[:] = 0.0
    assert q.step == 1.0 and not q.flat


@pytest.mark.parametrize("held, clipped", [(2, False), (6, True)])
def test_a_crest_held_at_a_rail_is_clipped_and_one_touching_it_is_not(held, clipped):
    """Two samples at the top are passed over unsearched; six, alone at their value, are a
    rail (more than CLIP_PILE = 5 times the samples below them)."""
    x = np.round(np.sin(np.linspace(0, 40 * np.pi, 8000)) * 50)
    x[x >= 50] = 49.0
    top = np.flatnonzero(x == 49.0)
    x[top[0]:top[0] + held] = 60.0                   # one crest held at the rail
    x[x == 49.0] = 45.0
    assert bool(clipped_mask(x).any()) is clipped
