"""The bundled sample data: found beside the sources, or inside the installed wheel."""
from __future__ import annotations

from pathlib import Path

from processing.diagnostics import InputError


def sample_dir(given: str | None = None) -> Path:
    """The sample data: ``--data``, else ./sample_data, else the source tree's, else the copy
    the wheel ships (``labs/sample_data``)."""
    here = Path(__file__).resolve().parent
    candidates = [Path(given)] if given else [Path.cwd() / "sample_data",
                                              here.parent / "sample_data", here / "sample_data"]
    for c in candidates:
        if c.is_dir() and any(c.glob("*/*.toml")):
            return c
    raise InputError("no sample data found", "run from the dynlab source folder, or give "
                     "--data DIR with the sample_data folder", file=str(candidates[0]),
                     ru=("данные примеров не найдены", "запустите из папки исходников dynlab "
                         "или задайте --data DIR с папкой sample_data"))
