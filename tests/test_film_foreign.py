"""Films that nobody here drew with the first renderer: phone films of
:mod:`processing.synth.phone_film` (a nonlinear damped pendulum or trifilar, motion blur, a
lamp's flicker beating with the frame rate, hands passing, roll and tilt, H.264 with each
frame's timestamp), read as a lab reads them. Small and short films here; 4K and long ones
belong to the bench (``python -m processing.bench --topic film``)."""
from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from processing.oscillations.anharmonic import fit_anharmonic_decay
from processing.oscillations.decay import fit_damped_sine
from processing.diagnostics import (DroppedFramesWarning, DynlabWarning, HiddenDropsWarning,
                                    IrregularFrameRateWarning, NominalFrameRateWarning)
from processing.oscillations.oscillation import pendulum_period_factor
from processing.synth.phone_film import Phone, Swinger, render
from processing.uncertainty import Measured, propagate
from processing.vision.frames import Film, frame_clock
from processing.vision.video import Filmed, swing_of, track_marker

SMALL = (320, 180)
"""The films' frame: small, for speed (a phone films 1080p or 4K: the bench reads those)."""


def _held(measured: Measured, truth: float) -> bool:
    k = stats.t.ppf(0.975, measured.dof) if math.isfinite(measured.dof) else 1.96
    return abs(measured.value - truth) <= k * measured.u


def _read(path):
    track = track_marker(path, field="pendulum.video")
    return track, swing_of(track, field="pendulum.video")


def test_a_wide_swing_is_fitted_with_its_period_drifting():
    """An 18° pendulum decaying to about 12°: its period shortens by 0.2 % along the record.
    One sinusoid's frequency misses the record's mean period by 4·10⁻⁵ (20 times its u);
    the fit whose frequency follows the amplitude squared gives it within 10⁻⁵, and says the
    amplitude it belongs to (the envelope's RMS) within 1 %."""
    swinger = Swinger(amplitude=math.radians(18.0), decrement=0.02, drag=0.0, period0=1.1)
    t = np.arange(0.0, 22.0, 1 / 30)
    theta, crossings = swinger.motion(23.0)
    s = 300.0 * theta(t) + np.random.default_rng(1).normal(0.0, 0.05, t.size)
    plain = fit_damped_sine(t, s, baseline_order=1)
    fit = fit_anharmonic_decay(t, s, plain)
    swings = np.interp([t[0], t[-1]], crossings, np.arange(crossings.size))
    swings[0] = (t[0] - crossings[0]) / (crossings[1] - crossings[0])
    mean_period = (t[-1] - t[0]) / (0.5 * (swings[1] - swings[0]))
    assert abs(plain.period / mean_period - 1) > 2e-5
    assert abs(fit.period / mean_period - 1) < 1e-5
    rms = math.sqrt(2 * np.mean(theta(np.linspace(t[0], t[-1], 20000)) ** 2))
    assert fit.reference_amplitude / 300.0 == pytest.approx(rms, rel=0.01)


@pytest.fixture(scope="module")
def wide(tmp_path_factory):
    """A 16° pendulum on a stand (no shake), a lamp flickering 30 % deep on 50 Hz mains, a
    hand passing, rolled 3° and tilted 4°, at 60 frames per second, 10 oscillations."""
    folder = tmp_path_factory.mktemp("wide")
    swinger = Swinger(amplitude=math.radians(16.0), period0=0.9, decrement=0.02, drag=0.03)
    phone = Phone(size=SMALL, fps=60.0, flicker=0.3, hands=1, roll=3.0, tilt=4.0, shake=0.0)
    return swinger, render(swinger, phone, folder / "wide.mp4", oscillations=10, seed=5)


def test_wide_swing_period_and_its_zero_amplitude_correction(wide):
    """The film's period within 10⁻³ of the swing's mean period and its 95 % interval holds
    it; corrected to zero amplitude with the amplitude it belongs to (lab 1's T/F(θ), the u
    through the one propagation), the period's interval holds T₀."""
    swinger, shot = wide
    track, swing = _read(shot.path)
    assert abs(swing.period.value / shot.mean_period - 1) < 1e-3
    assert _held(swing.period, shot.mean_period), (swing.period, shot.mean_period)
    read = Filmed("pendulum.video", track, swing)
    T0 = propagate(lambda T, a: {"T0": T / pendulum_period_factor(a)},
                   {"T": swing.period, "a": read.corrected_with},
                   n_samples=4000)["T0"]
    lo, hi = T0.interval95
    assert lo <= swinger.period0 <= hi, (T0.value, swinger.period0)


def test_240_fps_with_flicker_and_a_hand_is_reduced(tmp_path):
    """At 240 frames per second the 120 Hz light of 60 Hz mains is not averaged, and the
    survey's frames are taken every 15th: the marker is still found (the part that moves
    periodically), followed past a hand, and the period comes out within 10⁻³. A frame of
    256 × 144 px (its 768 frames take a third of the time at 320 × 180 to draw; the same
    film, read either size, misses the period by 2.7·10⁻⁵)."""
    swinger = Swinger(kind="trifilar", amplitude=math.radians(9.0), period0=0.8)
    phone = Phone(size=(256, 144), fps=240.0, exposure=0.9, mains=60.0, flicker=0.4, hands=1,
                  shake=0.0)
    shot = render(swinger, phone, tmp_path / "fast.mp4", oscillations=4, seed=3)
    _, swing = _read(shot.path)
    assert abs(swing.period.value / shot.mean_period - 1) < 1e-3


def test_variable_rate_with_dropped_frames_is_timed_and_warned(tmp_path):
    """A phone's variable frame rate (intervals ±20 %) with two frames dropped: each frame's
    time is read from the container, the dropped frames and the irregular rate are warned
    of, and the period holds."""
    swinger = Swinger(amplitude=math.radians(8.0), period0=1.0)
    phone = Phone(size=SMALL, fps=30.0, jitter=0.2, dropped=2, shake=0.0, hands=0)
    shot = render(swinger, phone, tmp_path / "vfr.mp4", oscillations=8, seed=4)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        track, swing = _read(shot.path)
    kinds = {w.category for w in caught}
    assert {DroppedFramesWarning, IrregularFrameRateWarning} <= kinds
    assert track.dropped == shot.dropped == 2
    np.testing.assert_allclose(track.time, shot.times, atol=1e-4)
    assert abs(swing.period.value / shot.mean_period - 1) < 1e-4


def test_avi_holds_only_a_nominal_rate_and_is_warned(tmp_path):
    """An AVI file holds no frame times: the frames are taken 1/rate apart, and the report
    says so."""
    swinger = Swinger(amplitude=math.radians(6.0), period0=1.0)
    phone = Phone(size=SMALL, fps=30.0, container="avi", hands=0, shake=0.0)
    shot = render(swinger, phone, tmp_path / "nominal.avi", oscillations=6, seed=6)
    with pytest.warns(NominalFrameRateWarning, match="nominal rate"):
        track, _ = _read(shot.path)
    assert not track.timed


def test_a_clock_rounded_to_its_tick_is_neither_irregular_nor_dropping():
    """240 frames per second on a 1/600 s clock: the intervals are 2 and 3 ticks in turn
    (±20 %), which is the container's rounding, not a variable rate nor a dropped frame;
    a real gap of two intervals is one dropped frame."""
    film = Film(Path("slowmo.mov"), (1920, 1080), 240.0, 1.0, True, 0, 1 / 600)
    times = np.round(np.arange(2400) / 240 * 600) / 600
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _, dropped = frame_clock(film, times)
    assert dropped == 0
    with pytest.warns(DroppedFramesWarning, match="1 frame"):
        _, dropped = frame_clock(film, np.delete(times, 1000))
    assert dropped == 1


def _lab1_pendulum(folder: Path, film: str, extra: str = "") -> Path:
    """A lab 1 file whose pendulum is timed by ``film`` alone."""
    path = folder / "m.toml"
    path.write_text(f'lab = "lab1"\n[body]\nm = "15 kg"\ng = "9.81 m/s^2"\n[pendulum]\nc = 120\n'
                    f'video = "{film}"\n{extra}', encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def short(tmp_path_factory):
    """A pendulum filmed for 3.5 oscillations at 256 × 144 (84 frames)."""
    folder = tmp_path_factory.mktemp("short")
    swinger = Swinger(amplitude=math.radians(8.0), period0=0.8)
    phone = Phone(size=(256, 144), fps=30.0, hands=0)
    return folder, render(swinger, phone, folder / "short.mp4", oscillations=3.5, seed=2)


def test_a_short_film_reduces_with_an_honest_u_and_no_n_osc(short):
    """3.5 oscillations: the period within its 95 % interval (its u from the residual's
    density across the arc too, where the camera's shake sits at the swing's frequency),
    lab 1 reduced from the film alone (no n_osc: a film needs none) into JSON without a
    NaN."""
    from labs.registry import evaluate
    from processing.reporting.render import to_json

    folder, shot = short
    _, swing = _read(shot.path)
    assert swing.period.u > 0 and _held(swing.period, shot.mean_period)
    result = evaluate(_lab1_pendulum(folder, "short.mp4"), n_samples=500)
    assert 0 < result["J_pendulum_cm"].u < result["J_pendulum_cm"].value
    assert "NaN" not in to_json(result)


def test_a_stopwatch_time_without_n_osc_is_refused(short):
    from labs.registry import evaluate
    from processing.diagnostics import InputError

    folder, _ = short
    with pytest.raises(InputError, match="n_osc") as exc:
        evaluate(_lab1_pendulum(folder, "short.mp4", "t = [20.1, 20.2]\n"), n_samples=200)
    assert exc.value.field == "pendulum.n_osc" and exc.value.ru is not None


def test_a_film_too_short_is_refused_with_the_length_needed(tmp_path):
    from processing.diagnostics import InputError

    swinger = Swinger(amplitude=math.radians(8.0), period0=0.8)
    shot = render(swinger, Phone(size=(256, 144), fps=30.0, hands=0), tmp_path / "s.mp4",
                  oscillations=1.6, seed=2)
    with pytest.raises(InputError, match="spans 1.[0-9] oscillations") as exc:
        _read(shot.path)
    assert "at least 2 oscillations" in exc.value.fix and exc.value.ru is not None


def test_the_marker_is_the_patch_inside_the_region_given(short):
    """Without a region the tracker takes the sticker (the widest swing of the largest,
    most contrasting patch at the swing's frequency); given the flywheel's hub as the
    region, it follows the hub, and the period is the same swing's."""
    folder, shot = short
    sticker = track_marker(shot.path)
    hub = track_marker(shot.path, roi=(113, 25, 24, 24), roi_field="pendulum.roi")
    assert np.nanmean(sticker.y) > 55
    assert 25 <= np.nanmean(hub.y) <= 49 and 113 <= np.nanmean(hub.x) <= 137
    a, b = swing_of(sticker).period, swing_of(hub).period
    assert abs(a.value - b.value) < 3 * math.hypot(a.u, b.u)


@pytest.mark.parametrize("roi, match", [("[300, 10, 40, 40]", "beyond the film's 256 × 144"),
                                        ("[10, 10, 40]", "four numbers"),
                                        ("[10, -1, 40, 40]", "four numbers"),
                                        ("[0, 0, 20, 20]", "nothing swings inside")])
def test_a_wrong_region_is_refused_at_its_field(short, roi, match):
    from labs.registry import evaluate
    from processing.diagnostics import InputError

    folder, _ = short
    with pytest.raises(InputError, match=match) as exc:
        evaluate(_lab1_pendulum(folder, "short.mp4", f"roi = {roi}\n"), n_samples=200)
    assert exc.value.field == "pendulum.roi" and exc.value.ru is not None


@pytest.mark.parametrize("kind, fall, share", [("pendulum", 0.25, 0.3), ("trifilar", 0.8, 1.0)])
def test_a_synthetic_swing_decays_as_a_real_one_does(kind, fall, share):
    """The phone family's swings lose what a real one loses over 20 swings (to 25–80 %),
    by viscous and air damping integrated from the nonlinear equation: the share asked for
    within a fifth (the two dampings split the loss only approximately: 0.29 for 0.25)."""
    swinger = Swinger.decaying(kind, 1.0, math.radians(15.0), fall, share)
    theta, _ = swinger.motion(20.5)
    late = np.abs(theta(np.linspace(19.5, 20.5, 400))).max()
    assert late / swinger.amplitude == pytest.approx(fall, rel=0.2)


def test_frames_dropped_under_constant_rate_times_are_found_from_the_phase(tmp_path):
    """A film whose times were rewritten at a constant rate (a constant-rate export) with
    two frames dropped: the swing's phase jumps by an interval at each; both are found,
    warned of, and taken into the timing (the period 0.7 % short without: now within
    2·10⁻⁴)."""
    swinger = Swinger(amplitude=math.radians(12.0), period0=1.0)
    phone = Phone(size=(320, 180), fps=30.0, hands=0, dropped=2, restamped=True)
    shot = render(swinger, phone, tmp_path / "restamped.mp4", oscillations=8, seed=7)
    with pytest.warns(DroppedFramesWarning, match="2 frame.*claim a constant rate"):
        _, swing = _read(shot.path)
    assert abs(swing.period.value / shot.mean_period - 1) < 2e-4


def _shaken_track(seed: int, dropped=(), fps: float = 30.0, noise: float = 1.0):
    """A 6° pendulum decaying to half over 20 swings, 100 px from its axis, filmed at
    ``fps`` by a phone shaking 0.3 px RMS (a random walk smoothed over a quarter second,
    as :mod:`processing.synth.phone_film` shakes) with 0.05 px of tracker noise (both times
    ``noise``); the frames
    numbered ``dropped`` never taken, every frame stamped at the constant rate."""
    from scipy.ndimage import gaussian_filter1d

    rng = np.random.default_rng([seed, 33])
    swinger = Swinger.decaying("pendulum", 1.1, math.radians(6.0), 0.5)
    n = int(10 * 1.1 * fps)
    taken = np.delete(np.arange(n + len(dropped)) / fps, list(dropped))[:n]
    theta, _ = swinger.motion(taken[-1] + 0.1)
    walk = gaussian_filter1d(np.cumsum(rng.standard_normal(n)), 0.25 * fps)
    shake = 0.3 * noise * (walk - walk.mean()) / walk.std()
    return np.arange(n) / fps, 100.0 * theta(taken) + shake + rng.normal(0.0, 0.05 * noise, n)


def test_a_dropped_frame_is_placed_from_the_swings_timing_through_a_phones_shake():
    """The shake puts most of the track's noise about the swing's frequency (0.3 px against
    a step of up to 1 px): weighed by the noise's own spectrum, both frames dropped are
    found at the frame after each, an interval each; the same film without them, none."""
    from processing.vision.video import _find_drops

    stamps, s = _shaken_track(5, dropped=(77, 250))
    found = sorted(_find_drops(stamps, s, 1 / 30))
    assert [m for _, m in found] == [1, 1]
    np.testing.assert_allclose([at for at, _ in found], [77 / 30, 249 / 30], atol=1.5 / 30)
    stamps, s = _shaken_track(5)
    assert _find_drops(stamps, s, 1 / 30) == []


def test_a_drop_too_faint_to_be_sure_of_is_carried_in_the_periods_u():
    """A phone shaking 0.8 px with 0.14 px of tracker noise hides a frame dropped at 5 s:
    its step stands 3.5 standard errors out, under the 4.5 a warning needs, so it is not
    found; the period's u carries it as a limit of the period's shift were it dropped
    (0.46 %, the error it makes). The same film without it carries none."""
    from processing.vision.video import _doubt, _find_drops, _fitted

    stamps, s = _shaken_track(4, dropped=(150,), noise=2.8)
    every = np.ones(stamps.size, bool)
    assert _find_drops(stamps, s, 1 / 30) == []
    at, share = _doubt(stamps, s, every, 1 / 30, [])
    assert abs(at - 150 / 30) <= 1.5 / 30
    taken = np.delete(np.arange(stamps.size + 1) / 30, [150])[:stamps.size]
    error = _fitted(stamps, s)[1].period / _fitted(taken, s)[1].period - 1
    assert share == pytest.approx(abs(error), rel=0.2)
    stamps, s = _shaken_track(4, noise=2.8)
    assert _doubt(stamps, s, every, 1 / 30, []) is None


def test_drops_are_sought_only_where_a_single_one_would_show():
    """At 120 frames per second a dropped frame's step is half one at 60: through the
    phone's shake a single one stands 5 standard errors out at the median frame, and is
    sought; through five times the shake 1.0 (under 3), and none is sought (a step found
    there is slow noise taken for a burst of drops: a clean slow-motion film was "found" to
    drop 32 frames and its period put 3.8 u off)."""
    from processing.vision.video import DROP_DETECTABLE, _drop_power

    assert _drop_power(*_shaken_track(4, fps=120.0), 1 / 120) >= DROP_DETECTABLE
    assert _drop_power(*_shaken_track(4, fps=120.0, noise=5.0), 1 / 120) < DROP_DETECTABLE


def test_a_drop_the_film_cannot_show_is_warned_of_where_it_would_move_the_period():
    """At 240 frames per second through 1.5 times the phone's shake a single dropped
    frame's step stands 3.5 standard errors out at the median frame, under the 4.9 the
    search needs on 2640 frames, and one dropped mid-film would move the period 0.06 %,
    more than its u: the film is warned that a drop could hide in it (not that one did),
    and of no drop. Filmed at 30 the same swing shows a drop 17 standard errors out at the
    median frame, and is warned of nothing."""
    from processing.vision.video import Track

    def swing(fps):
        stamps, s = _shaken_track(4, fps=fps, noise=1.5)
        theta = s / 100.0
        track = Track("synthetic", stamps, 160 + 100 * np.sin(theta),
                      20 + 100 * np.cos(theta), np.ones_like(stamps), 29, 0.0)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            swing_of(track)
        return [w for w in caught if issubclass(w.category, DynlabWarning)]

    slow = swing(240.0)
    assert [w.category for w in slow] == [HiddenDropsWarning]
    assert "could not show one" in str(slow[0].message) and "U)" in str(slow[0].message)
    assert "Это не значит, что кадр пропал" in slow[0].message.text("ru")
    assert swing(30.0) == []


def test_a_patch_at_a_harmonic_of_the_swing_is_not_the_marker():
    """A patch that moves twice a swing (a trifilar's ring seen from above, moving only as
    the platform rises and sinks) is as periodic as the marker: the swing's frequency is the
    lower one, and the marker is taken at it (else the period would come out half)."""
    from processing.vision.marker import _chosen

    times = np.linspace(0.0, 4.0, 64)
    way = np.zeros((64, 3))
    way[:, 0], way[:, 1] = 100.0, 100.0
    found = np.ones(64, bool)
    ring = (0.999, 400.0, 100.0, 100.0, 21, 50.0, way, found, 1.6)
    sticker = (0.995, 150.0, 140.0, 90.0, 15, 50.0, way, found, 0.8)
    assert _chosen([ring, sticker], times, (200, 300))[:2] == (140.0, 90.0)


def test_an_amplitude_given_with_a_film_is_carried_to_the_films_rms(short):
    """The student's amplitude (read at the film's start, 8°) is the one the decaying
    film's mean period belongs to only at its start: lab 1 corrects with it times the
    film's RMS-to-start ratio of its envelope."""
    from labs.registry import evaluate

    folder, shot = short
    _, swing = _read(shot.path)
    result = evaluate(_lab1_pendulum(folder, "short.mp4", 'amplitude = "8 deg"\n'),
                      n_samples=500)
    used = result.to_dict()["inputs"]["pendulum.amplitude"]["value"]
    ratio = swing.reference_amplitude / swing.amplitude
    assert ratio < 0.99 and used == pytest.approx(math.radians(8.0) * ratio, rel=1e-6)


def test_the_radial_density_allows_for_the_paths_shape_taken_out_at_the_swing():
    """The path's shape (θ, θ³ of a decaying swing) taken out of the radial residual empties
    part of its periodogram at the swing's frequency: over 300 white series of σ = 1 the
    density allowing for it comes out 1 on average, the plain mean of the five frequencies
    about 20 % low (the u of a phone's shaken film was 10 % short)."""
    from processing.vision.video import _density_at

    t = np.arange(600) / 30.0
    theta = 0.2 * np.exp(-t / 15.0) * np.cos(2 * np.pi * t + 0.3)
    tau = t / t[-1]
    shape = np.column_stack([theta ** j for j in range(4)] + [tau, tau ** 2])
    rng = np.random.default_rng(3)
    allowed, plain = [], []
    for _ in range(300):
        r = rng.standard_normal(t.size)
        r -= shape @ np.linalg.lstsq(shape, r, rcond=None)[0]
        allowed.append(_density_at(t, r, 1.0, shape)[0])
        plain.append(_density_at(t, r, 1.0)[0])
    assert np.mean(allowed) == pytest.approx(1.0, abs=0.06)
    assert np.mean(plain) < 0.88


def test_an_amplitude_whose_limit_reaches_below_zero_is_the_range_above_it():
    """A film whose arc hardly sags reads 1.7° ± 7.8° (truth 6.4°): the correction takes
    the amplitude anywhere in [0, 9.5°], not 1.7° with negative swings folded onto small
    ones; a limit inside the amplitude is kept as read."""
    from types import SimpleNamespace

    def film(value, limit):
        return SimpleNamespace(period_amplitude=value, period_amplitude_limit=limit)

    wide = Filmed.corrected_with.fget(film(math.radians(1.7), math.radians(7.8)))
    assert wide.value == pytest.approx(math.radians(4.75)) and wide.limit == wide.value
    kept = Filmed.corrected_with.fget(film(math.radians(5.0), math.radians(0.3)))
    assert kept.value == pytest.approx(math.radians(5.0))
    assert kept.limit == pytest.approx(math.radians(0.3))


def _two_stickers(frames: int = 64):
    """Frames (BGR) of a grey wall with a red sticker swinging 30 px and a blue one 12 px,
    at the same 0.8 Hz, and their times."""
    t = np.arange(frames) / 16.0
    shots = np.full((frames, 140, 220, 3), 128, np.uint8)
    for k, tk in enumerate(t):
        swing = math.sin(2 * math.pi * 0.8 * tk)
        for (x, y), reach, bgr in (((80, 50), 30, (30, 30, 220)), ((150, 90), 12, (220, 60, 30))):
            cx = int(round(x + reach * swing))
            shots[k, y - 6:y + 7, cx - 6:cx + 7] = bgr
    return shots, t


@pytest.mark.parametrize("colour, at", [(None, (80, 50)), ("blue", (150, 90)),
                                        ("red", (80, 50))])
def test_the_marker_is_the_patch_of_the_colour_named(colour, at):
    """Two stickers swing at the swing's frequency: without a colour the wider swing is the
    marker; named, the sticker of that colour is, wherever it swings."""
    import cv2

    from processing.vision.marker import colour_mask, survey

    shots, t = _two_stickers()
    grey = np.stack([cv2.cvtColor(f, cv2.COLOR_BGR2GRAY) for f in shots])
    masks = None if colour is None else [colour_mask(f, colour) for f in shots]
    marker = survey(grey, t, colours=masks)
    middle = (np.array(marker.region[:2]) + np.array(marker.region[2:])) / 2
    assert np.allclose(middle, at, atol=2), (marker, at)


def test_a_colour_that_does_not_swing_in_the_film_is_refused_at_its_field(short):
    from labs.registry import evaluate
    from processing.diagnostics import InputError

    folder, _ = short
    with pytest.raises(InputError, match="no green patch swings") as exc:
        evaluate(_lab1_pendulum(folder, "short.mp4", 'colour = "green"\n'), n_samples=200)
    assert exc.value.field == "pendulum.colour" and "roi" in exc.value.fix
    assert exc.value.ru is not None


@pytest.mark.parametrize("phase", [math.pi / 4, math.pi / 2])
def test_a_wander_over_the_films_length_is_carried_in_the_periods_u(phase):
    """A phone's slow shake wanders most at one cycle over the film, far below the swing's
    frequency, where the fit's frequency still leaks it: a wander of 0.42 px amplitude
    beside 0.01 px of tracker noise moves a 6° swing's period by up to 5·10⁻⁴, 3 times
    the U the residual's density about the swing gave (the slow-motion films that missed
    by 2.3–5.2 u). Weighed by its own power the u carries it at every phase."""
    from processing.vision.video import _fitted, period_of

    swinger = Swinger.decaying("pendulum", 1.1, math.radians(6.0), 0.5)
    t = np.arange(int(8 * 1.1 * 30)) / 30.0
    theta, _ = swinger.motion(t[-1] + 0.1)
    truth = _fitted(t, 100 * theta(t))[1].period
    wander = 0.3 * math.sqrt(2) * np.sin(2 * np.pi * t / t[-1] + phase)
    s = 100 * theta(t) + wander + np.random.default_rng(1).normal(0.0, 0.01, t.size)
    period = period_of(_fitted(t, s)[1], t, s)
    assert _held(period, truth)


def test_a_few_frames_matched_off_and_back_are_no_dropped_frame(monkeypatch):
    """At 120 frames per second the marker is matched off along its way over 6 frames
    (drifting to 2.5 intervals' worth of the swing's motion) and snaps back: the snap is an
    edge of the swing's timing standing out as a dropped frame's would, and the scan alone
    takes it for one. Judged away from its edge, the frames after it are nearer on time
    than an interval late (a 240 fps film warned so: 0.10 ± 0.33 of an interval late), so
    no frame is found; the same film with a frame dropped there is found, its later frames
    an interval late."""
    from processing.vision import video

    fps = 120.0
    stamps, s = _shaken_track(5, fps=fps)
    _, drifting = video._fitted(stamps, s)
    velocity = (drifting.predict(stamps + 0.25 / fps) - drifting.predict(stamps - 0.25 / fps)) \
        * 2 * fps
    third = stamps.size // 3
    d = third + int(np.argmax(np.abs(velocity[third:2 * third])))
    off = s.copy()
    off[d - 6:d] -= 2.5 * velocity[d] / fps * np.sqrt(np.arange(1, 7) / 6)
    late, se = video._late_beyond(stamps, off, 1 / fps, [], d)
    assert late * fps < 0.5 and late * fps < 1 - 2 * se * fps
    assert video._find_drops(stamps, off, 1 / fps) == []
    with monkeypatch.context() as patched:
        patched.setattr(video, "_lasting", lambda *args: True)
        assert [m for _, m in video._find_drops(stamps, off, 1 / fps)] == [1]
    stamps, s = _shaken_track(5, dropped=(d,), fps=fps)
    found = video._find_drops(stamps, s, 1 / fps)
    assert [m for _, m in found] == [1] and abs(found[0][0] - d / fps) <= 1.5 / fps
    late, se = video._late_beyond(stamps, s, 1 / fps, [], d)
    assert abs(late * fps - 1) < 3 * se * fps
