"""The benchmark harness on a toy family (rows, CSV, charts, targets), and the pulse-train
families on small cases: a δ within the target, edges matched to the truth, and streamed
edges equal to in-memory ones. Timings are never asserted here (ARCHITECTURE.md, Benchmarks).
"""
import json

import numpy as np
import pandas as pd
import pytest
from numpy.testing import assert_allclose

from processing.bench import docs, speed
from processing.bench.__main__ import parse_args
from processing.bench.harness import (
    Case,
    Family,
    MapAxes,
    Method,
    Target,
    coverage_targets,
    peak_memory,
    plot_error_time,
    plot_map,
    plot_time_size,
    run_family,
    summary,
    time_call,
    write_rows,
    write_targets,
)
from processing.speed.edges import detect_edges
from processing.synth.engine import ToothWheel, record
from processing.speed.toothwheel import track_teeth

PNG = b"\x89PNG\r\n\x1a\n"


def _broken(x):
    raise ArithmeticError("the toy method gives up")


def _toy_family():
    """Where is a constant in noise: mean, median, and a method that always fails."""
    return Family("toy", [Method("mean", np.mean), Method("median", np.median, "plain"),
                          Method("broken", _broken)],
                  error=lambda estimate, truth: {"error": estimate / truth - 1},
                  error_label="relative error", failures=(ArithmeticError,))


def _toy_cases():
    for n in (100, 1000, 10000):
        for noise in (0.01, 0.1):
            x = 1.0 + noise * np.random.default_rng(n).standard_normal(n)
            yield Case({"noise": noise, "length": n}, x, 1.0, n)


@pytest.fixture(scope="module")
def toy_rows():
    return run_family(_toy_family(), _toy_cases(), repeat=2, memory=True)


# ----------------------------------------------------------------------------- the harness

def test_rows_one_per_case_and_method(toy_rows):
    assert len(toy_rows) == 6 * 3
    first = toy_rows[0]
    assert {"family", "method", "setting", "noise", "length", "samples", "seconds",
            "samples_per_second", "error", "failed", "warnings", "peak_bytes"} <= set(first)
    ok = [r for r in toy_rows if r["method"] != "broken"]
    assert all(r["seconds"] > 0 and r["failed"] == "" for r in ok)
    assert all(abs(r["error"]) < 0.05 for r in ok), "the mean of 1 + noise is near 1"
    broken = [r for r in toy_rows if r["method"] == "broken"]
    assert all(np.isnan(r["error"]) and r["failed"].startswith("ArithmeticError")
               for r in broken)


def test_csv_columns_and_summary(toy_rows, tmp_path):
    frame = write_rows(toy_rows, tmp_path / "out" / "bench.csv")
    back = pd.read_csv(tmp_path / "out" / "bench.csv")
    assert list(back.columns) == list(frame.columns)
    assert list(back.columns[:5]) == ["family", "method", "setting", "noise", "length"]
    table = summary(frame).set_index("method")
    assert table.loc["broken", "failed"] == 6 and table.loc["broken", "worst|err|"] == np.inf
    assert table.loc["mean", "cases"] == 6 and table.loc["mean", "worst|err|"] < 0.05


def test_charts_are_written(toy_rows, tmp_path):
    frame = pd.DataFrame(toy_rows)
    plot_error_time(frame, tmp_path / "error.png", {"toy": "relative error"})
    plot_time_size(frame, tmp_path / "size.png", family="toy", target_rate=1e6)
    plot_map(frame, tmp_path / "map.png",
             MapAxes(x="length", y="noise", column="family"), threshold=0.01)
    for name in ("error.png", "size.png", "map.png"):
        assert (tmp_path / name).read_bytes().startswith(PNG), name


def test_docs_pages_show_targets_and_charts_and_replace_a_rerun(toy_rows, tmp_path):
    out, docs_dir = tmp_path / "out", tmp_path / "docs"
    out.mkdir()
    plot_error_time(pd.DataFrame(toy_rows), out / "error_vs_time.png", {"toy": "relative error"})
    targets = [Target("toy |error|", 0.002, 0.01, unit="rel"), Target("speed", 1.0, 5.0, "min")]
    page = docs.topic_page(docs_dir, "toy", ["toy: 1 case"], targets, out, quick=True)
    text = page.read_text(encoding="utf-8")
    assert "| toy \\|error\\| | 0.002 rel | ≤ 0.01 rel | PASS |" in text
    assert "| speed | 1  | ≥ 5  | FAIL |" in text and "--quick" in text
    assert "![toy: error vs time](toy__error_vs_time.png)" in text
    assert (docs_dir / "toy__error_vs_time.png").read_bytes().startswith(PNG)
    (out / "error_vs_time.png").rename(out / "renamed.png")
    docs.topic_page(docs_dir, "toy", [], [], out, quick=False)
    assert sorted(p.name for p in docs_dir.glob("*.png")) == ["toy__renamed.png"]
    index = docs.index_page(docs_dir, ["other", "toy"]).read_text(encoding="utf-8")
    assert "\ntoy\n" in index and "other" not in index


def test_time_call_stops_at_its_budget():
    calls = []
    seconds, result = time_call(calls.append, 1, repeat=3, budget=10.0)
    assert len(calls) == 3 and result is None and seconds >= 0
    time_call(calls.append, 1, repeat=3, budget=0.0)
    assert len(calls) == 4, "a zero budget times a single run"


def test_peak_memory_sees_numpy_arrays():
    peak, result = peak_memory(lambda n: np.ones(n).sum(), 10 ** 6)
    assert result == 10 ** 6 and peak >= 8 * 10 ** 6


def test_targets_pass_fail_and_json(tmp_path):
    found = [Target("speed", 60.0, 50.0, "min", "MS/s"), Target("error", 0.02, 0.01),
             Target("nothing measured", np.nan, 1.0)]
    assert [t.passed for t in found] == [True, False, False]
    assert found[0].line().startswith("PASS  speed: 60") and found[1].line().startswith("FAIL")
    write_targets(found, tmp_path / "targets.json", {"cpus": 2})
    saved = json.loads((tmp_path / "targets.json").read_text())
    assert [t["passed"] for t in saved["targets"]] == [True, False, False]
    assert saved["targets"][2]["value"] is None and saved["environment"] == {"cpus": 2}


def test_command_line():
    args = parse_args(["--quick", "--out", "here", "--large", "1e9"])
    assert args.quick and str(args.out) == "here" and args.large == 10 ** 9
    assert parse_args([]).large is None and str(parse_args([]).out) == "bench-results"
    assert parse_args([]).topic is None and parse_args(["--topic", "speed"]).topic == ["speed"]
    with pytest.raises(SystemExit):
        parse_args(["--topic", "no-such-topic"])
    with pytest.raises(SystemExit):
        parse_args(["--large", "0.5"])
    with pytest.raises(SystemExit) as done:
        parse_args(["--help"])
    assert done.value.code == 0


# ----------------------------------------------------------------------------- the families

@pytest.fixture(scope="module")
def clean_case():
    """60−2 wheel, about 20 samples per tooth, SNR 40 dB: inside the target region."""
    return speed.pulse_recording(60, 20, 40.0, seed=1)


def test_sample_rate_gives_a_golden_fraction_per_cycle():
    run = speed.engine_run()
    rate = speed.sample_rate(run, 60, 20)
    per_cycle = rate * 4 * np.pi / run.mean_angular_speed
    assert_allclose(per_cycle, 2400 + speed.GOLDEN, rtol=1e-12,
                    err_msg="2 revolutions × 60 pitches × 20 samples, plus 0.618…")


def test_fourier_delta_within_target(clean_case):
    rows = run_family(speed.delta_family(methods=["fourier"]),
                      speed.delta_cases([(20, clean_case)]), repeat=1)
    (row,) = rows
    assert row["failed"] == "" and np.isfinite(row["error"])
    # the benchmark's target: 1 % of δ in this region
    assert abs(row["error"]) < speed.DELTA_TOLERANCE, row


def test_edge_errors_count_misses_and_extras():
    true = np.arange(10, 200, 10.0)
    detected = np.concatenate([true[:5] + 0.1, true[6:] - 0.1, [205.0]])
    err = speed.edge_errors(detected, speed.EdgeTruth(true, 220))
    assert err["missed"] == 1 and err["extra"] == 1
    assert_allclose(err["error"], 0.1, rtol=1e-9, err_msg="RMS of ±0.1 samples")
    assert_allclose(err["bias"], 0.1 * (5 - 13) / 18, rtol=1e-9)


def test_fit_edges_match_the_true_edges(clean_case):
    rows = run_family(speed.edge_family(), speed.edge_cases([(20, clean_case)]), repeat=1)
    fit, matched = (next(r for r in rows if (r["method"], r["setting"]) == key)
                    for key in (("fit", "window=auto"), ("matched", "")))
    for row in (fit, matched):
        assert row["missed"] == 0 and row["extra"] == 0
    assert fit["error"] < 0.05, "SNR 40 dB: a few hundredths of a sample"
    assert matched["error"] < 0.8 * fit["error"], "the whole pulse holds more information"


def test_timing_bound_is_below_the_detected_edges_error(clean_case):
    """The Cramér–Rao bound is the floor the fitted edges approach (within 2×)."""
    bound = speed.timing_bound(clean_case) * clean_case.sample_rate
    edges = speed.edge_errors(detect_edges(clean_case.signal),
                              speed.EdgeTruth(clean_case.edge_times * clean_case.sample_rate,
                                              clean_case.signal.size))["error"]
    assert 0.4 * edges < bound < edges, f"bound {bound:.4f}, fit {edges:.4f} samples"
    (row,) = run_family(speed.bound_family(), speed.delta_cases([(20, clean_case)]), repeat=1)
    assert row["cycles"] == speed.CYCLES and abs(row["error"]) < speed.DELTA_TOLERANCE


def test_delta_target_per_record_length():
    rows = [{"family": family, "method": method, "teeth": 60, "samples_per_tooth": 20,
             "snr_db": 20.0, "seed": seed, "cycles": cycles, "error": error, "failed": ""}
            for family, method, cycles, seed, error in (
                ("speed irregularity", "fourier", 50, 1, -0.02),
                ("speed irregularity", "fourier", 50, 2, 0.004),
                ("timing bound", "fourier", 50, 1, -0.015),
                ("speed irregularity", "fourier-matched", 50, 1, 0.012),
                ("speed irregularity", "tooth", 50, 1, 0.3),
                ("speed irregularity", "fourier", 150, 1, -0.006))]
    frame = pd.DataFrame(rows)
    (found,) = speed.delta_targets(frame, stated=50)       # the lab's default chain only
    assert not found.passed and "fit edges" in found.name
    assert "50 cycles (3.3 s)" in found.name and found.value == pytest.approx(0.02)
    assert "seed 1" in found.detail and "0.015" in found.detail
    matched, other = speed.delta_findings(frame, stated=50)  # measured, not targets
    assert matched.startswith("beyond") and "matched edges" in matched and "50 cycles" in matched
    assert other.startswith("within") and "150 cycles" in other
    assert "20 samples/tooth, SNR 20 dB" in other            # a corner-only record length


def test_delta_target_says_where_it_holds():
    def found(errors):
        rows = [{"family": "speed irregularity", "method": "fourier", "teeth": 60,
                 "samples_per_tooth": spt, "snr_db": snr, "seed": 1, "cycles": 150,
                 "error": error, "failed": ""} for (spt, snr), error in errors.items()]
        return speed.delta_targets(pd.DataFrame(rows), stated=150)[0].detail

    detail = found({(20, 20): 0.03, (20, 40): -0.005, (50, 20): 0.02, (50, 40): 0.004,
                    (111, 20): -0.009, (111, 40): 0.001})
    assert "within tolerance at SNR ≥ 40 dB (any samples/tooth)" in detail
    assert "at ≥ 111 samples/tooth (any SNR)" in detail
    # a failure at the highest SNR leaves no SNR band; the samples per tooth still have one
    detail = found({(20, 20): 0.003, (20, 40): 0.02, (50, 20): 0.004, (50, 40): 0.001})
    assert "SNR ≥" not in detail and "at ≥ 50 samples/tooth (any SNR)" in detail
    assert "no SNR and no samples" in found({(20, 20): 0.03, (50, 40): 0.02})


def test_record_length_chart(tmp_path):
    rows = [{"family": family, "method": "fourier", "teeth": 60, "samples_per_tooth": spt,
             "snr_db": 20.0, "seed": seed, "cycles": cycles, "error": 0.01 / cycles ** 0.5,
             "failed": ""}
            for family in ("speed irregularity", "timing bound") for cycles in (50, 150, 450)
            for seed in (1, 2) for spt in (20, 50)]
    speed.plot_record_length(pd.DataFrame(rows), tmp_path / "length.png")
    assert (tmp_path / "length.png").stat().st_size > 10_000


def test_spline_baseline_dips_at_the_gap(clean_case):
    run = clean_case.run
    gap = track_teeth(clean_case.edge_times, 60, 2)
    # the gap's interval spans 3 pitches and is taken for one: ω/3 there, δ ≈ 2/3
    assert speed.spline_delta(gap, smoothing=0).min() > 0.5
    plain = record(run, ToothWheel(60), clean_case.sensor)
    delta = speed.spline_delta(track_teeth(plain.edge_times, 60), smoothing=0)
    assert_allclose(delta.mean(), run.delta, rtol=0.01,
                    err_msg="true edges of a plain wheel: the interpolating spline is right")


def test_streamed_edges_equal_in_memory(tmp_path):
    cases = speed.throughput_cases([300_000], tmp_path)
    case = next(cases)
    assert case.data.path.exists()
    rows = run_family(speed.throughput_family(), [case], repeat=1, memory=True)
    chains = [r["setting"] for r in rows]
    assert chains == ["edges", "edges → δ", "matched edges → δ", "edges"]
    # the reference is the in-memory fit edges: the matched ones differ from them by design
    assert [r["edges_equal"] for r in rows] == [True, True, False, True]
    assert all(r["edges"] > 400 for r in rows) and rows[2]["edges"] == rows[0]["edges"]
    streamed = rows[3]
    assert streamed["method"] == "streaming" and streamed["peak_bytes"] > 0
    assert np.isnan(rows[0]["error"]), "δ only for edges → δ"
    assert all(abs(r["error"]) < 0.05 for r in rows[1:3])
    assert list(cases) == [] and not case.data.path.exists(), "the file is deleted"


@pytest.mark.parametrize("hits, n, passed", [
    (198, 200, (True, True)),      # 0.99 of 200: consistent with a true 0.975
    (4950, 5000, (True, False)),   # 0.99 of 5000: too wide, beyond the binomial scatter
    (1700, 2000, (False, True)),   # 0.85 of 2000: too narrow
    (940, 1000, (True, True)),
])
def test_coverage_is_judged_allowing_for_the_number_of_trials(hits, n, passed):
    at_least, at_most = coverage_targets("x", np.arange(n) < hits)
    assert (at_least.passed, at_most.passed) == passed
    assert at_least.value == pytest.approx(hits / n)
