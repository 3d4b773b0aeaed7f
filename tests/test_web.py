"""`dynlab serve` over HTTP (Starlette's test client): each lab's sample posted through its
generated form gives the result JSON `dynlab run` gives; a bad value comes back at its field
with the boundary's message; and each safety rule (token, host, upload limits, CSRF,
escaping, paths, worker limits, expiry) holds."""
import asyncio
import io
import json
import os
import re
import time
import tomllib
from html.parser import HTMLParser
import zipfile
from pathlib import Path

import pytest

pytest.importorskip("starlette")
pytest.importorskip("multipart")

from starlette.testclient import TestClient  # noqa: E402

from labs.registry import LABS, evaluate  # noqa: E402
from labs.web import forms  # noqa: E402
from labs.web.app import Settings, create_app  # noqa: E402
from labs.web.classroom import Classroom  # noqa: E402
from labs.web.sessions import Store, safe_name  # noqa: E402
from labs.web.worker import Limits, Outcome, Pool  # noqa: E402
from processing.inputs.toml_writer import value_text  # noqa: E402
from processing.measurement import load  # noqa: E402
from processing.reporting.render import to_json  # noqa: E402

SAMPLES = Path(__file__).resolve().parent.parent / "sample_data"
FAST = ["lab1/flywheel.toml", "lab2/conrod.toml", "lab5/valve_train.toml", "lab8/d120.toml",
        "lab9/table1.toml", "dyncalc/marine_diesel.toml"]
"""Samples that reduce in well under a second: each is reduced through the page too. The others
(films, photographs, long recordings: 2–10 s each) go through the form to the boundary by
default, and through the reduction with DYNLAB_WEB_ALL=1."""
SLOW = ["lab3/engine_2regimes.toml", "lab3-photo/photographed_oscillogram.toml",
        "lab4/lab4_seed4.toml", "lab6/lab6_seed6.toml", "lab7/lab7_seed7.toml",
        "lab9-photo/photographed_decay.toml", "lab1-film/flywheel_filmed.toml",
        "dyncalc/car_petrol.toml"]
LAB1 = {"meta.student": "A. Ivanov", "body.m": "11,800", "body.g": "9,8156 ± 0,0005 m/s^2",
        "trifilar.R1": "99,8", "trifilar.R2": "140,3", "trifilar.l": "799,8",
        "trifilar.n_osc": "20", "trifilar.t": "36,07; 36,21; 36,22", "trifilar.m_p": "2,104",
        "trifilar.t_p": "34,38 34,27 34,33"}


@pytest.fixture(scope="module")
def client(tmp_path_factory):
    app = create_app(Settings(root=tmp_path_factory.mktemp("web")))
    with TestClient(app) as c:
        yield c


def csrf(client, path="/lab/lab1") -> str:
    return re.search(r'name="csrf" value="([^"]+)"', client.get(path).text)[1]


def post(client, lab, values, files=None, token=None):
    """POST a lab's form as a browser does (multipart, with the page's CSRF token)."""
    data = {"csrf": token or csrf(client, f"/lab/{lab}"), **values}
    return client.post(f"/lab/{lab}", data=data, files=files or {"_": ("", b"")},
                       follow_redirects=False)


def run_of(client, response):
    assert response.status_code == 303, re.findall(r'role="alert">(.*?)</', response.text)
    return response.headers["location"]


def sample_form(path: Path):
    """A sample measurement file as a student types it into the form: each value into its
    field (readings joined by ';', a table as TOML), each file attached."""
    doc = tomllib.loads(path.read_text(encoding="utf-8"))
    spec = LABS[doc["lab"]].SPEC
    values = {f"meta.{k}": str(v) for k, v in doc.get("meta", {}).items()}
    files = []
    for sec in spec.sections:
        raw = doc.get(sec.name)
        entries = raw if isinstance(raw, list) else [raw] if raw else []
        for i, entry in enumerate(entries):
            where = f"{sec.name}[{i}]" if sec.many else sec.name
            for key, v in entry.items():
                f = sec.field(key)
                if f.kind == "file":
                    files.append((f"{where}.{key}", (v, (path.parent / v).read_bytes())))
                elif f.kind == "flag":
                    values[f"{where}.{key}"] = "on" if v else ""
                elif isinstance(v, list) and not any(isinstance(x, dict) for x in v):
                    values[f"{where}.{key}"] = "; ".join(str(x) for x in v)
                elif isinstance(v, dict):
                    values[f"{where}.{key}"] = value_text(v)
                else:
                    values[f"{where}.{key}"] = str(v)
    return doc["lab"], values, files or {"_": ("", b"")}


def comparable(document: dict) -> dict:
    """A result JSON without what names the server's or the sample's folder."""
    document = dict(document)
    document.pop("toolkit", None)
    return json.loads(json.dumps(document).replace(str(SAMPLES), "")
                      .replace("measurement.toml", "FILE"))


def expected_json(path: Path) -> dict:
    """What `dynlab run --json` prints for the sample (the same call)."""
    return comparable(json.loads(to_json(evaluate(path))))


@pytest.mark.parametrize("sample", FAST + [pytest.param(
    s, marks=pytest.mark.skipif(not os.environ.get("DYNLAB_WEB_ALL"),
                                reason="2–10 s a sample: DYNLAB_WEB_ALL=1 runs it"))
    for s in SLOW])
def test_sample_through_the_form_gives_the_same_result(client, sample):
    path = SAMPLES / sample
    lab, values, files = sample_form(path)
    run = run_of(client, post(client, lab, values, files))
    got = comparable(client.get(f"{run}/report.json").json())
    want = expected_json(path)
    for d in (got, want):
        d["warnings"] = [{**w, "message": re.sub(r"\S+\.toml", "FILE", w["message"])}
                         for w in d["warnings"]]
    assert_same(got, want)


class NoReduction:
    """A pool that reduces nothing and says it went well: the measurement the form wrote is
    then compared with the sample at the boundary, without the reduction's seconds."""

    async def run(self, target, *args) -> Outcome:
        return Outcome("ok")

    def warm(self) -> None:
        return None


@pytest.fixture(scope="module")
def form_only(tmp_path_factory):
    app = create_app(Settings(root=tmp_path_factory.mktemp("web-form")))
    app.state.web.pool = NoReduction()
    with TestClient(app) as c:
        yield c


def _boundary_values(path: Path, lab: str) -> dict:
    """Every value of a measurement file as the lab reads it, a file by its bytes."""
    def value(v):
        named = path.parent / str(v)
        if isinstance(v, (str, Path)) and len(named.name) < 256 and named.is_file():
            return named.read_bytes()
        return v
    return {k: value(v) for k, v in load(path, LABS[lab].SPEC).flat().items()}


@pytest.mark.parametrize("sample", sorted(str(p.relative_to(SAMPLES))
                                          for p in SAMPLES.glob("*/*.toml")))
def test_every_sample_through_the_form_is_the_same_measurement(form_only, sample, tmp_path):
    path = SAMPLES / sample
    lab, values, files = sample_form(path)
    run = run_of(form_only, post(form_only, lab, values, files))
    zipfile.ZipFile(io.BytesIO(form_only.get(f"{run}/measurement.zip").content)).extractall(
        tmp_path)
    written = next(tmp_path.rglob("*.toml"))
    assert _boundary_values(written, lab) == _boundary_values(path, lab)


def assert_same(got, want, where="result"):
    """The same document; numbers to 1e-9 relative: a worker's BLAS runs on one thread, and
    sums taken in another order differ in their last digits."""
    if isinstance(want, dict):
        assert isinstance(got, dict) and got.keys() == want.keys(), where
        for k in want:
            assert_same(got[k], want[k], f"{where}.{k}")
    elif isinstance(want, list):
        assert isinstance(got, list) and len(got) == len(want), where
        for i, (g, w) in enumerate(zip(got, want)):
            assert_same(g, w, f"{where}[{i}]")
    elif isinstance(want, float) and not isinstance(want, bool):
        assert got == pytest.approx(want, rel=1e-9, abs=1e-300), where
    else:
        assert got == want, where


def test_lab1_decimal_commas_report_zip_and_reopen(client, tmp_path):
    run = run_of(client, post(client, "lab1", LAB1))
    page = client.get(run)
    assert page.status_code == 200 and f"{run}/report.pdf" in page.text
    result = client.get(f"{run}/report.json").json()
    assert result["meta"]["student"] == "A. Ivanov"
    assert result["inputs"]["trifilar.t"]["readings"] == [36.07, 36.21, 36.22]
    html = client.get(f"{run}/report.html")
    assert "A. Ivanov" in html.text and "script-src 'none'" in html.headers[
        "content-security-policy"]
    pdf = client.get(f"{run}/report.pdf")
    assert pdf.content.startswith(b"%PDF-")
    blob = client.get(f"{run}/measurement.zip").content
    zipfile.ZipFile(io.BytesIO(blob)).extractall(tmp_path)
    toml = next(tmp_path.rglob("*.toml"))
    assert comparable(json.loads(to_json(evaluate(toml)))) == comparable(result)
    token = csrf(client, "/")
    form = client.post("/open", data={"csrf": token},
                       files={"files": ("lab1.zip", blob, "application/zip")})
    assert form.status_code == 200
    assert 'value="36,07; 36,21; 36,22"' in form.text and 'value="99,8"' in form.text


def row_error(html: str, path: str) -> str:
    """The message shown in the form's row of field ``path``."""
    rows = re.findall(r'<tr class="field has-error">(.*?)</tr>', html, re.S)
    row = next(r for r in rows if f'name="{path}"' in r)
    return re.search(r'role="alert">(.*?)</p>', row, re.S)[1]


@pytest.mark.parametrize("field, typed, says", [
    ("trifilar.l", "12 kg", "is a mass, but a length is expected"),
    ("trifilar.R1", "-99,8", "must be &gt; 0"),
    ("trifilar.n_osc", "20,5", "must be a whole number"),
    ("trifilar.t", "36,07; 36,21; abc", "field &#39;trifilar.t&#39;"),
    ("trifilar.t", "[36.07, 36.21", "is not a TOML value"),
])
def test_a_bad_value_comes_back_at_its_field(client, field, typed, says):
    response = post(client, "lab1", {**LAB1, field: typed})
    assert response.status_code == 422
    message = row_error(response.text, field)
    assert says in message and "Fix:" in message
    assert f'value="{typed.replace("<", "&lt;")}"' in response.text      # what was typed stays
    web = client.app.state.web
    session = next(iter(web.store.sessions.values()))
    last = list(session.runs.values())[-1]
    assert not (last.folder / "report.json").exists()                     # nothing reduced


def test_a_bad_value_in_a_repeated_section_and_in_russian(client):
    client.get("/?lang=ru")
    values = {**LAB1, "analytic[0].shape": "cylinder", "analytic[0].R": "150",
              "analytic[3].shape": "cylinder", "analytic[3].R": "12 s"}
    response = post(client, "lab1", values)
    client.get("/?lang=en")
    message = row_error(response.text, "analytic[1].R")     # entries numbered as the file has
    assert "поле &#39;analytic[1].R&#39;" in message and "Как исправить" in message


def test_a_missing_required_section_is_named_at_the_section(client):
    values = {k: v for k, v in LAB1.items() if not k.startswith("body.")}
    response = post(client, "lab1", values)
    assert response.status_code == 422
    section = re.search(r'<details class="section" id="body" open>(.*?)</details>',
                        response.text, re.S)[1]
    assert "section [body] is missing" in section


# ------------------------------------------------------------------------------ safety

def test_loopback_refuses_another_sites_host(client):
    assert client.get("/", headers={"host": "evil.example"}).status_code == 400


def test_a_token_is_required_on_another_address(tmp_path):
    app = create_app(Settings(root=tmp_path, token="s3cret", hosts=None))
    with TestClient(app) as c:
        assert c.get("/").status_code == 403
        assert c.get("/?token=wrong").status_code == 403
        assert c.get("/lab/lab1", headers={"host": "10.0.0.5"}).status_code == 403
        first = c.get("/?token=s3cret", follow_redirects=False)
        assert first.status_code == 303 and "dynlab_token" in first.headers["set-cookie"]
        assert c.get("/").status_code == 200


def test_csrf_token_is_checked(client):
    assert post(client, "lab1", LAB1, token="forged").status_code == 403
    other = TestClient(client.app)                 # another browser: a session of its own
    assert post(other, "lab1", LAB1, token=csrf(client)).status_code == 403


def test_upload_limits_are_checked_before_reading(tmp_path):
    app = create_app(Settings(root=tmp_path, file_limit=1000, submission_limit=10_000))
    with TestClient(app) as c:
        token = csrf(c)
        big = post(c, "lab1", LAB1, {"trifilar.video": ("film.mp4", b"x" * 2000)}, token)
        assert big.status_code == 413 and "film.mp4" in big.text
        session = next(iter(app.state.web.store.sessions.values()))
        assert not list(session.folder.rglob("film.mp4"))
        read = []

        def body():
            read.append(1)
            yield b"x" * 100

        huge = c.post("/lab/lab1", content=body(), headers={
            "content-length": str(10**9), "content-type": "multipart/form-data; boundary=b"})
        assert huge.status_code == 413 and not read


def test_typed_text_is_escaped(client):
    script = "<script>alert(1)</script>"
    response = post(client, "lab1", {**LAB1, "meta.student": script, "trifilar.t": "[1,"})
    assert response.status_code == 422
    assert script not in response.text and "&lt;script&gt;alert(1)&lt;/script&gt;" in response.text


def test_no_request_reaches_outside_its_session(client):
    run = run_of(client, post(client, "lab1", LAB1))
    assert client.get("/run/..%2F..%2Fetc/report.json").status_code == 404
    other = TestClient(client.app)
    other.get("/")
    assert other.get(f"{run}/report.json").status_code == 404       # not this browser's run
    response = post(client, "lab9", {"decay.I": "0.03", "decay.signal": "../../../etc/passwd",
                                     "decay.cal_phi": "0; 3", "decay.cal_reading": "0; 1",
                                     "decay.T": "20"})
    assert "lies outside the submission" in row_error(response.text, "decay.signal")
    kept = post(client, "lab1", {**LAB1, "source": run.rsplit("/", 1)[1],
                                 "trifilar.video:kept": "../../../../etc/passwd"})
    folder = client.app.state.web.store.sessions
    assert kept.status_code == 303
    assert not any(p.name == "passwd" for s in folder.values() for p in s.folder.rglob("*"))
    assert safe_name("../../x/..\\evil.sh") == "evil.sh"


def test_sessions_expire_with_their_files(tmp_path):
    store = Store(tmp_path, ttl=0.05)
    session = store.new("en")
    run = store.new_run(session, "lab1")
    (run.folder / "photo.jpg").write_bytes(b"x")
    time.sleep(0.1)
    assert store.sweep() == 1 and not session.folder.exists()
    assert store.get(session.id) is None


def sleeper(conn, seconds):
    time.sleep(seconds)
    conn.send(("ok", None))


def hog(conn, size):
    conn.send(("ok", len(bytearray(size))))


def test_worker_time_and_memory_limits_leave_the_pool_working():
    pool = Pool(workers=1, limits=Limits(seconds=2.0, memory=1 << 30))

    async def go():
        slow = await pool.run(sleeper, 60)
        pool.limits = Limits(seconds=120.0, memory=1 << 30)   # a loaded machine starts slowly
        fast = await pool.run(sleeper, 0)
        greedy = await pool.run(hog, 2 << 30)
        return slow, fast, greedy

    slow, fast, greedy = asyncio.run(go())
    assert slow.status == "timeout" and slow.seconds < 10
    assert fast.status == "ok"
    assert greedy.status == "crash"


def test_a_class_check_has_one_reductions_time_per_hand_in():
    """The class's check reduces every hand-in: its time limit is one reduction's times
    their number, so a class of 200 is not stopped at a single reduction's 120 s."""
    pool = Pool(workers=1, limits=Limits(seconds=1.5, memory=1 << 30))

    async def go():
        return await pool.run(sleeper, 2.0), await pool.run(sleeper, 2.0, scale=4)

    alone, scaled = asyncio.run(go())
    assert alone.status == "timeout" and "1.5 s" in alone.error["en"]
    assert scaled.status == "ok"


# ------------------------------------------------------------------------------ teacher

def test_hand_in_lands_where_dynlab_check_reads_it(tmp_path):
    roster = tmp_path / "roster.csv"
    roster.write_text("id,name\ns01,Ivanov\ns02,Petrova\n", encoding="utf-8")
    room = Classroom(tmp_path / "class", roster)
    app = create_app(Settings(root=tmp_path / "web", classroom=room, teacher_token="t"))
    with TestClient(app) as c:
        run = run_of(c, post(c, "lab1", LAB1))
        assert "s01" in c.get(run).text
        handed = c.post(f"{run}/hand-in", data={"csrf": csrf(c), "student": "s01",
                                                "reported": "J_trifilar = 0,198 kg*m^2"},
                        files={"_": ("", b"")}, follow_redirects=False)
        assert handed.status_code == 303
        doc = tomllib.loads((tmp_path / "class/s01/lab1.toml").read_text(encoding="utf-8"))
        assert doc["meta"]["id"] == "s01" and doc["reported"] == {"J_trifilar": "0,198 kg*m^2"}
        assert c.post(f"{run}/hand-in", data={"csrf": csrf(c), "student": "zz"},
                      files={"_": ("", b"")}).status_code == 422
        assert c.get("/class").status_code == 403
        assert c.get("/class?key=t").status_code == 200
        deadline = time.time() + 120
        while "summary.csv" not in c.get("/class/status").json()["files"]:
            assert time.time() < deadline, room.log
            time.sleep(0.3)
        status = c.get("/class/status").json()
        assert status["handins"][0]["labs"] == ["lab1"] and status["handins"][1]["labs"] == []
        assert "s01" in c.get("/class/file/summary.csv").text
        assert c.get("/class/file/..%2Froster.csv").status_code == 404


def test_form_values_round_trip():
    doc = tomllib.loads((SAMPLES / "lab1/flywheel.toml").read_text(encoding="utf-8"))
    values, counts = forms.values(doc, LABS["lab1"].SPEC)
    assert counts["analytic"] == 3
    assert forms.document(LABS["lab1"].SPEC, values) == doc


class _Inputs(HTMLParser):
    """What a browser posts from a page's form: each named input, select and textarea."""

    def __init__(self):
        super().__init__()
        self.values, self._select, self._area = {}, None, None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "template":
            self._skip = True
        if getattr(self, "_skip", False):
            return
        if tag == "option" and self._select:
            if self._select not in self.values or "selected" in a:
                self.values[self._select] = a.get("value", "")
            return
        if "name" not in a:
            return
        if tag == "input" and a.get("type") not in ("file", "checkbox"):
            self.values[a["name"]] = a.get("value", "")
        elif tag == "input" and a.get("type") == "checkbox" and "checked" in a:
            self.values[a["name"]] = a.get("value", "on")
        elif tag == "select":
            self._select = a["name"]
        elif tag == "textarea":
            self._area = a["name"]
            self.values[a["name"]] = ""

    def handle_endtag(self, tag):
        if tag == "template":
            self._skip = False
        if tag in ("select", "textarea"):
            self._select = self._area = None

    def handle_data(self, data):
        if self._area:
            self.values[self._area] += data

    def handle_startendtag(self, tag, attrs):
        self.handle_starttag(tag, attrs)


def _posted(html: str) -> dict:
    parser = _Inputs()
    parser.feed(html)
    return parser.values


def test_a_zip_with_its_recording_opens_for_editing_and_reduces_the_same(client):
    sample = SAMPLES / "lab9/synthetic_damper.toml"
    blob = io.BytesIO()
    with zipfile.ZipFile(blob, "w") as z:
        z.write(sample, "damper/damper.toml")
        z.write(sample.parent / "decay.csv", "damper/decay.csv")
    form = client.post("/open", data={"csrf": csrf(client, "/")},
                       files={"files": ("damper.zip", blob.getvalue())})
    assert form.status_code == 200 and "decay.csv" in form.text
    values = {k: v for k, v in _posted(form.text).items() if k != "csrf"}
    assert values["decay.signal:kept"] == "decay.csv" and values["run[1].direction"] == "reverse"
    run = run_of(client, post(client, "lab9", values))
    assert comparable(client.get(f"{run}/report.json").json()) == expected_json(sample)


def test_a_toml_opened_with_its_recording_opens_as_its_zip_does(client):
    """A handout (``dynlab synth --students``) is a .toml and the files it names: chosen
    together, they open for editing and reduce as the zip of them does."""
    sample = SAMPLES / "lab9/synthetic_damper.toml"
    form = client.post("/open", data={"csrf": csrf(client, "/")},
                       files=[("files", ("damper.toml", sample.read_bytes())),
                              ("files", ("decay.csv", (sample.parent / "decay.csv").read_bytes()))])
    assert form.status_code == 200
    values = {k: v for k, v in _posted(form.text).items() if k != "csrf"}
    assert values["decay.signal:kept"] == "decay.csv"
    run = run_of(client, post(client, "lab9", values))
    assert comparable(client.get(f"{run}/report.json").json()) == expected_json(sample)


def test_a_toml_saved_by_notepad_as_toml_txt_opens(client):
    sample = SAMPLES / "lab1/flywheel.toml"
    form = client.post("/open", data={"csrf": csrf(client, "/")},
                       files=[("files", ("flywheel.toml.txt", sample.read_bytes()))])
    assert form.status_code == 200 and 'name="trifilar.R1"' in form.text


def test_a_toml_opened_without_the_recording_it_names_is_refused_naming_it(client):
    sample = SAMPLES / "lab9/synthetic_damper.toml"
    reply = client.post("/open", data={"csrf": csrf(client, "/")},
                        files=[("files", ("damper.toml", sample.read_bytes()))])
    assert reply.status_code == 422
    assert "names decay.csv (decay.signal), not given with it" in reply.text


@pytest.mark.parametrize("names, problem", [
    (["a.toml", "b.toml"], "2 .toml files chosen, not one"),
    (["decay.csv", "notes.txt"], "0 .toml files chosen, not one"),
])
def test_files_chosen_without_one_toml_are_refused_saying_what_to_choose(client, names,
                                                                         problem):
    reply = client.post("/open", data={"csrf": csrf(client, "/")},
                        files=[("files", (n, b'lab = "lab9"\n')) for n in names])
    assert reply.status_code == 422 and problem in reply.text
    assert "select them all" in reply.text


@pytest.mark.parametrize("argv, file, problem", [
    (["--class", "{tmp}/class"], "{tmp}/class", "--class needs the class's roster"),
    (["--class", "{tmp}/class", "--roster", "{tmp}/none.csv"], "{tmp}/none.csv",
     "file not found"),
    (["--roster", "{tmp}/r.csv"], "{tmp}/r.csv", "--roster goes with --class"),
])
def test_serve_refuses_bad_options_with_one_clear_error(capsys, tmp_path, argv, file, problem):
    from cli_contract import assert_one_clear_error, run

    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    code, out, err = run(capsys, "serve", "--port", str(_free_port()), *argv)
    assert_one_clear_error(code, out, err, Path(file.replace("{tmp}", str(tmp_path))), None,
                           problem, tmp_path / "nothing")


def _free_port() -> int:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_a_zip_bomb_is_cut_off_at_the_limit(tmp_path):
    app = create_app(Settings(root=tmp_path, file_limit=100_000, submission_limit=200_000))
    with TestClient(app) as c:
        blob = io.BytesIO()
        with zipfile.ZipFile(blob, "w", zipfile.ZIP_DEFLATED) as z:
            z.writestr("m/m.toml", 'lab = "lab9"\n')
            z.writestr("m/decay.csv", b"0" * 50_000_000)         # 50 MB in about 50 kB
        assert len(blob.getvalue()) < 100_000
        reply = c.post("/open", data={"csrf": csrf(c, "/")},
                       files={"files": ("m.zip", blob.getvalue())})
        assert reply.status_code == 422 and "unpacks to more than" in reply.text
        stored = [p.stat().st_size for p in (tmp_path / "sessions").rglob("decay.csv")]
        assert stored and max(stored) <= 100_000


def test_a_ratio_is_offered_no_angle_units_and_an_angle_no_share():
    """The units beside a field are of its kind: a rocker ratio's plain number or %, never
    degrees (pint takes both for dimensionless; the reading would be refused)."""
    fields = {f"{lab}.{s.name}.{f.name}": f for lab in LABS for s in LABS[lab].SPEC.sections
              for f in s.fields if f.kind == "quantity" and f.unit is not None}
    offered = {name: {c.value for c in forms.unit_choices(f, "en")} for name, f in fields.items()}
    assert offered["lab5.rig.i"] == {"", "%"}
    angles, plain = {"deg", "rad", "mrad"}, {"", "%"}
    for name, units in offered.items():
        assert not (units & angles and units & plain), (name, units)
