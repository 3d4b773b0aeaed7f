"""``python -m processing.bench [--quick] [--out DIR] [--large N]``: run the benchmarks.

Writes ``bench.csv``, ``error_vs_time.png``, ``time_vs_size.png``, ``stability_map.png``,
``delta_vs_record.png`` and ``targets.json`` to ``--out`` (default ``bench-results/``),
prints a summary and one PASS/FAIL line per target, and exits with 1 if a target fails.
Timings are taken on one core: the BLAS/OpenMP thread counts are set to 1 here, before numpy
is first imported.
"""
import os

if __name__ == "__main__":
    os.environ.update({name: "1" for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                              "MKL_NUM_THREADS")})

import argparse  # noqa: E402  (numpy's thread pools are sized when it is first imported)
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

from . import speed  # noqa: E402
from .harness import summary  # noqa: E402


def _count(text: str) -> int:
    """A positive whole number of samples, also written as ``1e9``."""
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not (value >= 1 and value == int(value)):
        raise argparse.ArgumentTypeError(f"a number of samples ≥ 1 is needed, got {text!r}")
    return int(value)


def parse_args(argv=None) -> argparse.Namespace:
    """The command line of ``python -m processing.bench``."""
    parser = argparse.ArgumentParser(
        prog="python -m processing.bench",
        description="Time the pulse-train estimators against their accuracy on synthetic "
                    "engine recordings; write a CSV, charts and the performance targets.")
    parser.add_argument("--quick", action="store_true",
                        help="a coarse grid and short signals (under a minute)")
    parser.add_argument("--out", type=Path, default=Path("bench-results"),
                        help="output folder (default: bench-results)")
    parser.add_argument("--large", type=_count, metavar="N",
                        help="also stream an N-sample HDF5 file (e.g. 1e9: 2 GB in the "
                             "temporary folder, deleted afterwards)")
    return parser.parse_args(argv)


def report(frame, targets) -> str:
    """The summary printed at the end: per-method table, δ by case, throughput by length,
    the worst δ errors of the target region, δ on the other record lengths, the targets."""
    def fmt(v):
        return f"{v:.3g}"

    lines = ["", "Summary (median over cases; |err|: edge timing in samples, δ relative):",
             summary(frame).to_string(index=False, float_format=fmt), "",
             "δ/δ_true − 1 [%] by case (60−2 wheel, median over seeds):",
             speed.delta_table(frame).to_string(float_format=fmt), "",
             "Throughput by signal length (one core):",
             speed.throughput_table(frame).to_string(float_format=fmt), "",
             "Worst |δ/δ_true − 1| in the target region "
             "(60−2, ≥ 20 samples/tooth, ≥ 20 dB):",
             speed.region_worst(frame).to_string(float_format=fmt), "",
             f"δ findings (other record lengths than the target's {speed.TARGET_CYCLES} "
             "working cycles, and matched edges):",
             *speed.delta_findings(frame), ""]
    return "\n".join(lines + [t.line() for t in targets])


def main(argv=None) -> int:
    """Run the benchmarks; 0 if every target passes, else 1."""
    args = parse_args(argv)
    frame, targets = speed.run(args.out, quick=args.quick, large=args.large)
    print(report(frame, targets))
    print(f"\nwritten to {args.out}/: bench.csv, error_vs_time.png, time_vs_size.png, "
          "stability_map.png, delta_vs_record.png, targets.json")
    return 0 if all(t.passed for t in targets) else 1


if __name__ == "__main__":
    sys.exit(main())
