"""What every test of the ``dynlab`` command shares: running it in-process, writing a
measurement file from a dict, and the contract a rejected input must keep."""
import re
import tomllib
from pathlib import Path

from labs.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
LAB1 = ROOT / "sample_data" / "lab1" / "flywheel.toml"
LAB2 = ROOT / "sample_data" / "lab2" / "conrod.toml"
SAMPLES = {"lab1": LAB1, "lab2": LAB2}


def run(capsys, *argv):
    """``dynlab *argv`` in-process → (exit code, stdout, stderr)."""
    code = main([str(a) for a in argv])
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def sample(lab: str) -> dict:
    return tomllib.loads(SAMPLES[lab].read_text(encoding="utf-8"))


def assert_one_clear_error(code, out, err, file: Path, field, problem: str, out_dir: Path):
    """The contract for bad input, with the whole output in every failure message."""
    shown = f"\n--- stdout:\n{out}\n--- stderr:\n{err}"
    assert code == 2, f"exit code {code}, expected 2{shown}"
    assert "Traceback" not in out + err, f"a traceback reached the user{shown}"
    lines = err.strip().splitlines()
    assert len(lines) == 1, f"expected exactly one message on stderr, got {len(lines)}{shown}"
    msg = lines[0]
    assert msg.startswith("error: "), f"the message does not start with 'error: '{shown}"
    assert file.name in msg, f"the message does not name the file {file.name}{shown}"
    if field is not None:
        assert f"field '{field}'" in msg, f"the message does not name the field {field!r}{shown}"
    assert "Fix:" in msg and msg.split("Fix:", 1)[1].strip(), f"no fix is given{shown}"
    assert re.search(problem, msg, flags=re.I), f"the message does not say {problem!r}{shown}"
    assert out.strip() == "", f"nothing should be printed on stdout for a bad file{shown}"
    left = sorted(p.name for p in out_dir.iterdir()) if out_dir.exists() else []
    assert not left, f"report files were left in --out although the input is bad: {left}"
