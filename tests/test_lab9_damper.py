"""Lab 9: the manual's Table 1, closed forms of loops, round trips through the synthetic
damper, coverage over seeded records, the warnings and the refusals.

The synthetic scene (:mod:`processing.synth.damper`) knows its true stiffnesses, loop and
decrement; the lab must recover them within the uncertainty it states, warn where its method
fails (amplitude-dependent damping, records too short or noisy) and stay silent elsewhere,
and refuse bad tables with a message naming the file, the field and the fix.
"""
import json
from pathlib import Path

import numpy as np
import pytest

from labs import lab9_damper as lab9
from labs.cli.main import main
from labs.registry import evaluate
from processing.diagnostics import InputError
from processing.oscillations.loops import loop_area
from processing.reporting.render import render
from processing.synth.damper import RubberLayer

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "sample_data" / "lab9"
TABLE1 = SAMPLES / "table1.toml"
FAST = {"n_samples": 2000}
KEYED = ("C_static", "E_max", "E_loss", "xi_static", "log_decrement", "T_d", "omega_d",
         "xi_dynamic", "C_dynamic", "C_ratio", "mu_phi")


def reduce(path, **options):
    """Load and reduce like ``dynlab run``, with fewer Monte Carlo draws."""
    return evaluate(path, **{**FAST, **options})


def codes(result):
    return {w.code for w in result.warnings}


def measurement(folder: Path, body: str) -> Path:
    path = folder / "m.toml"
    path.write_text(f'lab = "lab9"\n{body}', encoding="utf-8")
    return path


RUN = "[[run]]\nM = [90, 180, 270, 315, 270, 180, 90, 0]\nphi = [{}]\n"
TABLE1_RUN = RUN.format("2.69, 6.15, 9.91, 12.12, 10.89, 7.90, 4.58, 0.09")


# ----------------------------------------------------------------------------- the manual's Table 1

@pytest.fixture(scope="module")
def table1():
    return reduce(TABLE1)


def test_table1_stiffness_as_printed(table1):
    """The manual: C ≈ 2.6·10⁴ N·m/rad (two significant digits). Run 1's secant and the
    runs' mean loading slope give it to that precision; the secants' mean (2.66·10⁴; run 2
    is 5 % stiffer) holds it within its U."""
    assert round(table1["C_static_1"].value / 1e4, 1) == 2.6
    assert round(table1["C_static_fit"].value / 1e4, 1) == 2.6
    c = table1["C_static"]
    assert abs(c.value - 2.6e4) <= c.estimate.U
    assert c.value == pytest.approx((315 / 12.12e-3 + 315 / 11.56e-3) / 2, rel=1e-12)


def test_table1_energies_by_hand(table1):
    """E_max is the triangle OAB; E_n the polygon, worked independently as the difference of
    the branches' trapezoidal integrals ∫φ dM (unloading less loading)."""
    for k, phi in ((1, [0, 2.69, 6.15, 9.91, 12.12, 10.89, 7.90, 4.58, 0.09]),
                   (2, [0, 2.46, 5.79, 9.55, 11.56, 10.40, 7.49, 4.26, 0.81])):
        phi = 1e-3 * np.array(phi)
        M = np.array([0, 90, 180, 270, 315])
        load_w = np.trapezoid(phi[:5], M)
        unload_w = np.trapezoid(phi[4:][::-1], M)
        # the straight closing line at M = 0 adds nothing to ∫φ dM
        assert table1[f"E_loss_{k}"].value == pytest.approx(unload_w - load_w, rel=1e-12)
        assert table1[f"E_max_{k}"].value == pytest.approx(315 * phi[4] / 2, rel=1e-12)
        assert table1[f"xi_static_{k}"].value == pytest.approx(
            (unload_w - load_w) / (315 * phi[4] / 2), rel=1e-12)
    # printed precision of what the manual's figure implies: E_max ≈ 1.9 J
    assert round(table1["E_max_1"].value, 1) == 1.9
    assert round(table1["xi_static_1"].value, 3) == 0.208


def test_table1_reports_tables_and_figures(table1):
    assert [f.name for f in table1.figures] == ["loops"]
    readings = table1.measurements[0]          # Table 1, as the manual prints it
    assert [r["up"] for r in readings.rows[1:5]] == ["2.69", "6.15", "9.91", "12.12"]
    assert readings.rows[0]["down"] == "0.09" and readings.rows[0]["up"] == "—"
    assert readings.rows[4]["down"] == "—"          # the top is read once, as printed
    assert codes(table1) == set()


# ----------------------------------------------------------------------------- closed forms

def test_ellipse_of_a_visco_elastic_layer():
    """M = Cφ + cφ̇ with φ = φ₀ sin ωt traces an ellipse of area π c ω φ₀²; against the
    triangle C φ₀²/2 that is ξ′ = 2π·cω/C."""
    C, c, w, phi0 = 2.6e4, 3.0, 1200.0, 0.01
    t = np.linspace(0, 2 * np.pi / w, 4001)[:-1]
    phi = phi0 * np.sin(w * t)
    M = C * phi + c * phi0 * w * np.cos(w * t)
    area = loop_area(phi, M)
    assert area == pytest.approx(np.pi * c * w * phi0**2, rel=1e-6)
    xi = lab9.relative_damping(area, lab9.energy_at_max(C * phi0, phi0))
    assert xi == pytest.approx(2 * np.pi * c * w / C, rel=1e-6)


def test_triangle_is_e_max():
    assert lab9.energy_at_max(315.0, 12.12e-3) == pytest.approx(
        loop_area([0, 12.12e-3, 12.12e-3], [0, 315.0, 0]), rel=1e-12)


def test_dynamic_stiffness_of_a_viscous_oscillator():
    """C_d = I ω_d² [1 + (δ/2π)²] = I ω_n² and ξ_d = I ω_d δ/π = c for I φ̈ + c φ̇ + C_d φ = 0."""
    I, C, c = 0.03, 4.85e4, 40.0
    wn, sigma = np.sqrt(C / I), c / (2 * I)
    wd = np.sqrt(wn**2 - sigma**2)
    delta = 2 * np.pi * sigma / wd
    assert lab9.dynamic_stiffness(I, wd, delta) == pytest.approx(C, rel=1e-12)
    assert lab9.damping_coefficient(I, wd, delta) == pytest.approx(c, rel=1e-12)


def test_polygon_of_the_synthetic_loop():
    """The lens loop read in n equal steps encloses (1 − 1/n²) of h M_max/3."""
    layer = RubberLayer()
    m = np.linspace(0, 315, 8)
    load_, unload = layer.branches(m, 315)
    area = loop_area(np.concatenate([load_, unload[::-1][1:]]),
                     np.concatenate([m, m[::-1][1:]]))
    assert area == pytest.approx(layer.energies(315, steps=7)["E_loss"], rel=1e-12)


# ----------------------------------------------------------------------------- round trips

@pytest.mark.parametrize("options", [{}, {"paper": True}])
def test_synthetic_damper_round_trip(tmp_path, options):
    written = lab9.write_synthetic(tmp_path, seed=3, **options)
    key = json.loads(written["answer"].read_text())["results"]
    result = reduce(written["toml"])
    for name in KEYED:
        lo, hi = result[name].estimate.interval95
        assert lo <= key[name] <= hi, (name, result[name].value, key[name])
    assert result["C_ratio"].value == pytest.approx(1.87, rel=0.05)
    assert codes(result) == set()


@pytest.mark.parametrize("periods, rate", [(60, 100e3), (100, 200e3)])
def test_a_recorder_left_running_after_the_decay_is_read(tmp_path, periods, rate):
    """A decay that dies within ten periods, recorded for 60–100 (30 000–100 000 samples of
    noise after it): the noise tail is cut where the ringing ends (it swamped the spectrum
    that finds the period, and the record was refused as '1 extrema … stand out of the
    noise'); every keyed result holds its truth."""
    written = lab9.write_synthetic(tmp_path, seed=3, periods=periods, sample_rate=rate)
    key = json.loads(written["answer"].read_text())["results"]
    result = reduce(written["toml"])
    for name in KEYED:
        lo, hi = result[name].estimate.interval95
        assert lo <= key[name] <= hi, (name, result[name].value, key[name])


def test_result_names_of_the_contract(tmp_path):
    result = reduce(lab9.write_synthetic(tmp_path, seed=1)["toml"])
    for name in ("C_static", "E_max", "E_loss", "xi_static", "log_decrement", "C_dynamic",
                 "xi_dynamic"):
        assert name in result.to_dict()["results"]


def test_stated_intervals_cover_the_truth(tmp_path):
    """200 synthetic dampers at the target corner (30 dB, 5 periods): the 95 % intervals of
    δ, ω_d and the static means hold the truth in 90–98 % of them (± 3 %, the share's scatter
    on 200), every result's in ≥ 90 %, and δ is within 2 % in ≥ 95 %. (Measured: ω_d 99 %
    since the baseline model's spread joined its u; C 96 %, E_n 96 %; ξ′, ξ_d and C_d
    97–100 %: the scene's weights and ring are exact, the file states their tolerances.)"""
    hits, close = {k: [] for k in KEYED}, []
    for seed in range(200):
        w = lab9.write_synthetic(tmp_path / str(seed), seed=seed, snr_db=30, periods=5)
        key = json.loads(w["answer"].read_text())["results"]
        result = reduce(w["toml"], n_samples=1000)
        for k in KEYED:
            lo, hi = result[k].estimate.interval95
            hits[k].append(lo <= key[k] <= hi)
        close.append(abs(result["log_decrement"].value / key["log_decrement"] - 1) <= 0.02)
    margin = 1.96 * np.sqrt(0.95 * 0.05 / 200)     # the share's binomial scatter on 200
    for k in ("log_decrement", "omega_d", "C_static", "E_loss"):
        assert 0.90 - margin <= np.mean(hits[k]) <= 0.98 + margin, (k, np.mean(hits[k]))
    for k in KEYED:
        assert np.mean(hits[k]) >= 0.90, (k, np.mean(hits[k]))
    assert np.mean(close) >= 0.95


# ----------------------------------------------------------------------------- warnings

@pytest.mark.parametrize("p, warned", [(0.0, False), (0.3, True)])
@pytest.mark.parametrize("seed", [0, 1])
def test_amplitude_dependent_damping_warns_only_when_present(tmp_path, p, warned, seed):
    result = reduce(lab9.write_synthetic(tmp_path, seed=seed, amplitude_exponent=p)["toml"])
    assert ("amplitude_dependent_damping" in codes(result)) == warned, codes(result)
    if warned:
        text = [w for w in result.warnings if w.code == "amplitude_dependent_damping"][0]
        assert "average" in text.message and "среднее" in text.ru


def test_amplitude_dependent_peaks_read_off_paper_warn(tmp_path):
    path = measurement(tmp_path, '[decay]\nI = 0.03\nT = "5 ms"\n'
                       "peaks = [40.0, 20.0, 12.0, 8.0, 6.0, 4.8]\n")
    assert "amplitude_dependent_damping" in codes(reduce(path))
    geometric = ", ".join(f"{40 * np.exp(-0.6 * k):.1f}" for k in range(6))
    path = measurement(tmp_path, f'[decay]\nI = 0.03\nT = "5 ms"\npeaks = [{geometric}]\n')
    assert "amplitude_dependent_damping" not in codes(reduce(path))


@pytest.mark.parametrize("snr, periods, warned", [(20, 8, True), (30, 2, True), (30, 5, False),
                                                   (40, 8, False)])
def test_short_or_noisy_record_warns(tmp_path, snr, periods, warned):
    result = reduce(lab9.write_synthetic(tmp_path, seed=1, snr_db=snr, periods=periods)["toml"])
    assert ("short_record" in codes(result)) == warned, codes(result)


def test_static_warnings(tmp_path):
    body = (TABLE1_RUN + RUN.format("2.69, 6.15, 9.91, 12.12, 11.9, 10.5, 8.0, 3.5")
            + RUN.format("1.0, 2.0, 4.0, 12.12, 12.0, 11.5, 10.0, 0.5"))
    result = reduce(measurement(tmp_path, body))
    assert {"unclosed_loop", "large_hysteresis"} <= codes(result)
    single = reduce(measurement(tmp_path, TABLE1_RUN))
    assert codes(single) == {"single_reading"}


def test_wrong_inertia_gives_an_implausible_stiffness_ratio(tmp_path):
    written = lab9.write_synthetic(tmp_path, seed=0)
    text = written["toml"].read_text().replace('I = "0.03 ± 0.00015 kg*m^2"',
                                               'I = "0.3 ± 0.0015 kg*m^2"')
    written["toml"].write_text(text)
    result = reduce(written["toml"])
    assert "stiffness_ratio" in codes(result)
    assert result["C_ratio"].value == pytest.approx(18.7, rel=0.05)


# ----------------------------------------------------------------------------- bad input

@pytest.mark.parametrize("body, field, problem, fix", [
    (RUN.replace("90, 0]", "90]").format("2.69, 6.15, 9.91, 12.12, 10.89, 7.90, 4.58"),
     "run[0].M", "loop is not closed", "unload down to zero"),
    ("[[run]]\nM = [90, 270, 180, 315, 270, 180, 90, 0]\n"
     "phi = [2.69, 6.15, 9.91, 12.12, 10.89, 7.90, 4.58, 0.09]\n",
     "run[0].M", "out of order: reading 3", "rising to the largest"),
    ("[[run]]\nM = [90, 180, 270, 315, 270, 180, 90, 0]\nphi = [2.69, 6.15, 9.91]\n",
     "run[0].phi", "8 moments but 3 twists", "one twist for every moment"),
    ('[decay]\nI = 0.03\nT = "5 ms"\npeaks = [40.0, 16.0]\n',
     "decay.peaks", "2 amplitude", "at least three successive"),
    ('[decay]\nI = 0.03\nT = "5 ms"\npeaks = [40.0, 16.0, 7.0]\ncal_phi = [3]\n'
     "cal_reading = [12]\n", "decay.cal_reading", "1 distinct point", "at two or more"),
    ('[decay]\nI = 0.03\npeaks = [40.0, 16.0, 7.0]\n', "decay.T", "period is not given",
     "t_N"),
    ('[decay]\nI = 0.03\nT = "5 ms"\npeaks = [10.0, 16.0, 27.0]\n', "decay.peaks",
     "do not decrease", "from the release on"),
])
def test_bad_tables_name_the_file_the_field_and_the_fix(tmp_path, body, field, problem, fix):
    path = measurement(tmp_path, body)
    with pytest.raises(InputError) as exc:
        reduce(path)
    e = exc.value
    assert e.file == str(path) and e.field == field, e
    assert problem in e.problem and fix in e.fix, e
    assert "Fix:" in str(e)


def test_noise_record_is_refused_at_the_record_as_noise(tmp_path):
    t = np.arange(4000) / 20e3
    noise = 0.01 * np.random.default_rng(0).standard_normal(t.size)
    np.savetxt(tmp_path / "flat.csv", np.column_stack([t, noise]), delimiter=",",
               header="t,u", comments="")
    path = measurement(tmp_path, '[decay]\nI = 0.03\nsignal = "flat.csv"\n')
    with pytest.raises(InputError, match="no oscillation above its noise.*Fix: check that the "
                                         "sensor") as exc:
        reduce(path)
    assert exc.value.file.endswith("flat.csv") and exc.value.field == "decay.signal"


def test_cli_refuses_bad_input_with_exit_2_and_writes_nothing(tmp_path, monkeypatch, capsys):
    path = measurement(tmp_path, RUN.format("2.69, 6.15, 9.91, 12.12, 10.89, 7.90, 4.58, 0.09")
                       .replace("90, 0]", "90, 5]"))
    out = tmp_path / "reports"
    assert main(["run", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "m.toml" in err and "run[0].M" in err and "Fix:" in err
    assert not out.exists() or not any(out.iterdir())


# ----------------------------------------------------------------------------- reports

@pytest.mark.parametrize("sample", sorted(p.name for p in SAMPLES.glob("*.toml")))
def test_every_sample_renders_in_html_and_json_in_both_languages(sample):
    result = reduce(SAMPLES / sample)
    for lang in ("en", "ru"):
        out = render(result, ("html", "json"), lang)     # the PDFs: test_report_layout
        assert b"<html" in out["html"][:200].lower()
        assert json.loads(out["json"])["lab"] == "lab9"


def test_synthetic_sample_matches_its_answer_key():
    key = json.loads((SAMPLES / "answer_key.json").read_text())["results"]
    result = reduce(SAMPLES / "synthetic_damper.toml")
    for name in KEYED:
        lo, hi = result[name].estimate.interval95
        assert lo <= key[name] <= hi, name
    assert codes(result) == set()


# ----------------------------------------------------------------------------- a photographed record

@pytest.fixture(scope="module")
def photographed(tmp_path_factory):
    """The same seeded decays written as a recording and as a photograph of its paper."""
    out = {}
    for seed in (0, 5):
        folder = tmp_path_factory.mktemp(f"photo{seed}")
        out[seed] = (lab9.write_synthetic(folder / "csv", seed=seed),
                     lab9.write_synthetic(folder / "jpg", seed=seed, image=True))
    return out


def test_photographed_record_gives_the_recorded_decrement(photographed):
    """Read off a phone photograph (1.5° skew, perspective, blur, noise, JPEG), the decay
    gives δ within 2 % of the same record's δ from its samples (measured: 0.02–0.3 %), the
    period within 0.2 %, and intervals that hold the truth; the report shows what was read."""
    for recorded, photo in photographed.values():
        key = json.loads(photo["answer"].read_text())["results"]
        from_samples, from_photo = reduce(recorded["toml"]), reduce(photo["toml"])
        assert from_photo["log_decrement"].value == pytest.approx(
            from_samples["log_decrement"].value, rel=0.02)
        assert from_photo["T_d"].value == pytest.approx(from_samples["T_d"].value, rel=2e-3)
        for name in ("log_decrement", "T_d", "C_dynamic", "xi_dynamic", "mu_phi"):
            lo, hi = from_photo[name].estimate.interval95
            assert lo <= key[name] <= hi, (name, from_photo[name].value, key[name])
        assert "log_decrement_peaks" in from_photo.to_dict()["results"]
        assert "paper_record" in [f.name for f in from_photo.figures]


@pytest.mark.parametrize("change, field, problem", [
    (('mark_period = "1 ms"\n', ""), "image.mark_period", "no time base"),
    (('signal = "decay.jpg"', 'signal = "decay.jpg"\nsample_rate = 20'), "decay.signal",
     "sample rate is given for an image"),
    (('signal = "decay.jpg"', 'signal = "decay.jpg"\nchannel = "3"'), "decay.signal",
     "trace 3 asked for, 1 trace(s) found"),
])
def test_photographed_record_refusals(photographed, tmp_path, change, field, problem):
    _, photo = photographed[0]
    body = photo["toml"].read_text(encoding="utf-8").replace(*change)
    path = tmp_path / "m.toml"
    path.write_text(body, encoding="utf-8")
    (tmp_path / "decay.jpg").write_bytes(photo["record"].read_bytes())
    with pytest.raises(InputError) as exc:
        reduce(path)
    assert exc.value.field == field and problem in exc.value.problem, exc.value
    assert exc.value.file.endswith("decay.jpg")


@pytest.mark.parametrize("kind, size, image", [
    ("linear", 0.2, False), ("quadratic", 0.2, False), ("settling", 0.2, False),
    ("wander", 0.05, False), ("settling", 0.3, True), ("wander", 0.06, True)])
def test_a_drifting_baseline_is_carried_by_the_intervals(tmp_path, kind, size, image):
    """A bridge drifting, an amplifier settling within a period or two, a slow wander (three
    sines of up to 5 % of the twist): the data choose the baseline, and the spread over the
    baselines they admit joins δ's and T's u. Measured over 40 seeds of each kind
    (``python -m processing.bench --topic damper``, family ``baseline drift``): δ's and T's
    intervals hold the truth in 95 % and 94 % of the records (90–97.5 % per kind), and in
    95–100 % of 199 photographs; with the one quadratic baseline, T's held it in 57 % of the
    settling and 67 % of the wandering records, and 4 photographs whose held twist drifted
    were fitted from before the release (δ 43–59 % off)."""
    from processing.synth.damper import BridgeDrift

    w = lab9.write_synthetic(tmp_path, seed=7, periods=8, image=image,
                             drift=BridgeDrift(kind, size, time_constant=1.0, seed=7))
    key = json.loads(w["answer"].read_text())["results"]
    result = reduce(w["toml"])
    assert result["log_decrement"].value == pytest.approx(key["log_decrement"], rel=0.01)
    for name in ("log_decrement", "T_d"):
        lo, hi = result[name].estimate.interval95
        assert lo <= key[name] <= hi, (name, result[name].value, key[name])


def test_variants_differ_in_the_damper(tmp_path):
    """Seed 0 is the manual's damper 1; other seeds draw a damper of their own (stiffness,
    loop, ring, decrement within the manual's six dampers) whose reduction holds its key."""
    keys = {}
    for seed in (0, 1, 2):
        w = lab9.write_synthetic(tmp_path / str(seed), seed=seed)
        keys[seed] = json.loads(w["answer"].read_text())["results"]
        result = reduce(w["toml"], n_samples=1000)
        for name in ("C_static", "log_decrement", "C_dynamic", "xi_static"):
            lo, hi = result[name].estimate.interval95
            assert lo <= keys[seed][name] <= hi, (seed, name, result[name].value)
        assert 'rubber = "synthetic"' in w["toml"].read_text()
    assert keys[0]["C_static"] == 2.6e4 and keys[0]["log_decrement"] == pytest.approx(0.89)
    for seed in (1, 2):
        assert lab9.DAMPERS["C"][0] <= keys[seed]["C_static"] <= lab9.DAMPERS["C"][1]
        assert lab9.DAMPERS["decrement"][0] <= keys[seed]["log_decrement"] \
            <= lab9.DAMPERS["decrement"][1]
        assert keys[seed]["C_dynamic"] / keys[seed]["C_static"] == pytest.approx(1.87, rel=0.01)
    assert len({k["C_static"] for k in keys.values()}) == 3


def test_drift_benchmark_family_judges_its_records():
    """The benchmark's ``baseline drift`` family on one seed of each drift: every record
    reduced, δ within 2 % (seed 0's wander, at 37 dB, comes out 1.2 % off: within 1 % is
    asked of the 95th percentile over the benchmark's records), and both intervals holding
    the truth."""
    from processing.bench import damper
    from processing.bench.harness import run_family

    frame = __import__("pandas").DataFrame(
        run_family(damper.drift_family(), damper.drift_cases(1), repeat=1))
    assert len(frame) == 4 and (frame["failed"] == "").all()
    assert (frame["error"].abs() < damper.DELTA_TOLERANCE).all(), frame["error"].tolist()
    assert frame["covered"].all() and frame["T_covered"].all()
