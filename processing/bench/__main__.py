"""``python -m processing.bench [--quick] [--out DIR] [--topic T ...] [--large N]``.

Runs the benchmark of every topic (or those named): each writes ``bench.csv``, its charts
(error against time, stability maps) and ``targets.json`` to ``--out/<topic>/`` (default
``bench-results/``). Prints each topic's summary and one PASS/FAIL line per target, and exits
with 1 if a target fails. Timings are taken on one core: the BLAS/OpenMP thread counts are
set to 1 here, before numpy is first imported.

A topic is a module with ``run(out, quick) -> (DataFrame, list[Target])`` and
``summary_lines(frame) -> list[str]``.
"""
import os

if __name__ == "__main__":
    os.environ.update({name: "1" for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS",
                                              "MKL_NUM_THREADS")})

import argparse  # noqa: E402  (numpy's thread pools are sized when it is first imported)
import importlib  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

from . import damper, docs, film, speed, torsion, valve  # noqa: E402

TOPICS = {"speed": speed, "torsion": torsion, "damper": damper, "valve": valve, "film": film,
          "vibration": "processing.bench.vibration", "paper": "labs.bench.paper",
          "check": "labs.bench.check", "valve_dynamics": "labs.bench.valve_dynamics",
          "boundary": "labs.bench.boundary"}
"""The benchmark topics, by name: a module, or the name of one imported when run (those that
reduce whole labs live in :mod:`labs.bench`: the shared primitives know no lab)."""


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
        description="Time the estimators against their accuracy on synthetic scenes whose "
                    "truth is known; write a CSV, charts and the performance targets.")
    parser.add_argument("--quick", action="store_true",
                        help="coarse grids and short signals (a few minutes in all)")
    parser.add_argument("--topic", action="append", choices=tuple(TOPICS),
                        help="run only this topic (repeat for several; default: all)")
    parser.add_argument("--out", type=Path, default=Path("bench-results"),
                        help="output folder (default: bench-results)")
    parser.add_argument("--docs", type=Path, metavar="DIR",
                        help="also write each topic's page of the documentation (summary, "
                             "targets, charts) to DIR, e.g. docs/bench")
    parser.add_argument("--large", type=_count, metavar="N",
                        help="speed: also stream an N-sample HDF5 file (e.g. 1e9: 2 GB in "
                             "the temporary folder, deleted afterwards)")
    return parser.parse_args(argv)


def main(argv=None) -> int:
    """Run the benchmarks; 0 if every target passes, else 1."""
    args = parse_args(argv)
    passed = True
    for name in args.topic or TOPICS:
        module, out = TOPICS[name], args.out / name
        if isinstance(module, str):
            module = importlib.import_module(module)
        options = {"large": args.large} if name == "speed" else {}
        frame, targets = module.run(out, quick=args.quick, **options)
        summary = module.summary_lines(frame)
        print(f"\n=== {name} ===", *summary, "", *(t.line() for t in targets),
              f"\nwritten to {out}/", sep="\n")
        if args.docs is not None:
            docs.topic_page(args.docs, name, summary, targets, out, quick=args.quick)
            docs.index_page(args.docs, list(TOPICS))
        passed &= all(t.passed for t in targets)
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
