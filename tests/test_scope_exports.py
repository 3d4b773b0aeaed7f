"""Oscilloscope and acquisition-program exports read as the plain CSV of the same record.

Each layout is written here exactly as the instrument writes it (no real export is copied in:
the layouts are reproduced from where they are documented or quoted):

- Rigol DS1000Z: ``X,CH1,CH2,Start,Increment,`` / ``Sequence,Volt,Volt,-5.999998e-02,
  2.000000e-05`` (the DS1054Z header quoted in vidavidorra/rigol-csv-analyser), rows
  ``0,4.72e+01,2.40e+00,`` with a trailing comma (a lab's DS1000Z file quoted in a public
  parser's docstring);
- Tektronix TDS/TBS1000: 18 settings rows in columns 1–2 beside time and value in columns 4–5
  (Record Length, Sample Interval, Trigger Point, three empty rows, Source, Vertical Units,
  Vertical Scale, Vertical Offset, Horizontal Units, Horizontal Scale, Pt Fmt, Yzero, Probe
  Atten, Model Number, Serial Number, Firmware Version), as TDS2012B files show it;
- Tektronix MSO/MDO: ``Model,MDO3014`` … ``Sample Interval,4e-09`` ``Record Length,1e+07`` …
  ``Vertical Units,V,V`` … ``Label,…`` then ``TIME,CH1,CH2`` (an MDO3014 export quoted in a
  published write-up);
- Siglent SDS: ``Record Length,Analog:4``, ``Sample Interval,1.000000E-07``, ``Vertical
  Units,V``, ``Horizontal Units,s``, ``Source,CH1``, ``Second,Value`` (a public parser's
  fixture);
- Rigol DS1000E: ``X,CH1,CH2`` / ``Second,Voltage,Voltage`` / ``-8.19E-06,-4.00E-03,
  -2.40E-01``, the times printed to three digits so that five rows share one (DS1052E.csv and
  DS1102E-A.csv, exported by the scopes, in scottprahl/RigolWFM's wfm/); and ``Time,X(CH1),
  X(CH2),`` / ``Second,Volt,Volt,`` (quoted in a public reader's comments; a public config's
  DS1102E signature ``Time,X(CH1),X(CH2)``);
- Keysight InfiniiVision: ``x-axis,1,2`` / ``second,Volt,Volt`` / ``-1.000000E-03,+0.0E+00,
  -402.010E-06`` (the 3000 X-series files quoted by several public readers);
- PicoScope 6: ``Time,Channel A,Channel B`` / ``(µs),(V),(V)`` (PicoScope 6 User's Guide,
  Pico Technology, §6.1.1.1.1 "Text formats"), a blank row after the units as its exports have.
"""
import shutil
import warnings

import numpy as np
import pytest

from labs.registry import evaluate
from processing.diagnostics import ClippedRecordWarning, InputError
from processing.inputs.record_quality import check_record, clipped_mask
from processing.inputs.scope_exports import recognise
from processing.inputs.signals import open_channel, open_channels, sample_digest, write_csv

RATE = 50e3
N = 2000
rng = np.random.default_rng(11)
A = np.round(np.sin(2 * np.pi * 250 * np.arange(N) / RATE) + 0.01 * rng.standard_normal(N), 5)
B = np.round(0.5 * np.cos(2 * np.pi * 250 * np.arange(N) / RATE), 5)
T = -0.02 + np.arange(N) / RATE
ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]


def rows(*columns, end=""):
    return "".join(",".join(map(repr, map(float, r))) + end + "\n" for r in zip(*columns))


def rigol(a=A, b=B, step=1 / RATE):
    return ("X,CH1,CH2,Start,Increment,\n"
            f"Sequence,Volt,Volt,{T[0]:e},{step:e},\n"
            + "".join(f"{k},{x!r},{y!r},\n" for k, (x, y) in enumerate(zip(a.tolist(),
                                                                           b.tolist()))))


def tektronix(a=A, t=T, length=N, interval=1 / RATE):
    settings = [f"Record Length,{length:e}", f"Sample Interval,{interval:e}",
                "Trigger Point,1.000000000000e+03", ",", ",", ",", "Source,CH1",
                "Vertical Units,V", "Vertical Scale,5.000000e-01", "Vertical Offset,0.000000e+00",
                "Horizontal Units,s", "Horizontal Scale,4.000000e-03", "Pt Fmt,Y",
                "Yzero,0.000000e+00", "Probe Atten,1.000000e+00", "Model Number,TDS2012B",
                "Serial Number,C012345", "Firmware Version,FV:v22.16"]
    out = []
    for k, (s, x) in enumerate(zip(t.tolist(), a.tolist())):
        meta = settings[k] if k < len(settings) else ","
        out.append(f"{meta},,{s!r},{x!r},\n")
    return "".join(out)


def mso(a=A, b=B):
    return ("Model,MDO3014\nFirmware Version,1.26\n\nWaveform Type,ANALOG,ANALOG\n"
            "Point Format,Y,Y\nHorizontal Units,s,s\nHorizontal Scale,0.004,0.004\n,,\n"
            f"Sample Interval,{1 / RATE:g},{1 / RATE:g}\nRecord Length,{N:g},{N:g}\n"
            "Gating,0.0% to 100.0%,0.0% to 100.0%\n,,\nVertical Units,V,V\nLabel,,\n"
            "TIME,CH1,CH2\n" + rows(T, a, b))


def siglent(a=A):
    return (f"Record Length,Analog:{N}\nSample Interval,{1 / RATE:.6E}\nVertical Units,V\n"
            "Horizontal Units,s\nSource,CH1\nSecond,Value\n" + rows(T, a))


def keysight(a=A, b=B):
    return "x-axis,1,2\nsecond,Volt,Volt\n" + rows(T, a, b)


def rigol_e(a=A, b=B):
    return "Time,X(CH1),X(CH2),\nSecond,Volt,Volt,\n" + rows(T, a, b, end=",")


def pico(a=A, b=B, time_unit="ms", scale=1e3, volt_unit="V", volts=1.0):
    return (f"Time,Channel A,Channel B\n({time_unit}),({volt_unit}),(V)\n\n"
            + rows(T * scale, a * volts, b))


@pytest.fixture
def plain(tmp_path):
    path = tmp_path / "plain.csv"
    write_csv(path, {"a": A, "b": B}, RATE)
    return open_channels(path, ["a", "b"])


@pytest.mark.parametrize("make, names", [
    (rigol, ("CH1", "CH2")), (mso, ("CH1", "CH2")), (keysight, ("CH1", "CH2")),
    (rigol_e, ("CH1", "CH2")), (pico, ("Channel A", "Channel B"))])
def test_exports_read_as_the_plain_csv_by_name_and_index(tmp_path, plain, make, names):
    path = tmp_path / "export.csv"
    path.write_text(make(), encoding="utf-8")
    for selectors in (names, (0, 1), ("0", "1")):
        read = open_channels(path, list(selectors))
        assert [c.name for c in read] == list(names)
        for c, p in zip(read, plain):
            np.testing.assert_array_equal(c.read(), p.read(), err_msg=f"{make.__name__} {c.name}")
            assert c.sample_rate == pytest.approx(p.sample_rate, rel=1e-9)
    assert sample_digest(path) == sample_digest(plain[0].path), "the same recording saved again"


@pytest.mark.parametrize("make, name", [(tektronix, "CH1"), (siglent, "CH1")])
def test_one_channel_exports_read_as_the_plain_csv(tmp_path, plain, make, name):
    path = tmp_path / "export.csv"
    path.write_text(make(), encoding="utf-8")
    channel = open_channel(path, channel=name)
    np.testing.assert_array_equal(channel.read(), plain[0].read())
    assert channel.sample_rate == pytest.approx(RATE, rel=1e-9)
    assert open_channel(path).name == name


@pytest.mark.parametrize("time_unit, scale", [("s", 1.0), ("ms", 1e3), ("µs", 1e6),
                                              ("us", 1e6)])
def test_picoscope_units_rows_scale_to_seconds_and_volts(tmp_path, time_unit, scale):
    path = tmp_path / "pico.csv"
    path.write_text(pico(time_unit=time_unit, scale=scale, volt_unit="mV", volts=1e3),
                    encoding="utf-8")
    channel = open_channel(path, channel="Channel A")
    np.testing.assert_allclose(channel.read(), A, rtol=1e-12, atol=1e-15)
    assert channel.sample_rate == pytest.approx(RATE, rel=1e-9)


def test_a_channel_in_another_unit_is_refused_when_read(tmp_path):
    path = tmp_path / "pico.csv"
    path.write_text(pico(volt_unit="A"), encoding="utf-8")
    assert open_channel(path, channel="Channel B").length == N
    with pytest.raises(InputError, match="'Channel A' is in '\\(A\\)', not in volts.*volts"):
        open_channel(path, channel="Channel A")


MARKS = {"pico": ("Time,Channel A\n(ms),(V)\n\n", {1: "∞", -1: "-∞"}),
         "keysight": ("x-axis,1\nsecond,Volt\n", {1: "+9.9E+37", -1: "-9.9E+37"})}
"""An export's header and its over-range marks: PicoScope's, SCPI's (±9.9E+37)."""


def test_a_time_axis_in_another_unit_is_refused(tmp_path):
    path = tmp_path / "pico.csv"
    path.write_text(pico(time_unit="div"), encoding="utf-8")
    with pytest.raises(InputError, match=r"the time column 'Time' is in '\(div\)', not a unit of "
                                         "time.*s, ms, µs or ns"):
        open_channel(path)


@pytest.mark.parametrize("style", MARKS)
@pytest.mark.parametrize("amplitude, decay, clipped", [(1.2, 0.01, "warned"),
                                                      (1.3, np.inf, "refused")])
def test_over_range_marks_reach_the_clipping_diagnostics(tmp_path, style, amplitude, decay,
                                                         clipped):
    """An 8-bit input on its ±1 V range: samples at or beyond full scale are exported as
    ∞ / -∞ (SCPI: ±9.9E+37); read, they sit at the channel's rail as clipped samples do. A
    free decay whose first swings overrange (1.4 % of its samples) is warned about; a steady
    oscillation beyond the range (45 %) is refused."""
    header, marks = MARKS[style]
    t = np.arange(N) / RATE
    swing = amplitude * np.exp(-t / decay) * np.sin(2 * np.pi * 250 * t)
    codes = np.clip(np.round(swing * 127), -127, 127)
    volts = codes / 127
    over = np.where(codes >= 127, 1, np.where(codes <= -127, -1, 0))
    cells = [marks.get(o, repr(v)) for v, o in zip(volts.tolist(), over)]
    scale = 1e3 if style == "pico" else 1.0
    path = tmp_path / "export.csv"
    path.write_text(header + "".join(f"{t!r},{c}\n" for t, c in
                                     zip((scale * np.arange(N) / RATE).tolist(), cells)),
                    encoding="utf-8")
    x = open_channel(path).read()
    assert np.isfinite(x).all()
    np.testing.assert_array_equal(x[over > 0], volts[over == 0].max())
    np.testing.assert_array_equal(x[over < 0], volts[over == 0].min())
    np.testing.assert_array_equal(x[over == 0], volts[over == 0])
    assert clipped_mask(x)[over != 0].all(), "every over-range sample counts as clipped"
    options = dict(file=str(path), field="decay.signal", channel="CH1")
    if clipped == "warned":
        with pytest.warns(ClippedRecordWarning, match="sit at the recorder's limits"):
            check_record(x, RATE, **options)
    else:
        with pytest.raises(InputError, match="is clipped"):
            check_record(x, RATE, **options)


def test_an_scpi_not_a_number_is_refused_naming_its_row(tmp_path):
    path = tmp_path / "keysight.csv"
    text = "x-axis,1\nsecond,Volt\n" + rows(T[:4], [0.1, 0.2, 0.3, 0.4]).replace(
        "0.3\n", "9.91E+37\n")
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError, match="row 5, column 'CH1' holds 9.91e\\+37, the "
                                         "instrument's mark of a sample it does not have"):
        open_channel(path).read()


def test_a_channel_all_over_range_is_refused(tmp_path):
    path = tmp_path / "pico.csv"
    path.write_text("Time,Channel A\n(ms),(V)\n\n" + "".join(f"{k},∞\n" for k in range(10)),
                    encoding="utf-8")
    with pytest.raises(InputError, match="every sample of 'Channel A' is marked over range"):
        open_channel(path).read()


@pytest.mark.parametrize("text, problem", [
    (tektronix(length=N + 500),
     r"'Record Length' \(row 1\) says 2500 samples, but 2000 rows.*correct Record Length"),
    (tektronix(interval=2 / RATE),
     r"row 2: the time column 'TIME' steps by 2e-05 s, but the header's 'Sample Interval' "
     r"\(row 2\) is 4e-05 s"),
    (tektronix(t=np.delete(T, 700), a=np.delete(A, 700), length=N - 1),
     r"row 701: the time column 'TIME' steps by 4e-05 s.*'Sample Interval'"),
    (rigol().replace("\n700,", "\n701,", 1),
     r"row 703: the time column 'X' steps by 4e-05 s, but the header's 'Increment' \(row 2\)"),
    (mso().replace(f"Record Length,{N:g}", "Record Length,1000"),
     r"'Record Length' \(row 10\) says 1000 samples"),
    (keysight()[:-12], r"the last row \(row 2002\) is cut short"),
])
def test_inconsistent_headers_are_refused_naming_the_field_and_row(tmp_path, text, problem):
    path = tmp_path / "export.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError, match=problem) as info:
        open_channel(path).read()
    assert info.value.file == str(path) and info.value.fix


@pytest.mark.parametrize("text, instrument", [
    ("X,CH1,Start,Increment,\nSequence,Volt,-2.000000e-02,2.000000e-05,\n", "Rigol DS1000Z"),
    ("Time,Channel A\n(ms),(V)\n\n", "PicoScope"),
    ("x-axis,1\nsecond,Volt\n", "Keysight InfiniiVision"),
    ("".join(r.partition(",,")[0] + "\n" for r in tektronix().splitlines()[:18]),
     "oscilloscope"),
])
def test_a_header_without_samples_is_refused(tmp_path, text, instrument):
    path = tmp_path / "export.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError, match=f"the {instrument} export holds its header .* but no "
                                         "samples"):
        open_channel(path)


def test_an_unknown_instrument_keeps_its_clear_refusal(tmp_path):
    path = tmp_path / "export.csv"
    path.write_text("Saved by,ScopeX 9000\nChannel,Amplitude\n0.0,0.1\n1.0,0.2\n",
                    encoding="utf-8")
    with pytest.raises(InputError, match="row 2 holds no number"):
        open_channel(path)


def test_plain_tables_are_not_exports():
    assert recognise([(1, "t,u"), (2, "0.0,1.0")], None) is None
    assert recognise([(1, "0.0 1.0"), (2, "1.0 2.0"), (3, "2.0 3.0")], None) is None


@pytest.mark.parametrize("export", ["keysight", "pico"])
def test_lab9_gives_the_same_result_from_an_instrument_export(tmp_path, export):
    """Lab 9's sample decay recording re-exported as a Keysight and as a PicoScope file (the
    same cells under the instrument's header) reduces to identical results."""
    folder = tmp_path / "lab9"
    shutil.copytree(ROOT / "sample_data" / "lab9", folder)
    header, *lines = (folder / "decay.csv").read_text().splitlines()
    assert header == "t,u"
    top = {"keysight": "x-axis,1\nsecond,Volt\n", "pico": "Time,Channel A\n(s),(V)\n\n"}[export]
    (folder / "decay.csv").write_text(top + "\n".join(lines) + "\n")
    original = evaluate(ROOT / "sample_data" / "lab9" / "synthetic_damper.toml", n_samples=2000)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ClippedRecordWarning)
        exported = evaluate(folder / "synthetic_damper.toml", n_samples=2000)
    assert exported.to_dict()["results"] == original.to_dict()["results"]
    assert [w.code for w in exported.warnings] == [w.code for w in original.warnings]


LVM = ROOT / "tests" / "data" / "lvm_read_short.lvm"
"""A LabVIEW-written LVM file (ladisk/lvm_read's data/short.lvm, MIT; tests/data/README.md)."""


def labview(a=A, b=B, x_columns="One", segments=1):
    """A LabVIEW Measurement file as Write To Measurement File saves it (the layout of the
    real file :data:`LVM`), tab-separated, decimal point."""
    head = ("LabVIEW Measurement\t\nWriter_Version\t2\nReader_Version\t2\nSeparator\tTab\n"
            "Decimal_Separator\t.\nMulti_Headings\tNo\n"
            f"X_Columns\t{x_columns}\nTime_Pref\tRelative\nOperator\tlab\nDate\t2026/11/28\n"
            "Time\t00:40:00.0\n***End_of_Header***\t\n\t\n")
    segment = (f"Channels\t2\t\t\nSamples\t{N}\t{N}\t\nDate\t2026/11/28\t2026/11/28\t\n"
               "Time\t00:40:00.0\t00:40:00.0\t\nY_Unit_Label\tVolts\tVolts\t\n"
               f"X_Dimension\tTime\tTime\t\nX0\t{T[0]:.16E}\t{T[0]:.16E}\t\n"
               f"Delta_X\t{1 / RATE:.6E}\t{1 / RATE:.6E}\t\n***End_of_Header***\t\t\t\n"
               "X_Value\tacc\ttdc\tComment\n")
    if x_columns == "One":
        body = rows(T, a, b).replace(",", "\t")
    else:
        body = "".join(f"\t{x!r}\t{y!r}\n" for x, y in zip(a.tolist(), b.tolist()))
    return head + (segment + body) * segments


def test_a_labview_written_lvm_file_is_recognised_and_its_units_judged(tmp_path):
    """The real file's channels are in Newtons and m/s²: refused, the lab wants volts; the
    same file in Volts reads its decimal-comma samples at 1 / Delta_X = 25 600 Hz."""
    with pytest.raises(InputError, match="'Excitation \\(Trigger\\)' is in 'Newtons', not in "
                                         "volts"):
        open_channel(LVM)
    volts = tmp_path / "short.lvm"
    volts.write_text(LVM.read_text(encoding="utf-8").replace("Newtons\tm/s^2", "Volts\tVolts"),
                     encoding="utf-8")
    first, second = open_channels(volts, ["Excitation (Trigger)", 1])
    assert (first.name, second.name) == ("Excitation (Trigger)", "Response (Trigger)")
    assert first.sample_rate == 25600.0 and first.length == 10
    np.testing.assert_array_equal(first.read()[:3], [0.914018, 0.537321, 0.616905])
    np.testing.assert_array_equal(second.read()[-1], 1.212775)


@pytest.mark.parametrize("x_columns", ["One", "No"])
def test_lvm_files_read_as_the_plain_csv(tmp_path, plain, x_columns):
    path = tmp_path / "run.lvm"
    path.write_text(labview(x_columns=x_columns), encoding="utf-8")
    for c, p in zip(open_channels(path, ["acc", "tdc"]), plain):
        np.testing.assert_array_equal(c.read(), p.read())
        assert c.sample_rate == pytest.approx(p.sample_rate, rel=1e-9)


def test_an_lvm_file_of_two_segments_is_refused(tmp_path):
    path = tmp_path / "run.lvm"
    path.write_text(labview(segments=2), encoding="utf-8")
    with pytest.raises(InputError, match=f"a second segment begins: its header ends at row "
                                         f"{13 + 9 + 1 + N + 9}"):
        open_channel(path)


def ds1000e(rate=500e6, n=N):
    """A Rigol DS1052E export as the scope writes it: times and volts to three digits."""
    t = -8.19e-06 + np.arange(n) / rate
    return ("X,CH1,CH2\nSecond,Voltage,Voltage\n"
            + "".join(f"{s:.2E},{a:.2E},{b:.2E}\n" for s, a, b in zip(t, A[:n], B[:n])))


def test_a_ds1000e_export_takes_its_rate_from_sample_rate_checked_against_its_times(tmp_path):
    path = tmp_path / "ds1052e.csv"
    path.write_text(ds1000e(), encoding="utf-8")
    with pytest.raises(InputError, match=r"the time column 'X' repeats its times from row 4 "
                                         r"\(-8.19e-06 s\).*give sample_rate"):
        open_channel(path)
    first, second = open_channels(path, ["CH1", "CH2"], sample_rate=500e6)
    assert first.sample_rate == 500e6 and first.length == N
    np.testing.assert_array_equal(second.read(), [float(f"{b:.2E}") for b in B])
    with pytest.raises(InputError, match=r"sample_rate = 5e\+07 Hz puts row 5 at -8.15e-06 s, but its "
                                         r"time is -8.19e-06 s \(the times are rounded to "
                                         r"1e-08 s\)"):
        open_channel(path, sample_rate=50e6)


def test_the_first_rows_of_a_real_ds1054z_export(tmp_path):
    """The first rows of DS1054Z-A.csv (scottprahl/RigolWFM, wfm/), as the scope wrote them:
    four channels, the second header row without the trailing comma the rows carry."""
    path = tmp_path / "DS1054Z-A.csv"
    path.write_text("X,CH1,CH2,CH3,CH4,Start,Increment,\n"
                    "Sequence,Volt,Volt,Volt,Volt,-3.000000e-07,5.000000e-10\n"
                    "0,3.28e+00,9.60e-01,-1.60e-01,0.00e+00,\n"
                    "1,3.28e+00,9.60e-01,-1.60e-01,0.00e+00,\n"
                    "2,3.20e+00,9.60e-01,-8.00e-02,0.00e+00,\n"
                    "3,3.20e+00,9.60e-01,-8.00e-02,0.00e+00,\n"
                    "4,3.20e+00,1.12e+00,0.00e+00,0.00e+00,\n", encoding="utf-8")
    channels = open_channels(path, ["CH3", 3])
    assert [c.name for c in channels] == ["CH3", "CH4"]
    assert channels[0].sample_rate == pytest.approx(2e9, rel=1e-12)
    np.testing.assert_array_equal(channels[0].read(), [-0.16, -0.16, -0.08, -0.08, 0.0])


TDS2001C = """Record Length,2.50E+03,,-0.00000033,0.0056
Sample Interval,1.00E-09,,-0.000000329,0.0056
Trigger Point,3.30E+02,,-0.000000328,0.0056
,,,-0.000000327,0.0056
,,,-0.000000326,0.0056
,,,-0.000000325,0.0048
Source,CH1,,-0.000000324,0.0056
Vertical Units,V,,-0.000000323,0.0056
Vertical Scale,2.00E-02,,-0.000000322,0.0048
Vertical Offset,-4.32E-02,,-0.000000321,0.0056
Horizontal Units,s,,-0.00000032,0.0048
Horizontal Scale,2.50E-07,,-0.000000319,0.0056
Pt Fmt,Y,,-0.000000318,0.0048
Yzero,0.00E+00,,-0.000000317,0.0048
Probe Atten,1.00E+01,,-0.000000316,0.0048
Model Number,TDS2001C,,-0.000000315,0.0048
Serial Number,C040529,,-0.000000314,0.0048
Firmware Version,FV:v24.26,,-0.000000313,0.0048
,,,-0.000000312,0.0048
,,,-0.000000311,0.0048
,,,-0.00000031,0.0056
"""
"""The first 21 rows of a TDS2001C's F0000CH1.CSV as the scope wrote it (chemdrv/
python-for-pchem): no trailing comma, the settings printed as 2.50E+03."""


def test_the_first_rows_of_a_real_tds2001c_export(tmp_path):
    path = tmp_path / "F0000CH1.CSV"
    path.write_text(TDS2001C, encoding="utf-8")
    with pytest.raises(InputError, match=r"'Record Length' \(row 1\) says 2500 samples, but 21 "
                                         "rows of numbers follow"):
        open_channel(path)
    path.write_text(TDS2001C.replace("2.50E+03", "21"), encoding="utf-8")
    channel = open_channel(path, channel="CH1")
    assert channel.sample_rate == pytest.approx(1e9, rel=1e-12) and channel.length == 21
    np.testing.assert_array_equal(channel.read()[:6], [0.0056] * 5 + [0.0048])


def test_the_picoscope_manuals_layout(tmp_path):
    """PicoScope 6 User's Guide, §6.1.1.1.1: "Time, Channel A, Channel B / (µs), (V), (V) /
    -500.004, 5.511, 1.215 / -500.002, 4.724, 2.130 / -500, 5.552, 2.212" (a space after each
    comma, no blank row)."""
    path = tmp_path / "pico.csv"
    path.write_text("Time, Channel A, Channel B\n(µs), (V), (V)\n-500.004, 5.511, 1.215\n"
                    "-500.002, 4.724, 2.130\n-500, 5.552, 2.212\n", encoding="utf-8")
    a, b = open_channels(path, ["Channel A", "Channel B"])
    assert a.sample_rate == pytest.approx(500e6, rel=1e-6)  # 2 ns steps
    np.testing.assert_array_equal(b.read(), [1.215, 2.130, 2.212])


def test_a_segmented_memory_saved_whole_is_refused_asking_for_one_segment(tmp_path):
    """Keysight's "save all segments": a second acquisition's times follow the first's after
    a gap; the fix names the segments, not lost samples alone."""
    path = tmp_path / "segments.csv"
    half = N // 2
    path.write_text("x-axis,1,2\nsecond,Volt,Volt\n" + rows(T[:half], A[:half], B[:half])
                    + rows(T[:half] + 1.0, A[:half], B[:half]), encoding="utf-8")
    with pytest.raises(InputError, match="export one segment"):
        open_channel(path, field="decay.signal")
