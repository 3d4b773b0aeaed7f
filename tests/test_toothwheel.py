"""processing.speed.toothwheel: numbering tooth edges, finding revolutions, calibrating the pitch.

Ideal edge lists are built by hand from a known speed ω(θ): the edge of the tooth at angle θ
comes at t(θ) = ∫dθ/ω, integrated by 8-point Gauss–Legendre over each pitch (exact to
rounding for this smooth ω). Edges are then deleted, doubled or renumbered to see the
tracker count right. The pitch calibration is checked against a synthetic coast-down record
of a wheel with known tooth errors (processing.synth.engine).
Tolerances: angles in degrees, edge counts exact.
"""

import numpy as np
import pytest
from conftest import OMEGA0, times_at  # the shared ideal engine
from numpy.testing import assert_allclose, assert_array_equal

from processing.diagnostics import InputError
from processing.speed.edges import detect_edges
from processing.synth.engine import Sensor, ToothWheel, coast_run, record
from processing.speed.toothwheel import calibrate_pitch, track_teeth


def wheel_angles(teeth, missing, revolutions, *, first=0, reference=0.0):
    """Angles of the present teeth (0..teeth-missing-1 per revolution), from edge ``first``."""
    tooth = np.arange(teeth - missing)
    revolution = np.arange(revolutions)[:, None] * teeth
    return (reference + (revolution + tooth) * (2 * np.pi / teeth)).ravel()[first:]


# a 60−2 wheel, 9 revolutions, the record starting at tooth 20 (mid-revolution)
FIRST = 20
ANGLES = wheel_angles(60, 2, 9, first=FIRST, reference=np.radians(2.0))
TIMES = times_at(ANGLES)
LEAD_IN = 58 - FIRST          # edges before the first gap
TOOTH_25 = LEAD_IN + 2 * 58 + 25   # index of tooth 25 of revolution 2


@pytest.fixture(scope="module")
def ideal():
    return track_teeth(TIMES, 60, 2)


def test_gap_found_every_revolution(ideal):
    tr = ideal
    assert tr.reference == "gap" and tr.gap_found
    assert tr.missed == 0 and tr.doubled == 0 and tr.bad_revolutions.size == 0
    # gaps before revolutions 1..8 of the edge list: 8 references, 7 closed revolutions
    assert tr.revolutions == 7
    assert_array_equal(tr.times, TIMES, err_msg="no edge removed")
    after_gap = np.flatnonzero(np.diff(ANGLES) > 2 * tr.pitch) + 1
    assert_array_equal(tr.tooth[after_gap], 0, err_msg="the first tooth after each gap is 0")
    assert_array_equal(tr.revolution[after_gap], np.arange(after_gap.size))
    assert_array_equal(tr.position[:3], [-LEAD_IN - 2, -LEAD_IN - 1, -LEAD_IN],
                       err_msg="edges before the first gap count back from it")
    # position = angle from the first reference tooth, in pitches
    assert_allclose(tr.position, (ANGLES - ANGLES[after_gap[0]]) / tr.pitch, atol=1e-9)
    assert not tr.valid[:LEAD_IN].any(), "the lead-in before the first gap is not a revolution"
    assert tr.valid[LEAD_IN:LEAD_IN + 7 * 58].all() and not tr.valid[LEAD_IN + 7 * 58:].any()
    assert_array_equal(np.bincount(tr.revolution[tr.valid]), 58, err_msg="58 teeth per rev")


def test_missing_edge_is_counted_and_its_slot_left_empty(ideal):
    tr = track_teeth(np.delete(TIMES, TOOTH_25), 60, 2)
    assert tr.missed == 1 and tr.doubled == 0 and tr.gap_found and tr.revolutions == 7
    # the interval across the missed tooth counts two pitches, so the revolution still adds
    # up to 60: nothing is miscounted and no revolution is bad (fit_cycles skips the cycle
    # whose table has the empty slot)
    assert tr.bad_revolutions.size == 0
    assert_array_equal(tr.position, np.delete(ideal.position, TOOTH_25),
                       err_msg="every remaining edge keeps its tooth")
    assert ideal.position[TOOTH_25] not in tr.position


def test_missed_tooth_beside_the_gap_hides_it_but_not_the_count(ideal):
    """The last tooth before a gap missed: that gap reads four pitches, not three, so it is
    not taken for a gap and two revolutions run between the references around it. Both are
    left out (their teeth cannot be told), and every revolution after keeps its true number
    (numbering the references one by one put the rest a revolution behind their angle, and
    a coast-down calibration through them 1.7° off)."""
    hidden = LEAD_IN + 2 * 58 + 57           # tooth 57 of revolution 2
    tr = track_teeth(np.delete(TIMES, hidden), 60, 2)
    assert tr.revolutions == 7 and tr.missed == 3          # the tooth and the hidden gap's two
    assert_array_equal(tr.bad_revolutions, [2, 3])
    assert_array_equal(tr.position, np.delete(ideal.position, hidden),
                       err_msg="every remaining edge keeps its pitch position")
    assert_array_equal(np.unique(tr.revolution[tr.valid]), [0, 1, 4, 5, 6])
    assert_array_equal(np.bincount(tr.revolution[tr.valid])[[0, 1, 4, 5, 6]], 58)


def test_doubled_edge_is_removed(ideal):
    k = TOOTH_25
    spurious = TIMES[k - 1] + 0.6 * (TIMES[k] - TIMES[k - 1])
    tr = track_teeth(np.insert(TIMES, k, spurious), 60, 2)
    assert tr.doubled == 1 and tr.missed == 0 and tr.bad_revolutions.size == 0
    assert_array_equal(tr.times, TIMES, err_msg="the spurious edge, not its neighbour, goes")
    assert_array_equal(tr.position, ideal.position)


def test_60_minus_1_gap_found_by_periodicity_despite_a_missed_tooth():
    angles = wheel_angles(60, 1, 9, first=FIRST, reference=np.radians(2.0))
    times = times_at(angles)
    lead_in = 59 - FIRST
    missed = lead_in + 3 * 59 + 30          # tooth 30: also a one-pitch hole, like the gap
    tr = track_teeth(np.delete(times, missed), 60, 1)
    assert tr.gap_found and tr.revolutions == 7
    assert tr.missed == 1 and tr.bad_revolutions.size == 0
    full = track_teeth(times, 60, 1)
    assert_array_equal(tr.position, np.delete(full.position, missed))
    assert_array_equal(full.tooth[lead_in + 59 * np.arange(8)], 0, err_msg="tooth 0 after gap")


def test_tdc_reference_starts_revolutions_at_the_mark():
    # plain 36-tooth wheel, teeth at 2.5° + 10°·j, a TDC mark 4° before tooth 0 (at −1.5°)
    angles = wheel_angles(36, 0, 9, first=5, reference=np.radians(2.5))
    times = times_at(angles)
    marks = times_at(np.arange(1, 9) * 2 * np.pi - np.radians(1.5))
    tr = track_teeth(times, 36, reference_times=marks)
    assert tr.reference == "tdc" and tr.revolutions == 7 and tr.missed == 0
    first = np.searchsorted(times, marks)
    assert_array_equal(tr.position[first], 36 * np.arange(8), err_msg="revolution r at mark r")
    assert_array_equal(tr.tooth[first], 0)
    assert_allclose(angles[first] - np.arange(1, 9) * 2 * np.pi, np.radians(2.5), atol=1e-12)
    # the mark-to-tooth angle is converted from time at the revolution's mean speed: its error
    # is the angle times the local speed deviation (≤ 1.3 % here), 0.05° at most
    assert_allclose(np.degrees(tr.reference_offset), 4.0, atol=0.1)
    steady = track_teeth(angles / OMEGA0, 36, reference_times=(np.arange(1, 9) * 2 * np.pi
                                                               - np.radians(1.5)) / OMEGA0)
    assert_allclose(np.degrees(steady.reference_offset), 4.0, atol=1e-9,
                    err_msg="exact at constant speed")
    with pytest.raises(InputError, match="TDC"):
        track_teeth(times, 36, reference="tdc")


def test_no_reference_counts_from_the_first_edge():
    angles = wheel_angles(36, 0, 4, first=7)
    tr = track_teeth(times_at(angles), 36)
    assert tr.reference == "none" and tr.gap_found
    assert_array_equal(tr.position, np.arange(angles.size))
    assert tr.revolutions == (angles.size - 1) // 36
    assert_array_equal(tr.tooth[:3], [0, 1, 2])
    assert_array_equal(tr.revolution[[35, 36]], [0, 1])


def test_wrong_tooth_count_is_flagged():
    # a 60−2 wheel declared as 36−2: the gap is still seen (three pitches), but every
    # revolution counts 60 pitches, not 36, so all of them are bad and no edge is valid (the
    # 7 × 60 pitches read as 12 revolutions of the declared wheel)
    tr = track_teeth(TIMES, 36, 2)
    assert tr.gap_found and tr.revolutions == 12
    assert_array_equal(tr.bad_revolutions, np.arange(12))
    assert not tr.valid.any()
    # declared 60−1: no one-pitch hole recurs, the gap is not found (counting falls back to
    # the first edge) and each real gap is reported as a missed tooth
    tr = track_teeth(TIMES, 60, 1)
    assert not tr.gap_found and tr.reference == "none"
    assert tr.missed == 8 * 2


def test_bad_arguments():
    with pytest.raises(InputError):
        track_teeth(TIMES[:2], 60, 2)
    with pytest.raises(InputError):
        track_teeth(TIMES, 60, 30)
    with pytest.raises(InputError, match="reference"):
        track_teeth(TIMES, 60, 2, reference="cam")


# ------------------------------------------------------------------------- pitch calibration

WHEEL = ToothWheel(missing=2, pitch_error=np.radians(0.05), seed=3,
                   reference_angle=np.radians(3.0))


def _true_deviation(wheel):
    """Edge angle of each present tooth from tooth 0, minus k·pitch (the sensor's timing points
    are the falling zeros of dΦ/dα, slightly off the tooth centres next to a misplaced
    neighbour). [rad]"""
    edge, tooth = wheel.edge_angles()
    by_tooth = np.empty(wheel.teeth - wheel.missing)
    by_tooth[tooth] = edge
    by_tooth = np.unwrap(by_tooth)
    return by_tooth - by_tooth[0] - np.arange(by_tooth.size) * wheel.pitch


@pytest.fixture(scope="module")
def coast():
    """24 revolutions of the wheel coasting down from 160 to 140 rad/s."""
    run = coast_run(150.0, 1.0, deceleration=20.0)
    return run, Sensor(sample_rate=100e3, snr_db=40)


def test_calibrate_pitch_recovers_tooth_errors(coast):
    run, sensor = coast
    true = _true_deviation(WHEEL)
    assert np.degrees(np.std(true)) > 0.03, "the wheel's errors are there to be found"
    # noise-free, what is left is the edge fit's shape error next to off-pitch teeth
    # (edges.FIT_SPAN): 0.2 % of the 0.05° errors found
    for snr, tol in ((np.inf, 2e-4), (sensor.snr_db, 0.005)):
        rec = record(run, WHEEL, Sensor(sample_rate=sensor.sample_rate, snr_db=snr))
        track = track_teeth(detect_edges(rec.signal) / rec.sample_rate, 60, 2)
        cal = calibrate_pitch(track)
        assert cal.revolutions >= 20
        assert np.isnan(cal.angles[58:]).all() and np.isnan(cal.deviation[58:]).all()
        assert cal.deviation[0] == 0, "angles are from tooth 0"
        error = np.degrees(cal.deviation[:58] - true)
        assert np.sqrt(np.mean(error ** 2)) < tol, f"snr {snr}: RMS error {error.std():.2g}°"
        assert_allclose(cal.angles[:58], np.arange(58) * WHEEL.pitch + cal.deviation[:58],
                        rtol=1e-12)
        if np.isfinite(snr):
            u = np.degrees(np.sqrt(np.mean(cal.u[:58] ** 2)))
            assert 0 < u and np.sqrt(np.mean(error ** 2)) < 3 * u, "u is the error's size"


def test_calibrate_pitch_needs_four_revolutions():
    run = coast_run(150.0, 0.12)  # 2.9 revolutions
    rec = record(run, WHEEL, Sensor(sample_rate=50e3, snr_db=40))
    track = track_teeth(detect_edges(rec.signal) / rec.sample_rate, 60, 2)
    with pytest.raises(InputError, match="revolutions"):
        calibrate_pitch(track)
