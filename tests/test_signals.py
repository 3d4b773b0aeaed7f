"""Signal readers and writers: round trips through CSV, WAV and HDF5, chunked reads, and
errors that name the file, the field and the fix."""
import pickle
import struct

import h5py
import numpy as np
import pytest
from scipy.io import wavfile

from processing.diagnostics import InputError
from processing.inputs import signals
from processing.inputs.signals import (
    kept_open,
    open_channel,
    open_channels,
    read_edge_times,
    write_csv,
    write_hdf5,
    write_wav,
)

FIELD = "regime[0].signal"
rng = np.random.default_rng(7)


def assert_chunks_make_read(channel, sizes=(1, 7, 1000, 2**22)):
    whole = channel.read()
    assert len(whole) == channel.length and whole.dtype == channel.dtype
    for size in sizes:
        blocks = list(channel.chunks(size))
        assert all(len(b) == size for b in blocks[:-1]) and 0 < len(blocks[-1]) <= size
        np.testing.assert_array_equal(np.concatenate(blocks), whole, err_msg=f"size {size}")
    return whole


def wav_24bit(path, codes, rate, rf64=False):
    """A 24-bit PCM WAV of integer codes (frames × channels, within ±2²³), RIFF or RF64."""
    codes = np.atleast_2d(codes.T).T
    frames, count = codes.shape
    data = (codes.astype("<i4").view(np.uint8).reshape(frames, count, 4)[:, :, :3]).tobytes()
    fmt = struct.pack("<HHIIHH", 1, count, rate, rate * 3 * count, 3 * count, 24)
    chunks = b"fmt " + struct.pack("<I", len(fmt)) + fmt
    chunks += b"data" + struct.pack("<I", 0xFFFFFFFF if rf64 else len(data)) + data
    if rf64:  # sizes in a ds64 chunk: RIFF size, data size, sample count, table length
        size = 4 + 36 + len(chunks)
        ds64 = b"ds64" + struct.pack("<I", 28) + struct.pack("<QQQI", size, len(data), frames, 0)
        path.write_bytes(b"RF64" + struct.pack("<I", 0xFFFFFFFF) + b"WAVE" + ds64 + chunks)
    else:
        path.write_bytes(b"RIFF" + struct.pack("<I", 4 + len(chunks)) + b"WAVE" + chunks)


# ---- round trips ----

def test_csv_round_trip_with_time_column(tmp_path):
    x = rng.normal(size=1234)
    codes = rng.integers(-500, 500, size=1234)
    write_csv(tmp_path / "rec.csv", {"x": x, "codes": codes}, sample_rate=2500.0)
    ch = open_channel(tmp_path / "rec.csv", field=FIELD)
    assert (ch.name, ch.length, ch.dtype, ch.field) == ("x", 1234, np.float64, FIELD)
    assert ch.sample_rate == pytest.approx(2500.0, rel=1e-12)
    assert ch.duration == pytest.approx(1234 / 2500.0, rel=1e-12)
    np.testing.assert_array_equal(assert_chunks_make_read(ch), x)
    ints = open_channel(tmp_path / "rec.csv", channel=1)
    assert ints.name == "codes" and ints.dtype.kind == "i"
    np.testing.assert_array_equal(ints.read(), codes)


def test_wav_round_trip_stereo(tmp_path):
    tooth = rng.integers(-2**15, 2**15, size=5000, dtype=np.int16)
    tdc = rng.integers(-2**15, 2**15, size=5000).astype(np.int16)
    write_wav(tmp_path / "rec.wav", {"tooth": tooth, "tdc": tdc}, 48000)
    left, right = open_channels(tmp_path / "rec.wav", ["left", "right"])
    assert (left.name, right.name) == ("channel 0", "channel 1")
    assert left.sample_rate == right.sample_rate == 48000.0 and left.dtype == np.int16
    np.testing.assert_array_equal(assert_chunks_make_read(left), tooth)
    np.testing.assert_array_equal(assert_chunks_make_read(right), tdc)
    np.testing.assert_array_equal(open_channel(tmp_path / "rec.wav", channel=1).read(), tdc)
    np.testing.assert_array_equal(open_channel(tmp_path / "rec.wav").read(), tooth)


@pytest.mark.parametrize("dtype", [np.uint8, np.int16, np.int32, np.float32, np.float64])
def test_wav_sample_types_are_kept(tmp_path, dtype):
    data = (rng.normal(size=(300, 2)) * (0.5 if np.dtype(dtype).kind == "f" else 100)
            + (128 if dtype is np.uint8 else 0)).astype(dtype)
    wavfile.write(tmp_path / "rec.wav", 22050, data)
    ch = open_channel(tmp_path / "rec.wav", channel="right")
    assert ch.dtype == dtype and ch.sample_rate == 22050.0
    np.testing.assert_array_equal(assert_chunks_make_read(ch), data[:, 1])


@pytest.mark.parametrize("rf64", [False, True])
def test_wav_24_bit_streams_as_scipy_reads_it(tmp_path, rf64):
    codes = rng.integers(-2**23, 2**23, size=(777, 2))
    wav_24bit(tmp_path / "rec.wav", codes, 96000, rf64=rf64)
    ch = open_channel(tmp_path / "rec.wav", channel=1)
    assert (ch.length, ch.sample_rate, ch.dtype) == (777, 96000.0, np.int32)
    whole = assert_chunks_make_read(ch, sizes=(1, 100))
    np.testing.assert_array_equal(whole, codes[:, 1] * 256, err_msg="left-justified int32")
    np.testing.assert_array_equal(whole, wavfile.read(tmp_path / "rec.wav")[1][:, 1])


def test_hdf5_written_from_blocks_reads_back_by_slices(tmp_path):
    blocks = [rng.integers(-2**11, 2**11, size=n).astype(np.int16) for n in (1000, 1, 0, 4321)]
    tdc = rng.normal(size=5322)
    write_hdf5(tmp_path / "rec.h5", {"raw/tooth": iter(blocks), "raw/tdc": tdc}, 1e6,
               volts_per_code=5 / 2**12, attrs={"rig": "D-240 stand"})
    whole = np.concatenate(blocks)
    tooth, ref = open_channels(tmp_path / "rec.h5", ["raw/tooth", "/raw/tdc"], field=FIELD)
    assert (tooth.length, tooth.dtype, tooth.sample_rate) == (5322, np.int16, 1e6)
    assert tooth.volts_per_code == 5 / 2**12
    np.testing.assert_array_equal(assert_chunks_make_read(tooth), whole)
    np.testing.assert_array_equal(ref.read(), tdc)
    part = np.concatenate(list(tooth.chunks(size=300, start=999, stop=4000)))
    np.testing.assert_array_equal(part, whole[999:4000])
    assert list(tooth.chunks(size=10, start=7, stop=7)) == []
    with h5py.File(tmp_path / "rec.h5") as f:
        assert f.attrs["rig"] == "D-240 stand"
        assert f["raw/tooth"].chunks is not None and f["raw/tdc"].attrs["sample_rate"] == 1e6


def test_kept_open_opens_a_recording_once_for_its_channels_and_their_samples(tmp_path,
                                                                           monkeypatch):
    data = {"acc": rng.normal(size=3000), "tdc": rng.integers(0, 2, 3000).astype(np.int16)}
    write_hdf5(tmp_path / "rec.h5", data, 25600.0)
    outside = [c.read() for c in open_channels(tmp_path / "rec.h5", ["acc", "tdc"])]
    opened, plain = [], h5py.File

    def counted(*args, **kwargs):
        opened.append(plain(*args, **kwargs))
        return opened[-1]

    monkeypatch.setattr(signals.h5py, "File", counted)
    with kept_open():
        channels = open_channels(tmp_path / "rec.h5", ["acc", "tdc"])
        with kept_open():
            inside = [c.read() for c in channels]
        assert len(opened) == 1 and opened[0].id.valid
    assert not opened[0].id.valid            # closed when the outermost block ends
    for a, b, x in zip(outside, inside, data.values()):
        np.testing.assert_array_equal(a, x)
        np.testing.assert_array_equal(b, x)
    inside[0] = channels[0].read()            # outside the block: opened and closed again
    assert len(opened) == 2 and not opened[1].id.valid


def test_hdf5_blocks_fill_a_declared_length(tmp_path):
    blocks = [np.arange(4.0), np.arange(6.0)]
    write_hdf5(tmp_path / "ok.h5", {"x": iter(blocks)}, 10.0, length=10)
    np.testing.assert_array_equal(open_channel(tmp_path / "ok.h5").read(), np.concatenate(blocks))
    with pytest.raises(ValueError, match="length=9"):
        write_hdf5(tmp_path / "long.h5", {"x": iter(blocks)}, 10.0, length=9)
    with pytest.raises(ValueError, match="got 10 samples, not length=11"):
        write_hdf5(tmp_path / "short.h5", {"x": iter(blocks)}, 10.0, length=11)


def test_nan_deep_in_a_float_hdf5_names_its_sample(tmp_path):
    n, bad = 3_000_000, 2_345_678
    blocks = (np.where(np.arange(a, a + 2**20) == bad, np.nan, 0.5).astype(np.float32)[: n - a]
              for a in range(0, n, 2**20))
    write_hdf5(tmp_path / "long.h5", {"ch": blocks}, 1e6)
    ch = open_channel(tmp_path / "long.h5", field=FIELD)
    chunks = ch.chunks(size=2**20)
    assert len(next(chunks)) == 2**20 and len(next(chunks)) == 2**20
    with pytest.raises(InputError, match=rf"sample {bad} \(t = 2.34568 s\) is nan") as err:
        next(chunks)
    assert str(tmp_path / "long.h5") in str(err.value) and f"field '{FIELD}'" in str(err.value)
    assert "Fix:" in str(err.value)
    assert len(list(ch.chunks(size=2**20, stop=bad))) == 3
    with pytest.raises(InputError, match=f"sample {bad}"):
        ch.read()


def test_channels_pickle_for_a_process_pool(tmp_path):
    x = rng.integers(-100, 100, size=50).astype(np.int16)
    write_wav(tmp_path / "rec.wav", x, 8000)
    write_hdf5(tmp_path / "rec.h5", {"x": x}, 8000.0)
    write_csv(tmp_path / "rec.csv", {"x": x}, sample_rate=8000.0)
    for name in ("rec.wav", "rec.h5", "rec.csv"):
        ch = pickle.loads(pickle.dumps(open_channel(tmp_path / name)))
        np.testing.assert_array_equal(ch.read(), x, err_msg=name)


# ---- CSV time base ----

def test_csv_time_column_with_unit_semicolons_and_decimal_commas(tmp_path):
    path = tmp_path / "rec.csv"
    path.write_text("# scope export\nt, ms;U1;U2\n0,0;1,5;7\n0,5;2,5;8\n\n1,0;3,5;9\n1,5;4,5;10\n",
                    encoding="utf-8")
    ch = open_channel(path, channel="U1", sample_rate=2000.0)
    assert ch.sample_rate == pytest.approx(2000.0, rel=1e-12)
    np.testing.assert_allclose(ch.read(), [1.5, 2.5, 3.5, 4.5])


def test_csv_whitespace_table_without_header_needs_a_rate(tmp_path):
    path = tmp_path / "rec.txt"
    path.write_text("  0.1 \n 0.2\n0.3\n", encoding="utf-8")
    with pytest.raises(InputError, match="one column and no sample rate.*Fix: add a time column"):
        open_channel(path, field=FIELD)
    ch = open_channel(path, sample_rate=100)
    assert (ch.name, ch.sample_rate) == ("column 0", 100.0)
    np.testing.assert_array_equal(ch.read(), [0.1, 0.2, 0.3])


def test_csv_time_column_with_a_gap_is_refused(tmp_path):
    path = tmp_path / "rec.csv"
    write_csv(path, {"t": np.r_[0:4, 5:9] * 1e-3, "x": np.arange(8.0)})
    with pytest.raises(InputError, match="not uniformly sampled at row 6"):
        open_channel(path)


def test_csv_time_column_must_rise(tmp_path):
    path = tmp_path / "rec.csv"
    path.write_text("time_s,x\n0,1\n1,2\n1,3\n", encoding="utf-8")
    with pytest.raises(InputError, match="not strictly increasing at row 4"):
        open_channel(path)


# ---- errors name the file, the field and the fix ----

def _write(path, text):
    path.write_text(text, encoding="utf-8")
    return path


@pytest.mark.parametrize("name, make, kwargs, problem", [
    ("empty.csv", lambda p: _write(p, ""), {}, "the file is empty"),
    ("blank.csv", lambda p: _write(p, "\n# nothing\n"), {}, "no data"),
    ("header.csv", lambda p: _write(p, "t,x\n"), {}, "only a header row"),
    ("nan.csv", lambda p: _write(p, "t,x\n0,1\n1,\n2,3\n"), {}, "row 3, column 'x' is empty"),
    ("nan2.csv", lambda p: _write(p, "t,x\n0,1\n1,nan\n"), {}, "row 3, column 'x' is empty"),
    ("text.csv", lambda p: _write(p, "t,x\n0,1\n1,2 V\n"), {}, "row 3, column 'x': '2 V' is not"),
    ("cols.csv", lambda p: _write(p, "t,tooth,tdc\n0,1,2\n1,1,2\n"), {"channel": "toth"},
     "no column 'toth'.*did you mean 'tooth'"),
    ("only_t.csv", lambda p: _write(p, "t\n0\n1\n"), {}, "only a time column"),
    ("ragged.csv", lambda p: _write(p, "t,x\n0,1\n1,2,3\n"), {}, "not a regular table"),
    ("rec.mp3", lambda p: _write(p, "ID3"), {}, r"unknown file type '\.mp3'"),
    ("missing.wav", lambda p: p, {}, "file not found"),
    ("bad.wav", lambda p: _write(p, "RIFF not really"), {}, "not a readable WAV file"),
    ("bad.h5", lambda p: _write(p, "not hdf5"), {}, "not a readable HDF5 file"),
    ("rate.csv", lambda p: _write(p, "x\n1\n2\n"), {"sample_rate": -5}, "positive number of Hz"),
])
def test_bad_input_names_file_field_and_fix(tmp_path, name, make, kwargs, problem):
    path = make(tmp_path / name)
    with pytest.raises(InputError, match=problem) as err:
        open_channel(path, field=FIELD, **kwargs)
    text = str(err.value)
    assert text.startswith(f"{tmp_path / name}, field '{FIELD}': ") and "Fix: " in text, text


def test_wav_rate_disagreeing_with_the_given_one(tmp_path):
    write_wav(tmp_path / "rec.wav", np.zeros(10, np.int16), 44100)
    with pytest.raises(InputError, match="sample rate is 44100 Hz but sample_rate = 48000 Hz"):
        open_channel(tmp_path / "rec.wav", sample_rate=48000)
    assert open_channel(tmp_path / "rec.wav", sample_rate=44100).sample_rate == 44100.0


def test_wav_channel_out_of_range(tmp_path):
    write_wav(tmp_path / "rec.wav", np.zeros(10, np.int16), 8000)
    with pytest.raises(InputError, match="no channel 1: the file has 1"):
        open_channel(tmp_path / "rec.wav", channel="right")


def test_hdf5_channel_must_be_named_when_several(tmp_path):
    write_hdf5(tmp_path / "rec.h5", {"tooth": np.zeros(5), "tdc": np.zeros(5)}, 1e3)
    with pytest.raises(InputError, match=r"2 one-dimensional datasets.*'tooth' \(5,\)"):
        open_channel(tmp_path / "rec.h5")
    with pytest.raises(InputError, match="did you mean 'tooth'"):
        open_channel(tmp_path / "rec.h5", channel="Toth")


def test_hdf5_sample_rate_from_file_attribute_or_argument(tmp_path):
    with h5py.File(tmp_path / "rec.h5", "w") as f:
        f["x"] = np.arange(5, dtype=np.int16)
    with pytest.raises(InputError, match="no sample rate for dataset 'x'"):
        open_channel(tmp_path / "rec.h5")
    assert open_channel(tmp_path / "rec.h5", sample_rate=250).sample_rate == 250.0
    with h5py.File(tmp_path / "rec.h5", "a") as f:
        f.attrs["fs"] = 500
    ch = open_channel(tmp_path / "rec.h5")
    assert (ch.sample_rate, ch.volts_per_code) == (500.0, 1.0)


def test_channels_of_one_file_must_be_simultaneous(tmp_path):
    with h5py.File(tmp_path / "rec.h5", "w") as f:
        f["a"], f["b"] = np.zeros(5), np.zeros(5)
        f["a"].attrs["sample_rate"], f["b"].attrs["sample_rate"] = 1000.0, 2000.0
    with pytest.raises(InputError, match="were not recorded together"):
        open_channels(tmp_path / "rec.h5", ["a", "b"])


def test_chunk_arguments_are_checked(tmp_path):
    write_wav(tmp_path / "rec.wav", np.zeros(10, np.int16), 8000)
    ch = open_channel(tmp_path / "rec.wav")
    with pytest.raises(ValueError, match="size must be"):
        ch.chunks(0)
    with pytest.raises(ValueError, match="stop=11"):
        ch.chunks(start=2, stop=11)


def test_writers_refuse_what_they_cannot_store(tmp_path):
    with pytest.raises(ValueError, match="integer codes"):
        write_wav(tmp_path / "a.wav", np.zeros(4), 8000)
    with pytest.raises(ValueError, match="exceed int16"):
        write_wav(tmp_path / "a.wav", np.array([0, 40000]), 8000)
    with pytest.raises(ValueError, match="whole number"):
        write_wav(tmp_path / "a.wav", np.zeros(4, np.int16), 8000.5)
    with pytest.raises(ValueError, match="column 't' and a sample_rate"):
        write_csv(tmp_path / "a.csv", {"t": np.zeros(3)}, sample_rate=10)


# ---- counter edge times ----

def test_edge_times_in_seconds_from_one_column_or_a_named_one(tmp_path):
    edges = np.cumsum(rng.uniform(1e-4, 2e-4, size=50))
    write_csv(tmp_path / "one.csv", {"edge": edges})
    times = read_edge_times(tmp_path / "one.csv", field=FIELD)
    assert times.dtype == np.float64
    np.testing.assert_array_equal(times, edges)
    write_csv(tmp_path / "two.csv", {"t_ms": edges * 1e3, "level": np.ones(50)})
    np.testing.assert_allclose(read_edge_times(tmp_path / "two.csv"), edges, rtol=1e-12)
    write_csv(tmp_path / "named.csv", {"level": np.ones(50), "edge": edges})
    np.testing.assert_array_equal(read_edge_times(tmp_path / "named.csv", column="edge"), edges)
    np.testing.assert_array_equal(read_edge_times(tmp_path / "named.csv", column=1), edges)


@pytest.mark.parametrize("text, problem", [
    ("0.1\n0.2\n0.2\n0.3\n", "not strictly increasing at row 3"),
    ("t\n0.1\n0.05\n0.3\n", "not strictly increasing at row 3"),
    ("0.1\n0.2\n", "only 2 edge time"),
    ("0.1\ninf\n0.3\n", "row 2, column 'column 0' is inf"),
    ("a,b\n1,2\n3,4\n5,6\n", "2 columns and none named t"),
])
def test_edge_times_are_checked(tmp_path, text, problem):
    path = _write(tmp_path / "edges.txt", text)
    with pytest.raises(InputError, match=problem) as err:
        read_edge_times(path, field=FIELD)
    assert f"field '{FIELD}'" in str(err.value) and "Fix:" in str(err.value)


def test_edge_times_only_from_tables(tmp_path):
    write_wav(tmp_path / "rec.wav", np.zeros(10, np.int16), 8000)
    with pytest.raises(InputError, match=r"unknown file type '\.wav'.*Fix: give a \.csv"):
        read_edge_times(tmp_path / "rec.wav")


def _sine_table(header: str, t_scale: float, u_scale: float, sep: str = ",") -> str:
    t = np.arange(500) / 5000.0
    u = np.sin(2 * np.pi * 50 * t)
    return header + "\n" + "".join(f"{a * t_scale:.4f}{sep}{b * u_scale:.6f}\n"
                                   for a, b in zip(t, u))


@pytest.mark.parametrize("header, u_scale", [
    ('"t, ms","U, mV"', 1e3), ("t_ms,u_мВ", 1e3), ('"t, ms","u [µV]"', 1e6), ("t_ms,U", 1.0),
    ('"t, мс","Напряжение, В"', 1.0),
])
def test_a_channel_whose_header_names_millivolts_is_read_in_volts(tmp_path, header, u_scale):
    path = tmp_path / "decay.csv"
    path.write_text(_sine_table(header, 1e3, u_scale), encoding="utf-8")
    channel = open_channel(path, field="decay.signal")
    assert channel.sample_rate == pytest.approx(5000.0, rel=1e-9)
    assert channel.read().max() == pytest.approx(1.0, abs=2e-6)


def test_a_comma_inside_an_unquoted_name_is_refused_not_read_as_another_column(tmp_path):
    """'t, ms,U, mV' names four columns of a two-column table: read as it stands, the time
    would be taken in seconds (a rate of 5 Hz) and the volts from the millivolts."""
    path = tmp_path / "decay.csv"
    path.write_text(_sine_table("t, ms,U, mV", 1e3, 1e3), encoding="utf-8")
    with pytest.raises(InputError, match=r"names 4 columns .* row 2 holds 2 cells: a ',' inside"):
        open_channel(path, field="decay.signal")
