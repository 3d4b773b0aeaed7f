"""Records that are not what they claim (issue 27), labs 3, 6 and 9.

Every record here is made in the test from the lab's sample data (or its synthetic scene):
flat, white noise, clipped a little or a lot, too short, too fast for its sample rate, all
zero; and the calibrations beside them constant, turning back, of one point. A bad record
must keep the bad-input contract of :func:`cli_contract.assert_one_clear_error` with its
true cause (flat, noise, clipped, too short), its file, its field and a fix; a record that is
odd but usable (clipped where the lab reduces around the clipped samples, or a pulse train,
whose edges clipping does not move) must give the right value within its stated interval.
And correct data must stay quiet: the samples warn exactly what they warned before.
"""
import json
import shutil
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy import stats
from scipy.io import wavfile

from cli_contract import ROOT, assert_one_clear_error, run
from labs.registry import evaluate
from processing.oscillations.decay import analyse_decay
from processing.diagnostics import InputError
from processing.inputs.record_quality import (check_frequency, check_pulse_channel, check_pulses,
                                       check_record, clipped_mask, periodicity)
from processing.inputs.signals import open_channel, write_hdf5
from processing.synth.damper import Ring, StrainGauge, free_decay
from processing.inputs.toml_writer import dumps

SAMPLES = ROOT / "sample_data"


def copy_sample(tmp_path: Path, folder: str, toml: str) -> Path:
    """The sample's folder copied into the test's own; its measurement file's path."""
    shutil.copytree(SAMPLES / folder, tmp_path / folder)
    return tmp_path / folder / toml


def change_column(path: Path, column: str, change) -> None:
    """Rewrite one column of a CSV recording (``change`` may also cut rows: a frame)."""
    frame = pd.read_csv(path)
    if column is None:
        frame = change(frame)
    else:
        frame[column] = change(frame[column].to_numpy(dtype=float))
    frame.to_csv(path, index=False, float_format="%.6g")


def change_wav(path: Path, change) -> None:
    rate, x = wavfile.read(path)
    y = np.clip(np.round(change(x.astype(float))), -32768, 32767).astype(np.int16)
    wavfile.write(path, rate, y)


def edit_toml(path: Path, edit) -> None:
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    edit(data)
    path.write_text(dumps(data), encoding="utf-8")


def clip(level: float):
    """Clipped at ``level`` of the way from the record's median to each extreme: an
    overloaded amplifier or converter holding its limit."""
    def change(x):
        mid = np.median(x)
        return np.clip(x, mid - level * (mid - x.min()), mid + level * (x.max() - mid))
    return change


def noise(x):
    return np.random.default_rng(7).normal(np.mean(x), np.std(x), x.size)


def refused(capsys, toml: Path, file: Path, field, problem: str) -> None:
    out = toml.parent / "out"
    code, stdout, err = run(capsys, "run", toml, "--out", out)
    assert_one_clear_error(code, stdout, err, file, field, problem, out)


def reported(capsys, toml: Path) -> dict:
    """The result JSON of an accepted file (printed, nothing written)."""
    code, out, err = run(capsys, "run", toml, "--json")
    assert code == 0 and "Traceback" not in err, err
    return json.loads(out)


def key(toml: Path) -> dict:
    return json.loads((toml.parent / "answer_key.json").read_text(encoding="utf-8"))["results"]


def codes(doc: dict) -> set:
    return {w["code"] for w in doc["warnings"]}


def inside(doc: dict, name: str, truth: float) -> bool:
    lo, hi = doc["results"][name]["interval95"]
    return lo <= truth <= hi


# ------------------------------------------------------------------ the checks themselves

def test_a_one_sample_pulse_train_is_rough_but_no_noise():
    """Narrow marks make even a clean channel rough (ρ ≈ 1): the pulse check asks whether it
    repeats instead, which noise does not."""
    marks = (np.arange(20000) % 400 == 0).astype(float)
    assert periodicity(marks) > 0.9
    check_pulses(marks, 1e4, file="r.csv", field="record[0].tdc_channel", channel="tdc")
    with pytest.raises(InputError, match="channel 'tdc' holds no TDC marks above its noise"):
        check_pulses(noise(marks), 1e4, file="r.csv", field="record[0].tdc_channel",
                     channel="tdc", pulses="TDC marks")


def test_a_logic_channel_of_two_codes_is_not_flat():
    marks = (np.arange(5000) % 100 < 3).astype(np.int16)
    check_pulses(marks, 1e4, file="r.csv", field="f", channel="m")
    with pytest.raises(InputError, match="is flat: its 5000 samples stay at 0"):
        check_pulses(np.zeros(5000), 1e4, file="r.csv", field="f", channel="m")


def test_a_long_pulse_channel_is_checked_on_a_bounded_stretch(tmp_path):
    """Only the first ``head`` samples are read: a channel whose later samples are NaN (the
    reader refuses those when it reaches them) passes the check unread there."""
    x = np.sin(2 * np.pi * np.arange(200000) / 40.0)
    x[50000:] = np.nan
    write_hdf5(tmp_path / "r.h5", {"tooth": x}, 48e3)
    channel = open_channel(tmp_path / "r.h5", field="regime[0].signal")
    assert check_pulse_channel(channel, field="regime[0].signal", head=4096) > 0.9
    with pytest.raises(InputError, match="sample 50000"):
        channel.read()


def test_an_oscillation_faster_than_a_third_of_the_rate_is_not_called_noise():
    t = np.arange(4000) / 20e3
    with pytest.raises(InputError, match="faster than a third of its sample rate.*Fix: record "
                                         "at a higher sample rate"):
        check_record(np.exp(-5 * t) * np.sin(2 * np.pi * 9e3 * t), 20e3, file="d.csv",
                     field="decay.signal", channel="u")


def test_check_record_keeps_its_defaults_and_takes_a_fix_and_an_effect():
    """Backwards compatible: a lab that says nothing gets the sensor's fix and the peaks'
    consequence; one that fits around the clipped samples says so."""
    t = np.arange(20000) / 1e4
    x = np.clip(np.round(np.sin(2 * np.pi * 7 * t) * 1000), -998, 998)
    for effect, said in ((None, "peaks there are cut off"), (("left out", "исключены"),
                                                             "left out")):
        with pytest.warns(UserWarning, match=said):
            check_record(x, 1e4, file="r.csv", field="f", channel="u",
                         **({} if effect is None else {"clipped_effect": effect}))
    with pytest.raises(InputError, match="Fix: take another photograph"):
        check_record(np.zeros(100), 1e4, file="r.jpg", field="f", channel="trace 0",
                     fix="take another photograph")


def test_a_logic_channel_named_for_a_sensor_is_not_called_an_overload_alone():
    """TDC pulses with shaped edges sit at their two levels in nearly every sample: refused
    as a logic channel (or a sensor clipped past recognition), whatever share a lab allows."""
    k = np.arange(20000)
    tdc = np.interp(k % 2000, [0, 3, 17, 20, 2000], [0.0, 1.0, 1.0, 0.0, 0.0])
    with pytest.raises(InputError, match=r"sits at its two extremes in 100 % of its samples: "
                                         r"a logic channel.*Fix: name the sensor's own channel"):
        check_record(tdc, 1e4, file="r.csv", field="decay.signal", channel="tdc",
                     clip_refused=1.0)


@pytest.mark.parametrize("f, problem", [(6e3, "above the record's Nyquist frequency"),
                                        (1.0, "slower than one cycle over the record")])
def test_a_frequency_the_record_cannot_hold_is_refused(f, problem):
    with pytest.raises(InputError, match=problem):
        check_frequency(f, 10e3, 0.5, file="r.csv", field="record[0].signal", what="ν")


# ------------------------------------------------------------------------------------ lab 3

LAB3 = ("lab3", "engine_2regimes.toml")


@pytest.mark.parametrize("wav, field", [("regime1.wav", "regime[0].signal"),
                                        ("coast.wav", "wheel.calibration")])
@pytest.mark.parametrize("change, problem", [
    (np.zeros_like, r"is flat: its \d+ samples stay at 0, no tooth pulses to time"),
    (noise, r"holds no tooth pulses above its noise"),
], ids=["flat", "noise"])
def test_lab3_flat_or_noise_sensor_is_refused_as_such(tmp_path, capsys, wav, field, change,
                                                      problem):
    toml = copy_sample(tmp_path, *LAB3)
    change_wav(toml.parent / wav, change)
    refused(capsys, toml, toml.parent / wav, field, problem + ".*Fix: check that the sensor")


@pytest.mark.parametrize("level", [0.5, 0.1])
def test_lab3_clipped_sensor_is_timed_right_and_unwarned(tmp_path, capsys, level):
    """An inductive sensor's pulses clipped (even to a tenth of their height) keep their
    edges where they cross the mean level: δ stays right, nothing to warn."""
    toml = copy_sample(tmp_path, *LAB3)
    change_wav(toml.parent / "regime1.wav", lambda x: np.clip(x, -level * np.abs(x).max(),
                                                              level * np.abs(x).max()))
    doc = reported(capsys, toml)
    assert codes(doc) == set(), doc["warnings"]
    assert inside(doc, "delta_1", key(toml)["delta_1"])


def test_lab3_too_short_a_recording_says_so(tmp_path, capsys):
    toml = copy_sample(tmp_path, *LAB3)
    change_wav(toml.parent / "regime1.wav", lambda x: x[:4000])
    refused(capsys, toml, toml.parent / "regime1.wav", "regime[0].signal",
            r"no complete working cycle.*Fix: record at least two working cycles")


@pytest.mark.parametrize("change, problem", [
    (np.zeros_like, r"channel 'tdc' is flat.*no TDC marks to time"),
    (noise, r"channel 'tdc' holds no TDC marks above its noise"),
], ids=["flat", "noise"])
def test_lab3_flat_or_noise_tdc_channel_is_refused_at_it(tmp_path, capsys, change, problem):
    toml = copy_sample(tmp_path, *LAB3)
    rate, tooth = wavfile.read(toml.parent / "regime1.wav")
    tdc = change((np.arange(tooth.size) % 3200 < 20).astype(float))
    pd.DataFrame({"u": tooth, "tdc": tdc}).to_csv(toml.parent / "regime1.csv", index=False)

    def with_tdc(data):
        data["regime"][0].update(signal="regime1.csv", channel="u", tdc_channel="tdc",
                                 sample_rate=f"{rate / 1e3:g} kHz")
    edit_toml(toml, with_tdc)
    refused(capsys, toml, toml.parent / "regime1.csv", "regime[0].tdc_channel", problem)


def test_lab3_oscillogram_read_upside_down_is_refused_at_its_readings(tmp_path, capsys):
    """h_max below h_min would make δ negative: the readings are refused where written."""
    toml = copy_sample(tmp_path, *LAB3)
    edit_toml(toml, lambda d: d["regime"][0].update(h_max="88.6 ± 0.2 mm"))
    refused(capsys, toml, toml, "regime[0].h_max", r"h_max = 88.6 mm is not above h_min "
            r"= 89 mm.*Fix: .*not swapped")


# ------------------------------------------------------------------------------------ lab 6

LAB6 = ("lab6", "lab6_seed6.toml")


def lab6_first_records(tmp_path, count: int = 3) -> Path:
    """The lab 6 sample with its first ``count`` records (the third is r03.csv)."""
    toml = copy_sample(tmp_path, *LAB6)
    edit_toml(toml, lambda d: d.update(record=d["record"][:count]))
    return toml


@pytest.mark.parametrize("column, field, change, problem", [
    ("in", "record[2].signal", lambda x: np.full_like(x, x[0]),
     r"channel 'in' is flat: its \d+ samples stay at .*Fix: check that the sensor"),
    ("in", "record[2].signal", np.zeros_like, r"channel 'in' is flat"),
    ("in", "record[2].signal", noise, r"channel 'in' holds no oscillation above its noise"),
    ("in", "record[2].signal", clip(0.6), r"channel 'in' is clipped: \d+\.\d % of its samples "
     r"sit at the recorder's limits.*Fix: lower the amplifier's gain"),
    ("ex", "record[2].signal", clip(0.3), r"channel 'ex' is clipped"),
    ("tdc", "record[2].tdc_channel", np.zeros_like, r"channel 'tdc' is flat.*no TDC marks"),
    ("tdc", "record[2].tdc_channel", noise, r"channel 'tdc' holds no TDC marks above its "
     r"noise"),
    ("marks", "record[2].marks_channel", np.zeros_like, r"channel 'marks' is flat.*no time "
     r"marks.*Fix: check the time-mark generator"),
    ("marks", "record[2].marks_channel", noise, r"channel 'marks' holds no time marks above "
     r"its noise"),
], ids=["flat", "zero", "noise", "clipped", "clipped-ex", "tdc-flat", "tdc-noise",
        "marks-flat", "marks-noise"])
def test_lab6_record_that_is_not_what_it_claims(tmp_path, capsys, column, field, change,
                                                problem):
    toml = lab6_first_records(tmp_path)
    change_column(toml.parent / "r03.csv", column, change)
    refused(capsys, toml, toml.parent / "r03.csv", field, problem)


def test_lab6_one_channel_named_for_a_valve_and_the_tdc_marks(tmp_path, capsys):
    toml = lab6_first_records(tmp_path, 1)
    edit_toml(toml, lambda d: d["valve"][0].update(channel="tdc"))
    refused(capsys, toml, toml, "record[0].tdc_channel", r"channel 'tdc' is named both for "
            r"the inlet valve's force and for the TDC marks")


def test_lab6_too_short_a_record_says_so(tmp_path, capsys):
    toml = lab6_first_records(tmp_path)
    change_column(toml.parent / "r03.csv", None, lambda frame: frame.iloc[:500])
    refused(capsys, toml, toml.parent / "r03.csv", "record[2].signal",
            r"it lasts 0.06\d* s, shorter than the two camshaft revolutions .* \(0.16 s at n = "
            r"15\d\d min⁻¹\).*Fix: record at least two camshaft revolutions")


def test_lab6_a_little_clipped_warns_and_leaves_out_the_cut_largest_force(tmp_path, capsys):
    """A trace clipped at its crests: warned with the share; P_max of that record is not
    read off the cut crests (left out), and what the clipping does not touch stays right."""
    toml = lab6_first_records(tmp_path)
    change_column(toml.parent / "r03.csv", "in", clip(0.95))
    doc = reported(capsys, toml)
    truth = key(toml)
    warned = [w["message"] for w in doc["warnings"] if w["code"] == "clipped_record"]
    assert len(warned) == 1 and "r03.csv, channel 'in': 0.4" in warned[0], warned
    assert "P_max_in_3" not in doc["results"] and "P_max_ex_3" in doc["results"]
    for name in ("P_min_in_3", "nu_in_3", "phi_in_3", "advance_in_3", "P_max_in_2"):
        assert inside(doc, name, truth[name]), name


@pytest.mark.parametrize("deflection, problem", [
    ([50, 50, 50, 50, 50, 50], r"the deflections never change: every one of the 6 is 50"),
    ([0, 0, 0, 0, 0, 0], r"the deflections never change"),
    ([0, 18, 36, 10, 72, 90], r"deflection 4 \(10\) turns back past deflection 3 \(36\)"),
    ([0, 18, 36, 54, 72, 89.9], None),
], ids=["constant", "zero", "turns-back", "within-limit"])
def test_lab6_calibration_that_cannot_give_a_scale(tmp_path, capsys, deflection, problem):
    toml = lab6_first_records(tmp_path, 1)
    edit_toml(toml, lambda d: d["valve"][0].update(deflection=deflection))
    if problem is None:
        assert "k_in" in reported(capsys, toml)["results"]
    else:
        refused(capsys, toml, toml, "valve[0].deflection", problem + ".*Fix: read the trace's "
                "deflection again")


def test_lab6_calibration_of_one_point_is_refused(tmp_path, capsys):
    toml = lab6_first_records(tmp_path, 1)
    edit_toml(toml, lambda d: d["valve"][0].update(load=[300], deflection=[18]))
    refused(capsys, toml, toml, "valve[0].load", r"1 distinct load")


# ------------------------------------------------------------------------------------ lab 9

LAB9 = ("lab9", "synthetic_damper.toml")


@pytest.mark.parametrize("change, problem", [
    (np.zeros_like, r"channel 'u' is flat: its 848 samples stay at 0, nothing for the "
     r"decrement to read.*Fix: check that the sensor"),
    (lambda x: np.full_like(x, 1.23), r"is flat: its 848 samples stay at 1.23"),
    (noise, r"holds no oscillation above its noise.*Fix: check that the sensor"),
    (lambda x: x[:120], r"extrema of an oscillation stand out of the noise; a decay needs at "
     r"least three: the record lasts 0.006 s \(120 samples\).*Fix: record the whole decay"),
    (lambda x: x[:40], r"the record holds 40 samples, too short for a decay"),
    (clip(0.03), r"clipped: \d+\.\d % of its samples sit at the recorder's limits, and .* a "
     r"decay needs at least three.*Fix: lower the amplifier's gain"),
], ids=["all-zero", "constant", "noise", "too-short", "40-samples", "clipped-to-nothing"])
def test_lab9_decay_that_is_not_what_it_claims(tmp_path, capsys, change, problem):
    toml = copy_sample(tmp_path, *LAB9)

    def changed(frame):
        u = change(frame["u"].to_numpy(dtype=float))
        return frame.iloc[:u.size].assign(u=u)
    change_column(toml.parent / "decay.csv", None, changed)
    refused(capsys, toml, toml.parent / "decay.csv", "decay.signal", problem)


def test_lab9_decay_faster_than_the_sample_rate_resolves(tmp_path, capsys):
    toml = copy_sample(tmp_path, *LAB9)
    change_column(toml.parent / "decay.csv", None, lambda f: f.assign(
        u=np.exp(-5 * f["t"]) * np.sin(2 * np.pi * 9e3 * f["t"])))
    refused(capsys, toml, toml.parent / "decay.csv", "decay.signal",
            r"faster than a third of its sample rate")


@pytest.mark.parametrize("level", [0.9, 0.6, 0.4, 0.2])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_clipped_decay_is_fitted_around_its_clipped_samples(level, seed):
    """A synthetic decay (δ = 0.89) clipped at ``level`` of its swing: the fit around the
    clipped samples keeps δ within its stated 95 % interval (without the mask it read 34 %
    low at 0.6)."""
    rec = free_decay(Ring(), StrainGauge(), seed=seed)
    x = clip(level)(np.round(rec.signal, 4))
    mask = clipped_mask(x)
    assert mask.mean() > 0.05
    fit = analyse_decay(rec.time, x, clipped=mask).trace
    half = stats.t.ppf(0.975, fit.dof) * fit.u("delta")
    assert abs(fit.delta - rec.truth["log_decrement"]) <= half, (fit.delta, half)
    assert abs(fit.period - rec.truth["T_d"]) <= stats.t.ppf(0.975, fit.dof) * \
        fit.period * fit.u("omega_d") / fit.omega_d


@pytest.mark.parametrize("level", [0.8, 0.6, 0.4])
def test_lab9_clipped_decay_warns_and_reads_the_right_decrement(tmp_path, capsys, level):
    toml = copy_sample(tmp_path, *LAB9)
    change_column(toml.parent / "decay.csv", "u", clip(level))
    doc = reported(capsys, toml)
    assert codes(doc) == {"clipped_record"}, doc["warnings"]
    assert "% of the samples sit at the recorder's limits; the fit leaves them out" in \
        doc["warnings"][0]["message"]
    truth = key(toml)
    for name in ("log_decrement", "T_d", "C_dynamic", "xi_dynamic"):
        assert inside(doc, name, truth[name]), name


@pytest.mark.parametrize("edit, field, problem", [
    ({"cal_reading": [0.5, 0.5, 0.5, 0.5]}, "decay.cal_reading",
     r"the readings never change: every one of the 4 is 0.5"),
    ({"cal_reading": [0, 0, 0, 0]}, "decay.cal_reading", r"the readings never change"),
    ({"cal_reading": [0.001782, 0.6, 0.2992, 0.8994]}, "decay.cal_reading",
     r"reading 3 \(0.2992\) turns back past reading 2 \(0.6\), although its twist is larger"),
    ({"cal_phi": [3.0], "cal_reading": [0.3]}, "decay.cal_reading", r"1 distinct point"),
    ({"cal_phi": [3.0, 3.0, 3.0, 3.0]}, "decay.cal_phi", r"1 distinct twist"),
], ids=["constant", "zero", "turns-back", "one-point", "one-twist"])
def test_lab9_calibration_that_cannot_give_a_scale(tmp_path, capsys, edit, field, problem):
    toml = copy_sample(tmp_path, *LAB9)
    edit_toml(toml, lambda d: d["decay"].update(edit))
    refused(capsys, toml, toml, field, problem)


# ------------------------------------------------------------------- physical sense declared

@pytest.mark.parametrize("sample, positive, either", [
    ("lab9/synthetic_damper.toml", ("log_decrement", "log_decrement_peaks", "T_d", "omega_d",
                                    "xi_dynamic", "C_dynamic", "C_ratio", "mu_phi",
                                    "C_static", "C_static_1", "E_max"), ("E_loss", "xi_static")),
    ("lab3/engine_2regimes.toml", ("delta_1", "delta_mid_1", "delta_tooth_1", "delta_osc_1",
                                   "omega_mean_1", "omega_min_1", "omega_tach_1"), ()),
    ("lab6/lab6_seed6.toml", ("k_in", "n_1", "P_max_in_1", "nu_in_1", "phi_in_1",
                              "phi_crank_ex_1", "n_sep_in_800"),
     ("P_min_in_1", "advance_in_1", "lag_ex_1", "loss_in_1")),
])
def test_results_above_zero_by_nature_are_declared_so(sample, positive, either):
    """δ, frequencies, stiffnesses, speeds, durations, the largest force: refused at or below
    zero by :meth:`~processing.result.LabResult.check_sense`; a least force (zero at a loss
    of contact), a timing angle or a loop's area (negative when inverted, warned) are not."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        results = evaluate(SAMPLES / sample).results
    assert [n for n in positive if not results[n].positive] == []
    assert [n for n in either if results[n].positive] == []


# ------------------------------------------------------------------------ no false alarms

@pytest.mark.parametrize("sample, warned", [
    ("lab3/engine_2regimes.toml", set()), ("lab3-photo/photographed_oscillogram.toml", set()),
    ("lab6/lab6_seed6.toml", {"contact_lost"}), ("lab9/synthetic_damper.toml", set()),
    ("lab9-photo/photographed_decay.toml", {"baseline_drift"}),
])
def test_samples_warn_only_what_they_did(sample, warned):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = evaluate(SAMPLES / sample)
    assert {w.code for w in result.warnings} == warned


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_synthetic_decays_stay_quiet(tmp_path, seed):
    from labs.lab9_damper import write_synthetic

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = evaluate(write_synthetic(tmp_path, seed)["toml"])
    assert not result.warnings, [w.code for w in result.warnings]
