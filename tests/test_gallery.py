"""The documentation's gallery: a picture of every sample report, drawn by a real browser."""
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from labs.cli.gallery import index, picture_name
from processing.diagnostics import InputError
from processing.reporting.i18n import LANGS
from processing.reporting.screenshot import BROWSERS, find_browser, screenshot

ROOT = Path(__file__).resolve().parents[1]
GALLERY = ROOT / "docs" / "gallery"
SAMPLES = sorted((ROOT / "sample_data").glob("*/*.toml"))


def test_the_gallery_shows_every_sample_in_every_language():
    page = (GALLERY / "README.md").read_text(encoding="utf-8")
    shown = set(re.findall(r'src="([^"]+)"', page))
    for sample in SAMPLES:
        for lang in LANGS:
            name = picture_name(sample, lang)
            assert name in shown, f"{name} is not in the gallery: run python -m labs.cli.gallery"
            assert (GALLERY / name).stat().st_size > 10_000


def test_the_index_has_a_row_per_sample_and_a_column_per_language():
    page = index(SAMPLES[:2], ("en", "ru"), {s: s.stem for s in SAMPLES[:2]})
    rows = [line for line in page.splitlines() if line.startswith("| `")]
    assert len(rows) == 2 and all(row.count("<img") == 2 for row in rows)


def test_a_missing_browser_is_named_with_its_fix():
    with pytest.raises(InputError, match="no browser found.*apt-get install chromium"):
        find_browser("no-such-browser-dynlab")


@pytest.mark.skipif(not any(shutil.which(b) for b in BROWSERS), reason="no Chromium here")
def test_the_screenshot_is_what_the_browser_draws(tmp_path):
    import cv2

    html = tmp_path / "box.html"
    html.write_text('<body style="margin:0;background:#fff"><div style="width:200px;'
                    'height:100px;background:#000"></div></body>', encoding="utf-8")
    png = screenshot(html, tmp_path / "box.png", find_browser(), window=(400, 300))
    image = cv2.imread(str(png), cv2.IMREAD_GRAYSCALE)
    assert image.shape == (300, 400)
    assert np.mean(image[10:90, 10:190]) < 10 and np.mean(image[150:, 250:]) > 245
