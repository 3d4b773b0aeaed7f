"""The running valve drive's benchmark (labs.bench.valve_dynamics) on a handful of
cases: rows, the damped sine within its target and its stated interval, the separation
sweep against the scene, targets and charts. Timings are never asserted here
(ARCHITECTURE.md, Benchmarks)."""
import pandas as pd

from labs.bench import valve_dynamics as bench
from processing.bench.harness import run_family

PNG = b"\x89PNG\r\n\x1a\n"
SMALL = bench.Plan(speeds=(1500.0,), clearances=(0.5e-3,), snr_db=(53.0,), seeds=3, sweeps=2,
                   repeat=1)


def test_the_damped_sine_reads_the_drives_frequency():
    """At the sample's SNR every opening's ν is within the target and inside its interval;
    the spectrum's peak, a bin of a zero-padded FFT, is coarser."""
    frame = pd.DataFrame(run_family(bench.frequency_family(), bench.opening_cases(SMALL),
                                    repeat=1))
    assert len(frame) == 3 * 3 and (frame["failed"] == "").all()
    fit = frame[frame["method"] == "damped sine"]
    assert (fit["error"].abs() < bench.NU_TOLERANCE).all()
    assert fit["covered"].all()
    assert frame[frame["method"] == "spectrum peak"]["covered"].isna().all()


def test_quick_run_writes_its_files_and_targets(tmp_path, monkeypatch):
    monkeypatch.setattr(bench, "QUICK", SMALL)
    frame, targets = bench.run(tmp_path, quick=True, log=lambda _: None)
    assert (tmp_path / "error_vs_time.png").read_bytes().startswith(PNG)
    assert (tmp_path / "bench.csv").exists() and (tmp_path / "targets.json").exists()
    sep = frame[frame["family"] == "separation"]
    assert len(sep) == 2 and (sep["error"].abs() < bench.SEPARATION_TOLERANCE).all()
    names = {t.name for t in targets}
    assert "separation speed at 0.8 mm: 95th percentile of |n_sep/n_true − 1|" in names
    assert any("damped sine" in line for line in bench.summary_lines(frame))
