"""Hangs and runaway memory, as a user meets them: the boundary bench's cases about them
(:mod:`labs.bench.boundary`, ``limits=True``: a FIFO or a ``/dev/zero`` link as a measurement
file, a class's submission or a roster; images whose header claims 400 Mpx; 3 GB files), each
run as ``dynlab`` in a child process whose address space is capped.

A case passes when it is handled as it must be (refused with its cause and a fix, or a class
summarised around a bad submission) before :data:`HANG` seconds, with the child's peak
resident memory (``wait4``) under :data:`labs.bench.boundary.MEMORY_LIMIT`. No timing is
asserted: how fast a refusal answers is the bench's target, not a test's.
"""
import pytest

from labs.bench.boundary import corpus, run_case

HANG = 60.0
"""Seconds after which a case counts as hung (the child is killed)."""


@pytest.mark.parametrize("case", [c for c in corpus() if c.limits], ids=lambda c: c.name)
def test_a_hostile_input_is_handled_in_bounded_memory_without_hanging(tmp_path, case):
    row = run_case(case, tmp_path, hang=HANG)
    assert row["verdict"] == "ok", (f"{row['verdict']}: {row['detail']} (exit {row['code']}, "
                                    f"peak {row['peak_mib']:.0f} MiB)\n{row['message']}")
