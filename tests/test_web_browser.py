"""`dynlab serve` end to end in a real browser: Playwright for Python driving the system's
Chromium (Debian's ``chromium``; Playwright's own browser download does not run here).
Skipped, with the reason, where either is missing."""
import io
import os
import re
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

playwright = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
CHROMIUM = os.environ.get("DYNLAB_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
if not Path(CHROMIUM).exists():
    pytest.skip(f"no Chromium at {CHROMIUM} (apt-get install chromium)", allow_module_level=True)

SAMPLES = Path(__file__).resolve().parent.parent / "sample_data"
PHOTO = SAMPLES / "lab9-photo"


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    """`dynlab serve` with a class of two, on a free port: its address and the class page's
    link (read from what it prints)."""
    tmp = tmp_path_factory.mktemp("serve")
    roster = tmp / "roster.csv"
    roster.write_text("id,name\ns01,Ivanov\ns02,Petrova\n", encoding="utf-8")
    port = _free_port()
    proc = subprocess.Popen([sys.executable, "-m", "labs.cli.main", "serve", "--port", str(port),
                             "--class", str(tmp / "class"), "--roster", str(roster)],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lines = []
    while not any("class?key=" in line for line in lines):
        lines.append(proc.stdout.readline())
        assert lines[-1] or proc.poll() is None, "".join(lines)
    teacher = re.search(r"(http://\S+/class\?key=\S+)", "".join(lines))[1]
    base = f"http://localhost:{port}"
    deadline = time.time() + 60
    while True:
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            break
        except OSError:
            assert time.time() < deadline and proc.poll() is None, "".join(lines)
            time.sleep(0.2)
    yield base, teacher
    proc.terminate()
    proc.wait(10)


@pytest.fixture(scope="module")
def browser():
    with playwright.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM)
        yield b
        b.close()


def open_section(page, name: str) -> None:
    if page.locator(f"details#{name}").get_attribute("open") is None:
        page.click(f"details#{name} > summary")


def fill(page, values: dict) -> None:
    for field, text in values.items():
        page.fill(f"[id='{field}']", text)


def reduce_lab1(page, base: str) -> None:
    """A student types lab 1's trifilar readings with decimal commas and presses Reduce."""
    page.goto(f"{base}/lab/lab1")
    fill(page, {"meta.student": "A. Ivanov", "body.m": "11,800"})
    open_section(page, "trifilar")
    fill(page, {"trifilar.R1": "99,8", "trifilar.R2": "140,3", "trifilar.l": "799,8",
                "trifilar.n_osc": "20", "trifilar.t": "36,07; 36,21; 36,22",
                "trifilar.m_p": "2,104", "trifilar.t_p": "34,38; 34,27; 34,33"})
    page.click("button.primary")
    page.wait_for_url("**/run/*", timeout=120_000)


def test_lab1_typed_with_decimal_commas_gives_the_report_and_its_pdf(server, browser):
    from pypdf import PdfReader

    base, _ = server
    page = browser.new_page()
    reduce_lab1(page, base)
    report = page.frame_locator("iframe.report")
    report.locator("text=J_tr").first.wait_for(timeout=60_000)
    assert "A. Ivanov" in report.locator("body").inner_text()
    with page.expect_download() as got:
        page.click("text=PDF")
    pdf = PdfReader(io.BytesIO(Path(got.value.path()).read_bytes()))
    assert "J" in pdf.pages[0].extract_text() and len(pdf.pages) >= 1
    page.close()


def test_lab9_photograph_attached_gives_delta(server, browser):
    base, _ = server
    page = browser.new_page()
    page.goto(f"{base}/lab/lab9")
    open_section(page, "decay")
    fill(page, {"decay.I": "0,03 ± 0,00015 kg*m^2", "decay.cal_phi": "0; 3; 6; 9",
                "decay.cal_reading": "0,06239; 10,47; 21; 31,48"})
    page.set_input_files("[id='decay.signal']", str(PHOTO / "decay.jpg"))
    open_section(page, "image")
    fill(page, {"image.mark_period": "1", "image.paper_width": "120"})
    page.click("button.primary")
    page.wait_for_url("**/run/*", timeout=180_000)
    text = page.frame_locator("iframe.report").locator("body")
    text.locator("text=δ").first.wait_for(timeout=60_000)
    assert "δ" in text.inner_text()
    page.close()


def test_phone_form_is_usable_and_the_class_page_shows_two_hand_ins(server, browser,
                                                                     tmp_path):
    base, teacher = server
    phone = browser.new_page(viewport={"width": 390, "height": 844})
    phone.goto(f"{base}/lab/lab1?lang=ru")
    assert phone.evaluate("document.documentElement.scrollWidth") <= 390   # no sideways scroll
    box = phone.locator("[id='body.m']").bounding_box()
    assert box["width"] > 200 and box["x"] + box["width"] <= 390
    phone.locator("button.primary").scroll_into_view_if_needed()
    assert phone.locator("button.primary").is_visible()
    phone.screenshot(path=str(tmp_path / "phone.png"))
    phone.close()
    for sid in ("s01", "s02"):
        context = browser.new_context()
        page = context.new_page()
        reduce_lab1(page, base)
        page.select_option("select[name=student]", sid)
        page.fill("textarea[name=reported]", "J_trifilar = 0,168 kg*m^2")
        page.click("form.hand-in button")
        page.wait_for_selector("p.ok")
        context.close()
    page = browser.new_page()
    page.goto(teacher)
    rows = page.locator("#handins tbody tr")
    page.wait_for_function("[...document.querySelectorAll('#handins tbody tr')]"
                           ".filter(r => r.cells[2].innerText.includes('lab1')).length == 2",
                           timeout=30_000)
    assert rows.count() == 2
    page.wait_for_selector("#files a:text('summary.csv')", timeout=120_000)
    page.close()
