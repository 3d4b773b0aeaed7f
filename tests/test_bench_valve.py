"""The valve-train stiffness benchmark (processing.bench.valve) on a handful of cases: rows,
errors within the target, refusals of short tables, targets and charts. Timings are never
asserted here (ARCHITECTURE.md, Benchmarks)."""
import numpy as np
import pandas as pd

from processing.bench import valve
from processing.bench.harness import run_family

PNG = b"\x89PNG\r\n\x1a\n"


def test_methods_on_a_few_rigs_within_the_tolerance():
    rows = run_family(valve.stiffness_family(),
                      valve.table_cases((0.25,), (1.0,), (8.0, 30.0), 4), repeat=1)
    frame = pd.DataFrame(rows)
    assert len(frame) == 4 * 2 * 4 and (frame["failed"] == "").all()
    lab = frame[frame["method"] == "midway lines"]
    assert (lab["error"].abs() < valve.TOLERANCE).all()
    assert lab["covered"].notna().all()
    assert frame[frame["method"] == "top secant"]["covered"].isna().all()


def test_tables_of_two_steps_are_refused_and_count_as_failed():
    rows = run_family(valve.stiffness_family("stability", ("midway lines", "pointwise mean")),
                      valve.table_cases((0.25,), (1.0,), (8.0,), 2, steps=(2, 3)), repeat=1)
    frame = pd.DataFrame(rows)
    midway = frame[frame["method"] == "midway lines"]
    assert (midway[midway["steps"] == 2]["failed"] != "").all()
    assert (midway[midway["steps"] == 3]["failed"] == "").all()
    targets = {t.name: t for t in valve.targets(frame)}
    refused = targets["tables of fewer than three steps each way refused"]
    assert refused.passed and refused.value == 1.0


def test_quick_run_writes_its_files_and_targets(tmp_path, monkeypatch):
    small = valve.Plan(scatter=(0.25,), resolution=(1.0,), friction=(8.0,), seeds=3,
                       map_steps=(2, 10), map_friction=(8.0,), map_lash=(0.0,),
                       map_contact=(0.0, 40e-6), map_seeds=1, repeat=1)
    monkeypatch.setattr(valve, "QUICK", small)
    frame, targets = valve.run(tmp_path, quick=True, log=lambda _: None)
    for name in ("error_vs_time.png", "stability_map.png", "curvature_map.png"):
        assert (tmp_path / name).read_bytes().startswith(PNG)
    assert (tmp_path / "bench.csv").exists() and (tmp_path / "targets.json").exists()
    assert {t.name for t in targets} >= {
        "c, midway lines, target region: 95th percentile of |c/c_true − 1|",
        "stability cells (≥ 3 steps) beyond the tolerance and outside the stated U"}
    assert any("midway lines" in line for line in valve.summary_lines(frame))
    assert np.isfinite(frame[frame["family"] == "stiffness"]["error"]).all()
