"""The engine-on-mounts scene against the band chain, and the cut cylinder's finding: every
cylinder with marks per working cycle, twins split with marks per revolution, none in
healthy pairs."""
from dataclasses import replace

import numpy as np
import pytest

from processing.vibration.band_rms import QUANTITIES, band_rms
from processing.crank.dynamics import firing_phases
from processing.speed.edges import detect_edges
from processing.inputs.reuse import scope
from processing.vibration.misfire import find_cut_cylinder
from processing.torsional.orders import order_fit
from processing.synth.engine import Engine
from processing.synth.engine_mount import (POINTS, Accelerometer, Block, cylinder_factors,
                                           point_orders, record)
from processing.torsional.torsiogram import revolutions, steady_crank_angle

FIRING = (1, 3, 4, 2)
ENGINE, BLOCK = Engine(), Block()
W = 2000 * np.pi / 30


def _fit(rec, per_cycle=True, channel="acc1"):
    marks = detect_edges(rec.tdc, "fit") / rec.sample_rate
    t = np.arange(rec.tdc.size) / rec.sample_rate
    angle = steady_crank_angle(t, revolutions(marks))
    if per_cycle:
        return order_fit(t, 2 * angle, rec.volts[channel], max_order=8.0)
    # a mark per revolution: the angle known modulo 360° (here counted from the other
    # revolution's TDC); the half orders' phase is then lost
    return order_fit(t, 2 * angle + 2 * np.pi, rec.volts[channel], max_order=8.0)


def test_the_scenes_truth_is_what_the_band_chain_reads_without_noise():
    sensor = Accelerometer(snr_db=120.0, resonance=1e9)
    rec = record(ENGINE, BLOCK, POINTS, sensor, W, 2.4, seed=2, firing_order=FIRING)
    for name, volts in rec.volts.items():
        got = band_rms(volts / sensor.sensitivity, sensor.sample_rate)
        for q in QUANTITIES:
            assert got[q] == pytest.approx(rec.truth[name][q], rel=1e-3), (name, q)


def test_an_in_line_four_has_no_first_order_heave_and_a_second_order_one():
    # point 1 sits above the centre of mass: no roll; second order = the free P_j2 over m
    resp = point_orders(ENGINE, Block(unbalance=0.0), POINTS[0], W, firing_order=FIRING)
    k = resp.order
    assert abs(resp.coefficient[k == 1][0]) < 1e-9
    lam, mj, R = ENGINE.lambda_, ENGINE.reciprocating_mass, ENGINE.crank_radius
    exact = lam + lam ** 3 / 4 + 15 * lam ** 5 / 128         # j's second harmonic, exact
    wn = 2 * np.pi * BLOCK.frequencies[0]
    w2 = (2 * W) ** 2
    mount = w2 / np.abs(wn ** 2 - w2 + 2j * BLOCK.damping_ratio * wn * 2 * W)
    expected = 4 * mj * R * W ** 2 * exact / BLOCK.mass * mount
    assert abs(resp.coefficient[k == 2][0]) == pytest.approx(expected, rel=2e-3)


@pytest.fixture(scope="module")
def scenes():
    sensor = Accelerometer(snr_db=20.0)
    factors = cylinder_factors(ENGINE, BLOCK, np.random.default_rng(9))

    def make(cut, seed):
        return record(ENGINE, BLOCK, POINTS[1:2], sensor, W, 2.4, seed=seed, factors=factors,
                      firing_order=FIRING, cut=cut)

    return {cut: make(cut, 10 + (cut or 0)) for cut in (None, 1, 2, 3, 4)} | {
        "healthy2": make(None, 99)}


@pytest.mark.parametrize("cut", [1, 2, 3, 4])
def test_each_cut_cylinder_is_found_from_cycle_marks(scenes, cut):
    phases = firing_phases(4, firing_order=FIRING)
    found = find_cut_cylinder(_fit(scenes[None]), _fit(scenes[cut]), phases)
    assert found.found and found.cylinder == cut and found.confidence > 0.95
    assert found.rise > 5 and found.p_value < 1e-10


def test_a_healthy_pair_shows_no_cut_cylinder(scenes):
    phases = firing_phases(4, firing_order=FIRING)
    found = find_cut_cylinder(_fit(scenes[None]), _fit(scenes["healthy2"]), phases)
    assert not found.found and found.cylinder == 0
    assert found.rise < 1.5


def test_marks_per_revolution_split_cylinders_a_revolution_apart(scenes):
    # 1-3-4-2 fires cylinders 1 and 4 (and 3 and 2) 360° apart: with an angle known modulo
    # 360° their shares are equal
    phases = firing_phases(4, firing_order=FIRING)
    found = find_cut_cylinder(_fit(scenes[None], False), _fit(scenes[3], False), phases,
                              cycle_marks=False)
    shares = dict(enumerate(found.shares, 1))
    assert shares[3] == pytest.approx(shares[2]) and shares[3] + shares[2] > 0.95


def test_a_finding_is_kept_by_the_fits_orders_coefficients_and_covariances(scenes):
    # inside a scope: a fit differing in its drift and fitted signal alone (what the finding
    # does not read) finds the finding done; one differing in a coefficient does not
    phases = firing_phases(4, firing_order=FIRING)
    healthy, suspect = _fit(scenes[None]), _fit(scenes[2])
    with scope():
        first = find_cut_cylinder(healthy, suspect, phases)
        other = replace(suspect, drift=suspect.drift + 1.0, periodic=suspect.periodic * 0.0)
        assert find_cut_cylinder(healthy, other, phases) is first
        moved = replace(suspect, coefficient=suspect.coefficient * 1.5)
        assert find_cut_cylinder(healthy, moved, phases) is not first
        assert find_cut_cylinder(healthy, suspect, phases, seed=1) is not first


def test_fits_of_different_orders_are_refused(scenes):
    a = _fit(scenes[None])
    b = order_fit(np.arange(a.drift.size, dtype=float), np.arange(a.drift.size) * 0.01,
                  np.zeros(a.drift.size), max_order=4.0)
    with pytest.raises(ValueError, match="different orders"):
        find_cut_cylinder(a, b, [0.0, np.pi])


def test_records_sampled_alike_are_fitted_as_each_alone():
    # the channels of one recording share the design: each fit is the one of its record alone
    from processing.torsional.orders import order_fits

    rng = np.random.default_rng(6)
    t = np.linspace(0.0, 1.0, 3001)
    th = 2 * np.pi * 23 * t + 0.01 * np.sin(3 * t)
    records = [np.cos(2 * th + k) + 0.3 * np.sin(4.5 * th) + rng.normal(0, 0.1, t.size)
               for k in range(3)]
    for together, x in zip(order_fits(t, th, records, max_order=8.0), records):
        alone = order_fit(t, th, x, max_order=8.0)
        assert np.array_equal(together.coefficient, alone.coefficient)
        assert np.array_equal(together.covariance, alone.covariance)
        assert together.residual_sd == alone.residual_sd and together.dof == alone.dof
