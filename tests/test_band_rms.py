"""The meter's bands: closed-form sines in every band, the band edges as the meter's filters,
white noise against the integral of the weight, no drift from an offset, and the time
signals' peaks."""
import numpy as np
import pytest

from processing.vibration.band_rms import (BANDS, QUANTITIES, REFERENCES, Band, band_rms,
                                           band_signals, level_db, meter_gain, peaks, sine_band_rms,
                                           window_spread)

RATE = 25600.0
T = np.arange(int(2.4 * RATE)) / RATE   # 2.4 s: the record length


@pytest.mark.parametrize("frequency", [5.3, 8.33, 21.7, 97.1, 612.4, 2113.0, 5021.7])
def test_sine_comes_out_at_its_closed_form_in_every_band(frequency):
    # a non-whole number of periods in the record, with a DC offset of the sensor
    acc = 12.0 * np.cos(2 * np.pi * frequency * T + 0.7) + 0.8
    r = band_rms(acc, RATE)
    for q in QUANTITIES:
        truth = float(sine_band_rms(12.0, frequency, q))
        # the deconvolution leaves (σ_f/f)⁴ terms: 2·10⁻⁴ of x at 5 Hz on 2.4 s
        assert r[q] == pytest.approx(truth, rel=5e-4), f"{q} at {frequency} Hz"


def test_band_edges_behave_like_butterworth_filters():
    # at an edge −3 dB; an octave outside 6N dB down (order N: 1/√(1 + 2^2N)); N = 2, 3, 4
    for q, order in zip(QUANTITIES, (2, 3, 4)):
        b = BANDS[q]
        assert b.order == order
        octave = (1 + 2 ** (2 * order)) ** -0.5
        for f, gain in ((b.low, 2 ** -0.5), (b.high, 2 ** -0.5), (b.low / 2, octave),
                        (b.high * 2, octave)):
            if f < RATE / 2:
                t = np.arange(int(20 * RATE)) / RATE     # 0.7 Hz: long enough for the lobe
                acc = 10.0 * np.sin(2 * np.pi * f * t)
                expected = 10.0 / np.sqrt(2) * gain / (2 * np.pi * f) ** "avx".index(q)
                assert band_rms(acc, RATE)[q] == pytest.approx(expected, rel=5e-3), (q, f)
    assert BANDS["v"].high == 2800.0 and BANDS["a"].high == BANDS["x"].high == 8000.0
    assert Band(1.4, 8000.0, order=4).gain(0.7) == pytest.approx((1 + 2 ** 8) ** -0.5)


def test_white_noise_reads_the_integral_of_the_weight():
    # S_a = 2σ²/f_s one-sided: X² = (2σ²/f_s) ∫ g df (Parseval through the band)
    rng = np.random.default_rng(3)
    sigma = 5.0
    runs = [band_rms(sigma * rng.standard_normal(T.size), RATE) for _ in range(20)]
    f = np.linspace(0, RATE / 2, 2_000_001)[1:]
    for q in QUANTITIES:
        expected = np.sqrt(2 * sigma ** 2 / RATE * np.trapezoid(meter_gain(f, q) ** 2, f))
        got = np.sqrt(np.mean([r[q] ** 2 for r in runs]))
        # v and x of white noise sit in the few bins near 1.4 Hz: three standard errors
        scatter = np.std([r[q] for r in runs]) / expected / np.sqrt(len(runs))
        assert got == pytest.approx(expected, rel=max(0.01, 3 * scatter)), q


def test_two_lines_add_in_power_and_nothing_drifts():
    # an offset and a slow sensor wander below the band stay out of velocity and displacement
    acc = 8 * np.cos(2 * np.pi * 12.5 * T) + 3 * np.cos(2 * np.pi * 37.5 * T + 1)
    wander = 0.5 + 0.3 * np.cos(2 * np.pi * 0.1 * T)
    r = band_rms(acc + wander, RATE)
    for q in QUANTITIES:
        truth = np.hypot(sine_band_rms(8, 12.5, q), sine_band_rms(3, 37.5, q))
        assert r[q] == pytest.approx(float(truth), rel=2e-3), q


def test_whole_periods_integrate_exactly_in_time():
    cycle = int(RATE / 6.25)                # 6.25 Hz: the half order at 750 min⁻¹
    t = np.arange(8 * cycle) / RATE
    acc = 10 * np.cos(2 * np.pi * 6.25 * t) + 4 * np.cos(2 * np.pi * 50 * t + 0.3)
    x = band_signals(acc, RATE, periodic=True)["x"]
    x_true = (10 * meter_gain(6.25, "x") * np.cos(2 * np.pi * 6.25 * t)
              + 4 * meter_gain(50, "x") * np.cos(2 * np.pi * 50 * t + 0.3))
    # zero-phase band: cos in, −cos out for two integrations
    assert np.max(np.abs(x + x_true)) < 1e-3 * np.max(np.abs(x_true))
    p = peaks(x)
    assert p.peak_to_peak == pytest.approx(np.ptp(x_true), rel=1e-3)


def test_a_period_of_any_length_comes_back_interpolated_exactly():
    # 51 206 samples (2·25 603, a prime): transformed back on the FFT's next fast length,
    # 51 840; the band signals are the closed forms at the finer grid's times, the Nyquist
    # cosine (−1)ⁿ included
    size = 51206
    t = np.arange(size) / RATE
    period = size / RATE
    f1, f2 = 7 / period, 911 / period
    acc = 6 * np.cos(2 * np.pi * f1 * t + 0.4) + 2 * np.sin(2 * np.pi * f2 * t) \
        + 0.5 * np.cos(np.pi * RATE * t)
    s = band_signals(acc, RATE, periodic=True)
    assert s.time.size == 51840 and s.time[-1] < period
    u = s.time
    for q, n in zip(QUANTITIES, (0, 1, 2)):
        gain = [meter_gain(f, q) for f in (f1, f2, RATE / 2)]
        # integrating n times: each sine lags by n·90°
        truth = (6 * gain[0] * np.cos(2 * np.pi * f1 * u + 0.4 - n * np.pi / 2)
                 + 2 * gain[1] * np.sin(2 * np.pi * f2 * u - n * np.pi / 2)
                 + 0.5 * gain[2] * np.cos(np.pi * RATE * u - n * np.pi / 2))
        assert np.max(np.abs(s[q] - truth)) < 1e-9 * np.max(np.abs(truth)), q


def test_a_long_record_is_read_in_segments_as_exactly():
    # 100 s (2.56 M samples, three segments): the orders at 6.31 and 51.7 Hz
    t = np.arange(int(100 * RATE)) / RATE
    acc = 10 * np.cos(2 * np.pi * 6.31 * t) + 3 * np.cos(2 * np.pi * 51.7 * t + 2)
    r = band_rms(acc, RATE)
    for q in QUANTITIES:
        truth = np.hypot(sine_band_rms(10, 6.31, q), sine_band_rms(3, 51.7, q))
        assert r[q] == pytest.approx(float(truth), rel=1e-6), q


def test_levels_name_their_reference():
    assert level_db(REFERENCES["iso1683"]["v"], "v") == pytest.approx(0.0)
    assert level_db(1e-3, "v", "gost25275") == pytest.approx(20 * np.log10(1e-3 / 5e-8))


def test_window_spread_and_short_record_refused():
    assert window_spread(64) == pytest.approx(1 / 3, rel=0.01)
    with pytest.raises(ValueError, match="too few"):
        band_rms(np.ones(8), RATE)


def test_records_transformed_together_come_back_as_each_alone():
    # a recording's channels at once: a length Bluestein's algorithm transforms (a prime)
    # packs two to a complex transform, a fast one does not; each row as the record alone
    rng = np.random.default_rng(3)
    for size in (4999, 5000):
        rows = rng.standard_normal((3, size)) * np.array([[1.0], [0.02], [30.0]])
        for periodic in (True, False):
            together = band_signals(rows, RATE, periodic=periodic)
            for k, row in enumerate(rows):
                alone = band_signals(row, RATE, periodic=periodic)
                assert np.array_equal(together.time, alone.time)
                for q in QUANTITIES:
                    scale = np.abs(alone[q]).max()
                    assert np.abs(together[q][k] - alone[q]).max() < 1e-13 * scale, (size, q)


def test_the_decimating_filter_is_the_polyphase_resampler():
    # the FIR at the kept samples alone: scipy's resample_poly with the same taps, ends cut
    from scipy.signal import resample_poly

    from processing.vibration.steady_record import DECIMATION_TAPS, _taps, decimate

    rng = np.random.default_rng(4)
    for size, highest in ((20000, 600.0), (10007, 1500.0), (300, 200.0)):
        x, t = rng.standard_normal(size), np.arange(size) / RATE
        q = int(RATE / (4 * highest))
        y = resample_poly(x, 1, q, window=_taps(q))
        keep = slice(DECIMATION_TAPS // 2 + 1, y.size - DECIMATION_TAPS // 2 - 1)
        t2, a2, x2 = decimate(t, 2 * t, x, RATE, highest)
        assert np.array_equal(t2, t[::q][keep]) and np.array_equal(a2, 2 * t[::q][keep])
        assert x2.shape == y[keep].shape
        assert np.allclose(x2, y[keep], rtol=0, atol=1e-13 * max(np.abs(y).max(), 1.0))


def test_mean_cycles_interpolate_as_numpy_does():
    # the grid placed once for several signals: the values np.interp gives, bit for bit
    from processing.vibration.steady_record import mean_cycles

    rng = np.random.default_rng(5)
    angle = np.cumsum(rng.uniform(0.9, 1.1, 7001)) * 0.01
    signals = rng.standard_normal((3, angle.size))
    cycle = 4 * np.pi
    count = int(round((angle[-1] - angle[0]) / cycle))
    points = angle.size // count
    grid = angle[0] + (np.arange(count)[:, None] * cycle
                       + np.arange(points)[None, :] * (cycle / points))
    for row, got in zip(signals, mean_cycles(signals, angle, cycle)):
        want = np.interp(grid.ravel(), angle, row).reshape(count, points).mean(axis=0)
        assert np.array_equal(got, want)


@pytest.mark.parametrize("length", [51206, 51203, 51200, 998])
@pytest.mark.parametrize("count", [1, 2, 3])
def test_records_transformed_together_have_their_own_spectra(length, count):
    # a slow even length (halves as complex records), a slow odd one (pairs), a fast one:
    # each record's spectrum is rfft's to a few units of the last place of the largest
    # record's, a record a thousand times smaller than its partner's included
    from processing.vibration.band_rms import _spectra

    rng = np.random.default_rng(length + count)
    records = [rng.standard_normal(length) * s for s in (1.0, 1e-3, 5.0)[:count]]
    got = _spectra(records, length)
    largest = max(np.abs(np.fft.rfft(r)).max() for r in records)
    assert got.shape == (count, length // 2 + 1)
    for row, r in zip(got, records):
        assert np.max(np.abs(row - np.fft.rfft(r))) < 1e-13 * largest
