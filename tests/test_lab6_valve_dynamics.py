"""Lab 6: the valve drive's forces and oscillations end to end — the sample against its
answer key, the reports, the warnings where the drive separates or the records mislead, and
bad input refused with the file, the field and the fix.

The synthetic drive (:mod:`processing.synth.valve_drive`) knows its forces, its free
oscillations' frequency, its valve events, its losses of contact and the speed at which it
separates; the lab must recover them within the uncertainty it states.
"""
import json
import math
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

from labs import lab6_valve_dynamics as lab6
from labs.registry import evaluate
from processing.diagnostics import InputError
from processing.measurement import template
from processing.reporting.render import render
from processing.synth.valve_drive import RPM, Cam, Drive, simulate_event

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "sample_data" / "lab6" / "lab6_seed6.toml"
FAST = {"n_samples": 2000}
SMALL = dict(speeds=(1000.0, 1500.0, 1800.0), clearances=(0.8e-3,), valves=("in",), part=0)
"""Three records through the 0.8 mm drive's separation (near 1626 min⁻¹: part 0, the scene's
drive under any seed's readings), the inlet only."""


def reduce(path, **options):
    """Load and reduce like ``dynlab run``, with fewer Monte Carlo draws."""
    return evaluate(path, **{**FAST, **options})


def codes(result):
    return {w.code for w in result.warnings}


def synthetic(folder, **options):
    written = lab6.write_synthetic(folder, seed=3, **{**SMALL, **options})
    return written, json.loads(written["answer"].read_text())["results"]


def edit(path: Path, old: str, new: str, count: int = 1) -> None:
    text = path.read_text()
    assert old in text, old
    path.write_text(text.replace(old, new, count))


# ----------------------------------------------------------------------------- the sample

@pytest.fixture(scope="module")
def sample():
    return reduce(SAMPLE)


@pytest.fixture(scope="module")
def key():
    return json.loads((SAMPLE.parent / "answer_key.json").read_text())["results"]


def test_sample_recovers_its_answer_key(sample, key):
    """Every keyed result within 3 u of the truth, except a ν whose opening rings too weakly
    for a fit (named by a warning: at 500 min⁻¹ and 0.3 mm the lash closes at a crawl); the
    separation speed within 3 % besides."""
    missing = {name for name in key if name not in sample}
    assert len(missing) <= 2 and all(name.startswith("nu_") for name in missing)
    poor = [w.message for w in sample.warnings if w.code == "free_oscillation_poor"]
    assert bool(poor) == bool(missing)
    for name in missing:
        _, valve, i = name.split("_")
        assert f"{i} ({valve}: none fitted)" in poor[0]
    for name in set(key) - missing:
        r, truth = sample[name], key[name]
        assert abs(r.value - truth) <= 3 * r.u + 1e-9 * abs(truth), (name, r.value, r.u, truth)
    for name in ("n_sep_in_800", "n_sep_ex_800"):
        assert sample[name].value == pytest.approx(key[name], rel=0.03)


def test_sample_warns_that_the_drive_separates(sample):
    """At 0.8 mm the drive loses contact at 1800 and 2000 min⁻¹; nothing else is suspect
    but, at most, the weak ringing of a slow, tight record."""
    assert "contact_lost" in codes(sample)
    assert codes(sample) <= {"contact_lost", "free_oscillation_poor"}
    lost = next(w for w in sample.warnings if w.code == "contact_lost").message
    assert "records 14 (in, δ = 0.8 mm" in lost and "separates at in, δ = 0.8 mm" in lost


def test_sample_reports_render_in_html_and_json_in_both_languages(sample):
    for lang in ("en", "ru"):
        out = render(sample, ("html", "json"), lang)     # the PDFs: test_report_layout
        assert len(out["html"]) > 10_000
        assert "n_sep_in_800" in json.loads(out["json"])["results"]
    assert "разрыв" in out["html"].decode("utf-8")
    assert [f.name for f in sample.figures] == ["calibration", "traces", "forces", "phases"]


def test_the_manuals_formulas():
    assert lab6.force(1500 / 90, 90.0) == pytest.approx(1500.0)
    # φ = 360 T_open/T_cam: a quarter of the camshaft's revolution is 90°
    assert math.degrees(lab6.opening_duration(0.25, 1.0)) == pytest.approx(90.0)
    # the line through (1000, 100 N) and (1500, 50 N) reaches 0 at 2000
    assert lab6.separation_speed(1000.0, 100.0, 1500.0, 50.0) == pytest.approx(2000.0)


def test_template_lists_every_section():
    text = template(lab6.SPEC, "ru")
    for section in ("[engine]", "[[valve]]", "[[record]]", "[image]"):
        assert section in text


# ----------------------------------------------------------------------------- the scene's physics

def test_the_scene_is_static_at_a_crawl():
    """Without lash at a crawl inertia and damping vanish: at full lift the drive and the
    springs are two springs in series, P = c (P₀ + c_n h_max)/(c + c_n), and the valve opens
    on the ramp (slope v_r, cam speed ω) where c h + b ω v_r = P₀. The inertia's share of
    P_max grows as ω²: 2·10⁻⁶ at 0.3 rad/s, 2·10⁻⁵ at 1 rad/s, 9·10⁻⁵ at 2 rad/s (38 min⁻¹
    of the crankshaft), where the simulation is half as long as at 1 rad/s."""
    cam, drive = Cam(), Drive()
    w = 2.0
    slow = simulate_event(cam, drive, 0.0, w)
    h_max = float(cam.profile(cam.total_angle / 2)[0])
    c, c_n, P0 = drive.c, drive.c_n, drive.P0
    assert slow.P_max == pytest.approx(c * (P0 + c_n * h_max) / (c + c_n), rel=2e-4)
    ramp = cam.ramp / cam.ramp_angle
    assert slow.opening == pytest.approx((P0 - drive.b * w * ramp) / (c * ramp), rel=1e-9)
    assert slow.loss == 0


def test_a_larger_clearance_separates_earlier():
    """The lash is taken up higher on the flank at a larger clearance: the impact grows,
    P_min falls faster with the speed and the opening is shorter."""
    cam, drive = Cam(), Drive()
    w = 1500 * RPM / 2
    small, large = (simulate_event(cam, drive, d, w) for d in (0.3e-3, 0.8e-3))
    assert large.P_min < small.P_min
    assert large.closing - large.opening < small.closing - small.opening
    assert large.P_max > small.P_max


# ----------------------------------------------------------------------------- round trips

def test_hdf5_records_round_trip(tmp_path):
    written, truth = synthetic(tmp_path, fmt="h5")
    result = reduce(written["toml"])
    assert result["n_sep_in_800"].value == pytest.approx(truth["n_sep_in_800"], rel=0.03)
    for i in (1, 2):
        for name in ("P_max", "P_min", "phi", "advance", "lag", "nu"):
            r, true = result[f"{name}_in_{i}"], truth[f"{name}_in_{i}"]
            assert abs(r.value - true) <= 3 * r.u, (name, i, r.value, r.u, true)
    assert result["loss_in_3"].value > 0 and result["loss_in_1"].value == 0


def test_each_variant_draws_its_own_drive(tmp_path):
    """Seeds 2 and 1 draw their own cam and drive (the preload in the file, the force and
    the drive's frequency in the key differ); over SMALL's speeds seed 2's drive separates
    at 0.8 mm, and every key value lies within 3 u of its reduction, as the sample's. (One
    value in a few hundred lies beyond: seeds 0–20's full programmes, 5 of 5439; the scene's
    drive, 4.)"""
    options = {k: v for k, v in SMALL.items() if k != "part"}
    two = lab6.write_synthetic(tmp_path / "2", seed=2, **options)
    one = lab6.write_synthetic(tmp_path / "1", seed=1, **{**options, "speeds": (1000.0,)})
    keys = [json.loads(w["answer"].read_text())["results"] for w in (two, one)]
    texts = [tomllib.loads(w["toml"].read_text()) for w in (two, one)]
    assert texts[0]["valve"][0]["P0"] != texts[1]["valve"][0]["P0"]
    assert keys[0]["nu_in_1"] != keys[1]["nu_in_1"]
    assert keys[0]["P_max_in_1"] != keys[1]["P_max_in_1"]
    result = reduce(two["toml"])
    assert "n_sep_in_800" in keys[0] and "contact_lost" in codes(result)
    for name, truth in keys[0].items():
        r = result[name]
        assert abs(r.value - truth) <= 3 * r.u + 1e-9 * abs(truth), (name, r.value, r.u, truth)


def test_the_separation_is_not_claimed_without_a_loss(tmp_path):
    """Where every record keeps contact, no separation speed is given and nothing warns of
    contact."""
    written, truth = synthetic(tmp_path, speeds=(500.0, 1000.0, 1500.0))
    result = reduce(written["toml"])
    assert not any(name.startswith("n_sep") for name in result.results)
    assert "contact_lost" not in codes(result)
    assert all(result[f"P_min_in_{i}"].value > 0 for i in (1, 2, 3))


def test_a_bent_calibration_warns(tmp_path):
    written, _ = synthetic(tmp_path, speeds=(1000.0,), bend=0.06)
    assert "table_curvature" in codes(reduce(written["toml"]))


def test_a_tachometer_far_from_the_marks_warns_then_is_refused(tmp_path):
    written, _ = synthetic(tmp_path, speeds=(1000.0,))
    toml = written["toml"]
    edit(toml, re.search(r'n = "\d+ ± 10 rpm"', toml.read_text()).group(0),
         'n = "1060 ± 10 rpm"')
    assert "inconsistent_input" in codes(reduce(toml))
    edit(toml, 'n = "1060 ± 10 rpm"', 'n = "2000 ± 10 rpm"')
    with pytest.raises(InputError, match="TDC marks give 10.. min⁻¹") as err:
        reduce(toml)
    assert err.value.field == "record[0].n"


def test_noisy_records_widen_the_stated_uncertainty(tmp_path):
    """At a quarter of the sample's SNR the forces' u grows in proportion and still holds the
    truth."""
    quiet, truth = synthetic(tmp_path / "q", speeds=(1000.0,))
    loud, _ = synthetic(tmp_path / "l", speeds=(1000.0,), snr_db=40.0)
    a, b = reduce(quiet["toml"]), reduce(loud["toml"])
    assert b["P_max_in_1"].u > 3 * a["P_max_in_1"].u
    assert abs(b["P_max_in_1"].value - truth["P_max_in_1"]) <= 3 * b["P_max_in_1"].u


# ----------------------------------------------------------------------------- bad input

def test_a_missing_force_channel_names_the_channels(tmp_path):
    written, _ = synthetic(tmp_path, speeds=(1000.0,))
    edit(written["toml"], 'name = "in"\n', 'name = "in"\nchannel = "inlet"\n')
    with pytest.raises(InputError, match="inlet") as err:
        reduce(written["toml"])
    assert err.value.field == "record[0].signal"


def test_a_wrong_sample_rate_is_caught_by_the_time_marks(tmp_path):
    written, _ = synthetic(tmp_path, speeds=(1000.0,))
    edit(written["toml"], 'sample_rate = "10 kHz"', 'sample_rate = "12 kHz"')
    with pytest.raises(InputError, match="time marks come every"):
        reduce(written["toml"])


def test_a_calibration_that_does_not_pair_is_refused(tmp_path):
    written, _ = synthetic(tmp_path, speeds=(1000.0,))
    text = written["toml"].read_text()
    loads = re.search(r"load = \[[^\]]*\]", text).group(0)
    edit(written["toml"], loads, loads.replace("[0, ", "["))
    with pytest.raises(InputError, match="5 loads but 6 deflections") as err:
        reduce(written["toml"])
    assert err.value.field == "valve[0].deflection"


def test_too_short_a_record_is_refused(tmp_path):
    """Half a camshaft revolution holds no whole opening."""
    written, _ = synthetic(tmp_path, speeds=(1000.0,), revolutions=0.9)
    with pytest.raises(InputError, match="(TDC mark|no whole valve event)"):
        reduce(written["toml"])


def test_the_trace_zero_and_events_of_a_plain_hump():
    """A half-sine force pulse on a known zero: the events' crossings of a level are where
    the sine passes it, and the extremes are the sine's."""
    from processing.valvetrain.valve_force import trace_zero, valve_events

    rate, T = 10e3, 0.05
    t = np.arange(int(0.2 * rate)) / rate
    rng = np.random.default_rng(2)
    hump = np.where((t > 0.07) & (t < 0.07 + T), 30 * np.sin(np.pi * (t - 0.07) / T), 0.0)
    x = 2.0 + hump + 0.05 * rng.standard_normal(t.size)
    zero = trace_zero(x)
    assert zero.level == pytest.approx(2.0, abs=0.01)
    (e,) = valve_events(t, x - zero.level, 15.0, noise=zero.noise, period=0.005)
    # 30 sin(π τ/T) = 15 at τ = T/6 and 5T/6
    assert e.opening == pytest.approx(0.07 + T / 6, abs=1 / rate)
    assert e.closing == pytest.approx(0.07 + 5 * T / 6, abs=1 / rate)
    assert e.P_max == pytest.approx(30.0, abs=3 * e.u_P)
    assert e.loss == 0


# ----------------------------------------------------------------------------- photographs

def test_photographed_oscillograms_hold_their_truth(tmp_path):
    """Phone photographs of the paper (the drive's 450 Hz ringing spans 25–90 px a period):
    the traces at rest between events are not taken for straight lines, the crests are
    read off the stroke's outer edge, and every result holds its truth within its 95 %
    interval, widened by what a stroke's width hides (the extremes, the events' times)."""
    written, truth = synthetic(tmp_path, image=True)
    assert written["r1"].suffix == ".jpg"
    result = reduce(written["toml"])
    held = [name for name in truth if name in result
            and abs(result[name].value - truth[name]) <= result[name].estimate.U + 1e-9]
    assert len(held) == len(truth), sorted(set(truth) - set(held))
    assert "contact_lost" in codes(result)
    assert [f.name for f in result.figures][4:] == [f"paper_record_{i}" for i in (1, 2, 3)]


def test_photographs_under_a_camera_of_their_own_hold_their_truth(tmp_path):
    """A phone held otherwise (the benchmark's camera drawn for seed 2: skew, perspective,
    blur, noise, JPEG quality and light of its own) on a drive of its own: every result's
    95 % interval holds its truth. (Benchmark ``photographed``, 12 sweeps of both valves:
    ν's interval had held it in about 70 % of the records that lose contact while ν was fitted
    on a cubic baseline alone.)"""
    from labs.bench.valve_dynamics import drawn_shot

    written = lab6.write_synthetic(tmp_path, seed=2, image=True, shot=drawn_shot(2),
                                   **{**SMALL, "part": 2})
    truth = json.loads(written["answer"].read_text())["results"]
    result = reduce(written["toml"])
    missed = [name for name in truth if name in result
              and not result[name].estimate.interval95[0] <= truth[name]
              <= result[name].estimate.interval95[1]]
    assert missed == [], missed
    assert {name for name in truth if name.startswith("nu_")} <= set(result.to_dict()["results"])
