"""Hostile and odd records of labs 4 (engine vibration) and 7 (torsiograph), issue 27.

Every record here is generated: the sample data's records changed one way (white noise, a
constant channel, a clipped channel, a record cut short, TDC marks that are noise or
missing, a low sample rate), or :mod:`processing.synth.engine_mount`'s records with added
broadband noise of known spectrum. A refusal keeps the bad-input contract
(:func:`cli_contract.assert_one_clear_error`: exit 2, one line naming the file, the field, the
true cause and a fix, nothing written); an odd but valid record is reduced, its values within
their stated intervals of the answer key, with the warning that says what is odd.
"""
import json
import re
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

from cli_contract import ROOT, assert_one_clear_error, run
from labs import lab4_vibration as lab4
from labs.registry import evaluate
from processing.vibration.band_rms import QUANTITIES, band_rms
from processing.inputs.signals import write_csv, write_hdf5
from processing.synth.engine import Engine
from processing.synth.engine_mount import POINTS, Accelerometer, Block, record

LAB4 = ROOT / "sample_data" / "lab4"
LAB7 = ROOT / "sample_data" / "lab7"
FAST = {"n_samples": 2000}
RATE4 = 25600.0
RATE7 = 4000.0
rng = np.random.default_rng(27)


def codes(result):
    return {w.code for w in result.warnings}


def refused(capsys, tmp_path, toml: Path, blamed: Path, field: str, problem: str):
    out = tmp_path / "out"
    code, stdout, stderr = run(capsys, "run", toml, "--out", out)
    assert_one_clear_error(code, stdout, stderr, blamed, field, problem, out)
    return stderr


def within_key(result, key: dict, names, *, first: int = 1) -> None:
    """Every named result within its expanded uncertainty U = k·u of the key; a file that
    keeps one record of the sample numbers its measurements from 1, the key from ``first``."""
    for name in names:
        r = result[name]
        head, number = name.rsplit("_", 1)
        truth = key[f"{head}_{int(number) + first - 1}"]
        assert abs(r.value - truth) <= r.estimate.U, (name, r.value, r.estimate.U, truth)


# ----------------------------------------------------------------------------- lab 4's records

def lab4_copy(tmp_path, mutate=None, *, record_file="r01.h5", toml=None) -> Path:
    """The lab 4 sample in ``tmp_path`` with one record's channels (volts) changed by
    ``mutate(channels, rate)`` and the file's text by ``toml(text)``."""
    folder = tmp_path / "lab4"
    shutil.copytree(LAB4, folder)
    if mutate is not None:
        path = folder / record_file
        with h5py.File(path) as h:
            volts = {k: h[k][...] * h[k].attrs["volts_per_code"] for k in h}
        path.unlink()
        write_hdf5(path, mutate(volts, RATE4), RATE4)
    path = folder / "lab4_seed4.toml"
    if toml is not None:
        path.write_text(toml(path.read_text(encoding="utf-8")), encoding="utf-8")
    return path


def key4() -> dict:
    return json.loads((LAB4 / "answer_key.json").read_text())["results"]


def only(signal: str):
    """The measurement file with this one [[record]] (and the meter's readings)."""
    def keep(text):
        head, *tables = text.split("\n[[")
        return "\n[[".join([head] + [t for t in tables if not t.startswith("record]]")
                                     or f'signal = "{signal}"' in t])
    return keep


def changed(name: str, how):
    def mutate(volts, rate):
        return {**volts, name: how(volts[name], rate)}
    return mutate


def white(x, rate):
    return rng.standard_normal(x.size) * x.std()


def constant(x, rate):
    return np.full(x.size, 0.0123)


def clipped_at(share):
    def clip(x, rate):
        limit = np.quantile(np.abs(x), 1 - share)
        return np.clip(x, -limit, limit)
    return clip


def cut_to(seconds):
    def cut(volts, rate):
        return {k: v[:int(seconds * rate)] for k, v in volts.items()}
    return cut


@pytest.mark.parametrize("mutate, field, problem", [
    (changed("acc1", white), "record[0].channels",
     r"channel 'acc1' holds no vibration above its noise: its broadband floor makes 100 %"),
    (changed("acc2", constant), "record[0].channels", r"channel 'acc2' is flat"),
    (changed("acc3", clipped_at(0.12)), "record[0].channels",
     r"channel 'acc3' is clipped: \d+\.\d % of its samples sit at the recorder's limits"),
    (cut_to(0.3), "record[0].channels",
     r"lasts 0.3 s .*the meter.s band reading needs at least 0.714\d* s"),
    (cut_to(10 / RATE4), "record[0].channels", r"lasts 0.0003906 s \(10 samples\)"),
    (changed("tdc", white), "record[0].tdc_channel", r"channel 'tdc' holds noise, not pulses"),
], ids=["noise", "flat", "clipped", "short", "ten-samples", "tdc-noise"])
def test_lab4_refuses_a_bad_record_with_its_cause(capsys, tmp_path, mutate, field, problem):
    """White noise was refused as 'the sensitivity is likely in the wrong unit', a record
    shorter than the band edge's period was read, and noise on the TDC channel called the
    marks irregular."""
    toml = lab4_copy(tmp_path, mutate)
    refused(capsys, tmp_path, toml, toml.parent / "r01.h5", field, problem)


def test_lab4_refuses_marks_at_twice_the_rate_the_tachometer_contradicts(capsys, tmp_path):
    """TDC marks once per revolution where the file says once per cycle: the marks' speed
    is twice the tachometer's."""
    toml = lab4_copy(tmp_path, toml=lambda t: t.replace('ignition = "all"',
                                                        'ignition = "all"\ntdc = "revolution"', 1))
    refused(capsys, tmp_path, toml, toml.parent / "r01.h5", "record[0].n",
            r"the TDC marks give 50\d min⁻¹ but n = 1007 min⁻¹ \(-50 %\): marks once per "
            "cycle taken for once per revolution")


def test_lab4_names_a_wrong_sample_rate_the_tachometer_contradicts(capsys, tmp_path):
    """Record 1 as a CSV whose stated sample rate is 20 kHz (it was 25.6): the marks give
    787 min⁻¹ against n = 1007, no simple ratio of marks per revolution."""
    folder = tmp_path / "lab4"
    toml = lab4_copy(tmp_path, toml=lambda t: only("r01.h5")(t).replace(
        'signal = "r01.h5"', 'signal = "r01.csv"\nsample_rate = "20 kHz"'))
    with h5py.File(folder / "r01.h5") as h:
        write_csv(folder / "r01.csv", {k: h[k][...] * h[k].attrs["volts_per_code"] for k in h})
    refused(capsys, tmp_path, toml, folder / "r01.csv", "record[0].n",
            r"the TDC marks give 78\d min⁻¹ but n = 1007 min⁻¹ \(-22 %\): a wrong sample rate")


@pytest.fixture(scope="module")
def unmarked(tmp_path_factory):
    """The lab 4 sample with every record's TDC channel taken out."""
    tmp_path = tmp_path_factory.mktemp("unmarked")
    folder = tmp_path / "lab4"
    shutil.copytree(LAB4, folder)
    for path in folder.glob("r0*.h5"):
        with h5py.File(path, "a") as h:
            del h["tdc"]
    return evaluate(folder / "lab4_seed4.toml", **FAST)


def test_lab4_reduces_records_without_tdc_marks(unmarked):
    """Band readings, levels, a and v peak-to-peak, the meter's comparison: within their U of
    the key; the speed, the orders, x's peak-to-peak and the cut cylinder left out, and said
    so."""
    key = key4()
    [w] = [w for w in unmarked.warnings if w.code == "no_tdc_marks"]
    assert "record 1: the recording has no channel 'tdc'" in w.message
    assert "a1_j and a2_j and the cut cylinder need the marks" in w.message
    names = [k for k in key if k.split("_")[0] in QUANTITIES and "_pp_" not in k] \
        + [k for k in key if k.startswith(("a_pp_", "v_pp_"))]
    assert len(names) == 12 * 5
    within_key(unmarked, key, names)
    for left_out in ("n_1", "a1_1", "a2_1", "x_pp_1", "cut_cylinder_4"):
        assert left_out not in unmarked
    assert [(c.a, c.b) for c in unmarked.comparisons][:3] == [
        ("a_rms_4", "a_meter_4"), ("v_rms_4", "v_meter_4"), ("x_rms_4", "x_meter_4")]
    assert "F2_2" in unmarked          # the free force on the tachometer's n
    assert codes(unmarked) == {"no_tdc_marks"}


def test_lab4_a_constant_tdc_channel_leaves_the_record_without_marks(tmp_path):
    toml = lab4_copy(tmp_path, changed("tdc", constant),
                     toml=only("r01.h5"))
    result = evaluate(toml, **FAST)
    [w] = [w for w in result.warnings if w.code == "no_tdc_marks"]
    assert "its TDC channel 'tdc' is constant (0.0123)" in w.message
    within_key(result, key4(), [f"{q}_rms_{j}" for q in QUANTITIES for j in (1, 2, 3)])


def test_lab4_warns_a_clipped_channel_with_its_share(tmp_path):
    """Clipped at 2 % of its samples: reduced, warned with the share, the others untouched."""
    toml = lab4_copy(tmp_path, changed("acc2", clipped_at(0.02)),
                     toml=only("r01.h5"))
    result = evaluate(toml, **FAST)
    [w] = [w for w in result.warnings if w.code == "clipped_record"]
    assert re.search(r"r01.h5, channel 'acc2': (1.9\d|2.0\d) % of the samples", w.message)
    assert "lower the amplifier's gain" in w.message
    within_key(result, key4(), ["a_rms_1", "a_rms_3", "x_rms_1"])


def test_lab4_warns_a_record_sampled_below_the_band_edges(tmp_path):
    """Resampled to 8.53 kHz: a and x bands reach 8 kHz, above its 4267 Hz; v's 2.8 kHz band
    is whole, and within its U of the key."""
    from scipy.signal import resample_poly

    def slow(volts, rate):
        return {k: resample_poly(v, 1, 3) if k != "tdc" else v[::3] for k, v in volts.items()}

    folder = tmp_path / "lab4"
    toml = lab4_copy(tmp_path, toml=lambda t: only("r01.h5")(t).replace(
        'signal = "r01.h5"', 'signal = "r01.csv"\nsample_rate = "8.5333333 kHz"'))
    with h5py.File(folder / "r01.h5") as h:
        volts = {k: h[k][...] * h[k].attrs["volts_per_code"] for k in h}
    write_csv(folder / "r01.csv", slow(volts, RATE4))
    result = evaluate(toml, **FAST)
    [w] = [w for w in result.warnings if w.code == "record_bandwidth"]
    assert "4267 Hz" in w.message and "a 8000 Hz, x 8000 Hz" in w.message
    within_key(result, key4(), ["v_rms_1", "v_rms_2", "v_rms_3", "n_1"])


# ----------------------------------------------------------------------------- lab 4's floor

def noise_of(kind: str, size: int, seed: int) -> np.ndarray:
    """Broadband noise of a known spectrum: white, rising as f² above 20 Hz (an engine's
    combustion and valve noise), or confined below 100 Hz."""
    f = np.fft.rfftfreq(size, 1 / RATE4)
    density = {"white": np.ones_like(f), "rising": (f / 1000) ** 2 * (f > 20),
               "low": (f < 100) * (f > 0) * 1.0}[kind]
    white = np.random.default_rng(seed).standard_normal(size)
    return np.fft.irfft(np.fft.rfft(white) * np.sqrt(density), size)


@pytest.mark.parametrize("kind", ["white", "rising", "low"])
@pytest.mark.parametrize("rpm", [800.0, 3000.0])
def test_the_floor_warning_fires_exactly_where_the_floor_holds_the_reading(kind, rpm):
    """A clean synthetic record plus noise whose own band reading is 3 %, 15 %, 60 % and
    150 % of the record's in one band: the floor estimated (its share of the reading) within
    25 % of the noise's true share, so the warning (share > 0.3) fires where the true share
    is above it and not where it is below (no case lies within 20 % of the threshold)."""
    sensor = Accelerometer(snr_db=300.0)
    rec = record(Engine(), Block(), POINTS, sensor, rpm * np.pi / 30, 1.2, seed=4)
    lowest = 0.5 * rpm / 60
    for p, x in enumerate(rec.volts.values()):
        x = x / sensor.sensitivity
        clean = band_rms(x, RATE4, lowest_line=lowest)
        base = noise_of(kind, x.size, p)
        unit = band_rms(base, RATE4)
        for q in QUANTITIES:
            assert clean.floor[q] < 0.01 * clean[q], (q, "the lines alone are no floor")
            for level in (0.03, 0.15, 0.6, 1.5):
                noise = base * level * clean[q] / unit[q]
                got = band_rms(x + noise, RATE4, lowest_line=lowest)
                true = band_rms(noise, RATE4)[q] / got[q]
                share = got.floor[q] / got[q]
                assert share == pytest.approx(true, rel=0.25), (kind, rpm, p, q, level)
                assert abs(true / lab4.FLOOR_SHARE - 1) > 0.2
                assert (share > lab4.FLOOR_SHARE) == (true > lab4.FLOOR_SHARE)


def median_density(y) -> float:
    """The median periodogram bin of ``y`` over 640–10 240 Hz."""
    f = np.fft.rfftfreq(y.size, 1 / RATE4)
    return float(np.median(np.abs(np.fft.rfft(y))[(f >= 640) & (f <= 10240)] ** 2))


def test_lab4_is_quiet_on_an_engines_broadband_noise(tmp_path):
    """The issue's false alarm: broadband vibration rising with frequency at 10 % of a's
    reading holds 0.01–0.02 % of x's at 2000 min⁻¹; a white floor at its level over
    640–10 240 Hz, carried down to 1.4 Hz, reads 45–58 % of x (what was claimed). Now the
    floor is what it is: no warning, and x within its U."""
    def noisy(volts, rate):
        out = dict(volts)
        for p, name in enumerate(("acc1", "acc2", "acc3")):
            x = volts[name]
            base = noise_of("rising", x.size, p)
            noise = base * 0.1 * band_rms(x, rate)["a"] / band_rms(base, rate)["a"]
            white = noise_of("white", x.size, p)
            white *= np.sqrt(median_density(noise) / median_density(white))
            reading = band_rms(x + noise, rate)["x"]
            assert band_rms(noise, rate)["x"] < 3e-4 * reading
            assert band_rms(white, rate)["x"] > 0.4 * reading
            out[name] = x + noise
        return out

    toml = lab4_copy(tmp_path, noisy, record_file="r02.h5", toml=only("r02.h5"))
    result = evaluate(toml, **FAST)
    assert "noise_floor" not in codes(result)
    within_key(result, key4(), [f"{q}_rms_{j}" for q in "vx" for j in (1, 2, 3)], first=4)


def test_lab4_warns_a_reading_that_rests_on_low_frequency_noise(tmp_path):
    """Noise below 100 Hz as large as x's own reading: x rests on it (warned), a does not."""
    def noisy(volts, rate):
        x = volts["acc1"]
        base = noise_of("low", x.size, 9)
        return {**volts, "acc1": x + base * band_rms(x, rate)["x"] / band_rms(base, rate)["x"]}

    toml = lab4_copy(tmp_path, noisy,
                     toml=only("r01.h5"))
    [w] = [w for w in evaluate(toml, **FAST).warnings if w.code == "noise_floor"]
    assert "x_rms_1" in w.message and "a_rms_1" not in w.message


# ----------------------------------------------------------------------------- lab 7's records

def lab7_copy(tmp_path, mutate=None, *, record_file="r01.csv", toml=None) -> Path:
    """The lab 7 sample in ``tmp_path``, one record's columns changed by ``mutate(columns)``
    and the file's text by ``toml(text)``."""
    folder = tmp_path / "lab7"
    shutil.copytree(LAB7, folder)
    if mutate is not None:
        rows = np.genfromtxt(folder / record_file, delimiter=",", names=True)
        columns = {k: rows[k] for k in rows.dtype.names}
        write_csv(folder / record_file, mutate(columns))
    path = folder / "lab7_seed7.toml"
    if toml is not None:
        path.write_text(toml(path.read_text(encoding="utf-8")), encoding="utf-8")
    return path


def column(name: str, how):
    def mutate(columns):
        return {**columns, name: how(columns[name])}
    return mutate


def drifting_noise(x):
    t = np.arange(x.size) / RATE7
    return 20 * x.std() * np.sin(2 * np.pi * 0.4 * t) + x.std() * rng.standard_normal(x.size)


def clip_crest(share):
    def clip(x):
        mid = np.median(x)
        limit = share * np.abs(x - mid).max()
        return np.clip(x, mid - limit, mid + limit)
    return clip


def first(seconds):
    def cut(columns):
        return {k: v[:max(int(seconds * RATE7), 3)] for k, v in columns.items()}
    return cut


@pytest.mark.parametrize("mutate, field, problem", [
    (column("phi", lambda x: x.std() * rng.standard_normal(x.size)), "record[0].channel",
     r"channel 'phi' holds no oscillation above its noise"),
    (column("phi", lambda x: np.full(x.size, 0.25)), "record[0].channel",
     r"channel 'phi' is flat: its \d+ samples stay at 0.25"),
    (column("phi", clip_crest(0.5)), "record[0].channel", r"channel 'phi' is clipped"),
    (column("phi", drifting_noise), "record[0].channel",
     r"no order stands above its uncertainty .*the baseline drifts"),
    (first(0.0), "record[0].signal",
     r"the record lasts 0.00075 s \(3 samples\), .* too short to hold two TDC marks"),
    (column("tdc", lambda x: 0 * x), "record[0].tdc_channel",
     r"channel 'tdc' is constant \(0\): it holds no TDC marks"),
    (column("tdc", lambda x: rng.standard_normal(x.size)), "record[0].tdc_channel",
     r"channel 'tdc' holds noise, not pulses"),
    (column("marks", lambda x: rng.standard_normal(x.size)), "record[0].marks_channel",
     r"channel 'marks' holds noise, not pulses"),
    (column("marks", lambda x: 0 * x), "record[0].marks_channel",
     r"channel 'marks' is constant \(0\): it holds no time marks"),
], ids=["white-noise", "flat", "clipped", "noise-under-drift", "three-samples",
        "tdc-constant", "tdc-noise", "marks-noise", "marks-constant"])
def test_lab7_refuses_a_bad_record_with_its_cause(capsys, tmp_path, mutate, field, problem):
    """White noise was reduced to ν = 49.8 Hz, K = 1.99 (or ended in an internal
    LinAlgError); noise on the time marks blamed the sample rate, on the TDC marks the
    trace."""
    toml = lab7_copy(tmp_path, mutate)
    refused(capsys, tmp_path, toml, toml.parent / "r01.csv", field, problem)


def test_lab7_reads_one_working_cycle_by_its_single_oscillations(tmp_path):
    """One working cycle (0.15 s at 800 min⁻¹) was refused; the manual reads single
    oscillations on it: reduced, and warned that its orders are left out."""
    result = evaluate(lab7_copy(tmp_path, first(0.15)), **FAST)
    assert result["phi_max_1"].value > 0
    assert any(w.code == "short_record" and "records 1 (1.0)" in w.message
               for w in result.warnings)


def test_lab7_names_a_wrong_sample_rate_the_tachometer_contradicts(capsys, tmp_path):
    """Record 1 without its time marks and a stated 3 kHz (it was 4): the marks give
    602 min⁻¹ against n = 803."""
    toml = lab7_copy(tmp_path, toml=lambda t: t.replace(
        'signal = "r01.csv"\nsample_rate = "4 kHz"\nchannel = "phi"\nmarks_channel = "marks"',
        'signal = "r01.csv"\nsample_rate = "3 kHz"\nchannel = "phi"', 1))
    refused(capsys, tmp_path, toml, toml.parent / "r01.csv", "record[0].n",
            r"the TDC marks give 60\d min⁻¹ but n = 803 min⁻¹ \(-25 %\): a wrong sample rate")


def test_lab7_warns_a_clipped_trace_with_its_share(tmp_path):
    """A trace clipped at 80 % of its crest (φ_max 4 % low): reduced, and warned with the
    share of its samples at the limits."""
    toml = lab7_copy(tmp_path, column("phi", clip_crest(0.8)), record_file="r06.csv",
                     toml=lambda t: "[[record]]".join(t.split("[[record]]")[:1] + [
                         r for r in t.split("[[record]]")[1:] if '"r0' in r and any(
                             f'"r0{i}.csv"' in r for i in (5, 6, 7))]))
    result = evaluate(toml, **FAST)
    [w] = [w for w in result.warnings if w.code == "clipped_record"]
    assert "r06.csv, channel 'phi'" in w.message and "% of the samples sit at the" in w.message


LAB7_HEAD = """lab = "lab7"
[engine]
cylinders = 4
strokes = 4
firing_order = "1-3-4-2"
"""
CHAIN = """[chain]
J = { readings = [0.05, 0.035, 0.035, 0.035, 0.035, 1.3], u = "0.0007 kg*m^2" }
c = { readings = [520000, 780000, 780000, 780000, 610000], u = "10400 N*m/rad" }
"""


def test_lab7_reduces_the_chain_alone(capsys, tmp_path):
    """Before the test: the sample's chain without any record gives its modes (the first
    within its U of the key's 199.9 Hz), the phase sums (1 for the major orders) and the
    critical speeds 60 f/k; the report is written."""
    toml = tmp_path / "chain.toml"
    toml.write_text(LAB7_HEAD + CHAIN, encoding="utf-8")
    code, out, err = run(capsys, "run", toml, "--out", tmp_path / "out", "--json")
    assert code == 0, err
    results = json.loads(out)["results"]
    key = json.loads((LAB7 / "answer_key.json").read_text())["results"]
    f1 = results["f_model_1"]
    assert abs(f1["value"] - key["f_model_1"]) <= 2 * f1["u"]
    for k in (2, 4, 6, 8, 10, 12):
        assert results[f"phase_sum_1_{k}"]["value"] == pytest.approx(1.0, abs=1e-9)
        assert results[f"n_crit_1_{k}"]["value"] == pytest.approx(
            2 * np.pi * f1["value"] / k, rel=1e-6)
    assert not any(name.startswith(("phi_max", "l", "n_res")) for name in results)
    assert (tmp_path / "out" / "chain.html").exists()


def test_lab7_refuses_a_file_without_records_or_chain(capsys, tmp_path):
    toml = tmp_path / "empty.toml"
    toml.write_text(LAB7_HEAD, encoding="utf-8")
    refused(capsys, tmp_path, toml, toml, "record",
            r"neither records nor the equivalent chain are given")


def test_lab7_refuses_records_without_their_calibration(capsys, tmp_path):
    def drop(text):
        head, rest = text.split("[calibration]")
        return head + "[chain]" + rest.split("[chain]", 1)[1]

    toml = lab7_copy(tmp_path, toml=drop)
    refused(capsys, tmp_path, toml, toml, "calibration",
            r"records are given but section \[calibration\] is missing")


@pytest.mark.parametrize("rate", [0.0, float("nan"), 1e3])
def test_lab7_scene_refuses_a_sample_rate_below_its_orders(tmp_path, rate):
    """The scene's own guard (the command line refuses such rates before it, by
    labs.cli.synth_options): a rate that does not hold the orders writes nothing."""
    from labs.lab7_torsiograph import write_synthetic
    from processing.diagnostics import InputError

    out = tmp_path / "synth"
    with pytest.raises(InputError, match="does not hold the orders up to 24"):
        write_synthetic(out, sample_rate=rate)
    assert not out.exists() or not any(out.iterdir())
