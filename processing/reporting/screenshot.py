"""A report's first screen as a person sees it: the HTML drawn by a real, headless browser.

Chromium (or Chrome) draws the page at a laptop's window size and saves what the window
shows. Nothing here is needed to write a report; it makes the pictures of the documentation's
gallery, so the browser is looked for only when a screenshot is asked for.
"""
from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

from processing.diagnostics import InputError

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable", "chrome")
WINDOW = (1100, 850)
"""The window the first screen is taken in, px: a laptop's browser window."""


def find_browser(given: str | None = None) -> str:
    """The browser to draw with: ``given`` (a name on PATH or a path), else the first of
    :data:`BROWSERS` on PATH."""
    for name in (given,) if given else BROWSERS:
        found = shutil.which(name)
        if found:
            return found
    raise InputError(f"no browser found (looked for {given or ', '.join(BROWSERS)})",
                     "install Chromium (apt-get install chromium) or give --browser PATH",
                     field="--browser")


def screenshot(html: Path, png: Path, browser: str, window=WINDOW, timeout: float = 60.0) -> Path:
    """Draw ``html`` in a headless ``browser`` window of ``window`` px and save it to ``png``.

    The browser runs with a profile of its own in a temporary folder, so it neither reads nor
    changes the user's, and without a sandbox (a container's root cannot start one).
    """
    png = Path(png).resolve()
    with tempfile.TemporaryDirectory(prefix="dynlab-browser-") as profile:
        cmd = [browser, "--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
               f"--user-data-dir={profile}", f"--window-size={window[0]},{window[1]}",
               f"--screenshot={png}", Path(html).resolve().as_uri()]
        done = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if done.returncode != 0 or not png.is_file():
        tail = (done.stderr or done.stdout).strip().splitlines()[-1:] or ["no output"]
        raise RuntimeError(f"{browser} drew no screenshot of {html}: {tail[0]}")
    return png
