"""An image file's pixel size read off its header, before anything decodes it.

A decoder allocates the whole picture as its header states it: a 0.5 MB PNG or a 1 kB JPEG
whose header claims 20 000 × 20 000 px asks for 1.2 GB before a row of it is read. So the
paper-record reader (:func:`processing.vision.paper.load_image`) reads the header first —
the few bytes that state the size — and refuses a picture too large to read
(:data:`processing.vision.paper.MAX_PIXELS`) before decoding it.

:func:`image_header` knows the formats a record is photographed or scanned in, by their
first bytes (not the file's extension), and where each states its size:

* PNG: the IHDR chunk, first after the signature (width, height: 4 bytes each, big-endian);
* JPEG: the first SOFn segment (baseline, progressive, lossless, arithmetic) after the
  application segments (EXIF, ICC profile, ...), each skipped by its length;
* TIFF and BigTIFF: tags 256 (ImageWidth) and 257 (ImageLength) of the first IFD (the page
  a decoder reads), SHORT, LONG or LONG8, in the file's byte order;
* BMP: the DIB header after the 14-byte file header (BITMAPCOREHEADER: 16-bit sizes; the
  later ones: 32-bit, the height negative for a top-down bitmap).

References
----------
.. [1] ISO/IEC 15948:2004 (PNG), section 11.2.2, IHDR.
.. [2] ITU-T T.81 (1992) (JPEG), annex B.2: marker segments, B.2.2 the frame header.
.. [3] Adobe, TIFF revision 6.0 (1992), section 2 (the IFD) and section 8 (baseline tags);
       BigTIFF: the LibTIFF design note, https://libtiff.gitlab.io/libtiff/specification/bigtiff.html
.. [4] Microsoft, "Bitmap storage" (BITMAPFILEHEADER, BITMAPINFOHEADER), Win32 GDI docs.
"""
from __future__ import annotations

import struct
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from ..diagnostics import Reason

FORMATS = "PNG, JPEG, TIFF or BMP"
"""The formats :func:`image_header` reads (those a record is photographed or scanned in)."""

MAX_SEGMENTS = 4096
"""Most JPEG marker segments passed over before the frame header (a real file has a dozen)."""

MAX_TIFF_TAGS = 65535
"""Most entries a TIFF directory may claim (a classic TIFF's limit; a real one has ~20)."""

_PNG = b"\x89PNG\r\n\x1a\n"
_JPEG_SOF = frozenset(range(0xC0, 0xD0)) - {0xC4, 0xC8, 0xCC}
"""SOF0–SOF15 less DHT (C4), JPG (C8) and DAC (CC), which share the range."""
_TIFF_TYPES = {3: ("H", 2), 4: ("I", 4), 16: ("Q", 8)}
"""TIFF field types a size may be stored in: SHORT, LONG, LONG8 (format, bytes)."""


class HeaderError(Reason):
    """The file is not an image of a known format, or its header is broken: the reason, and
    in Russian (``ru``)."""


@dataclass(frozen=True)
class Header:
    """What an image's header states.

    Attributes
    ----------
    format : str
        ``"PNG"``, ``"JPEG"``, ``"TIFF"``, ``"BigTIFF"`` or ``"BMP"``.
    field : str
        Where the size is stated (``"IHDR"``, ``"SOF2"``, ``"tags 256/257"``, ...).
    width, height : int
        The picture's size. [px]
    """

    format: str
    field: str
    width: int
    height: int

    @property
    def pixels(self) -> int:
        return self.width * self.height

    def says(self) -> str:
        """``"its JPEG header (SOF0) says 20000 × 20000 px (400 Mpx)"``."""
        return (f"its {self.format} header ({self.field}) says {self.width} × {self.height} px "
                f"({self.pixels / 1e6:.3g} Mpx)")


def image_header(path) -> Header:
    """The format and pixel size an image file's header states, read without decoding.

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    Header

    Raises
    ------
    HeaderError
        The first bytes are none of PNG, JPEG, TIFF, BMP; or the header is cut short or
        states a size of 0.
    OSError
        The file cannot be read.

    Examples
    --------
    >>> import struct, tempfile
    >>> png = tempfile.NamedTemporaryFile(suffix=".png", delete=False)
    >>> _ = png.write(b"\\x89PNG\\r\\n\\x1a\\n" + struct.pack(">I4sII", 13, b"IHDR", 20000, 20000))
    >>> png.close()
    >>> image_header(png.name).says()
    'its PNG header (IHDR) says 20000 × 20000 px (400 Mpx)'
    """
    with Path(path).open("rb") as f:
        start = f.read(8)
        if start.startswith(_PNG):
            header = _png(f)
        elif start.startswith(b"\xff\xd8"):
            header = _jpeg(f)
        elif start[:4] in (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+"):
            header = _tiff(f, start)
        elif start.startswith(b"BM"):
            header = _bmp(f)
        else:
            raise HeaderError(f"its first bytes, {start[:8].hex(' ')}, are not those of a "
                              f"{FORMATS} file", f"его первые байты, {start[:8].hex(' ')}, — не "
                              f"начало файла {FORMATS.replace(' or ', ' или ')}")
    if header.width <= 0 or header.height <= 0:
        raise HeaderError(f"its {header.format} header ({header.field}) states a size of "
                          f"{header.width} × {header.height} px",
                          f"его заголовок {header.format} ({header.field}) указывает размер "
                          f"{header.width} × {header.height} пикс.")
    return header


_PARTS_RU = {"PNG header": "заголовка PNG", "JPEG markers": "маркеров JPEG",
             "JPEG segment": "сегмента JPEG", "JPEG frame header": "заголовка кадра JPEG",
             "BigTIFF header": "заголовка BigTIFF", "TIFF directory": "каталога TIFF",
             "BMP header": "заголовка BMP"}
"""The parts of an image's header a file may end inside, in Russian."""


def _read(f: BinaryIO, n: int, what: str) -> bytes:
    data = f.read(n)
    if len(data) < n:
        raise HeaderError(f"the file ends inside its {what}",
                          f"файл обрывается внутри {_PARTS_RU.get(what, what)}")
    return data


def _png(f: BinaryIO) -> Header:
    f.seek(8)
    length, kind, width, height = struct.unpack(">I4sII", _read(f, 16, "PNG header"))
    if kind != b"IHDR":
        raise HeaderError(f"its first PNG chunk is {kind!r}, not the IHDR header",
                          f"его первый блок PNG — {kind!r}, а не заголовок IHDR")
    return Header("PNG", "IHDR", width, height)


def _jpeg(f: BinaryIO) -> Header:
    f.seek(2)
    for _ in range(MAX_SEGMENTS):
        byte = _read(f, 1, "JPEG markers")
        if byte != b"\xff":
            raise HeaderError(f"a JPEG marker was expected at byte {f.tell() - 1}, "
                              f"found {byte.hex()}", f"на байте {f.tell() - 1} ожидался маркер "
                              f"JPEG, а стоит {byte.hex()}")
        marker = 0xFF
        while marker == 0xFF:                          # fill bytes before a marker
            marker = _read(f, 1, "JPEG markers")[0]
        if marker == 0x01 or 0xD0 <= marker <= 0xD7:  # TEM, RSTn: no length
            continue
        if marker in (0xD9, 0xDA):
            raise HeaderError("its JPEG data starts (SOS) or ends (EOI) before any frame "
                              "header (SOFn) states the picture's size", "данные JPEG "
                              "начинаются (SOS) или кончаются (EOI) раньше, чем заголовок кадра "
                              "(SOFn) указывает размер снимка")
        (length,) = struct.unpack(">H", _read(f, 2, "JPEG segment"))
        if length < 2:
            raise HeaderError(f"a JPEG segment at byte {f.tell() - 4} states a length of "
                              f"{length}", f"сегмент JPEG на байте {f.tell() - 4} указывает "
                              f"длину {length}")
        if marker in _JPEG_SOF:
            _, height, width = struct.unpack(">BHH", _read(f, 5, "JPEG frame header"))
            return Header("JPEG", f"SOF{marker - 0xC0}", width, height)
        f.seek(length - 2, 1)
    raise HeaderError(f"no JPEG frame header (SOFn) in its first {MAX_SEGMENTS} segments",
                      f"в первых {MAX_SEGMENTS} сегментах нет заголовка кадра JPEG (SOFn)")


def _tiff(f: BinaryIO, start: bytes) -> Header:
    order = "<" if start[:2] == b"II" else ">"
    big = start[2:4] in (b"+\x00", b"\x00+")
    if big:
        f.seek(8)
        (offset,) = struct.unpack(order + "Q", _read(f, 8, "BigTIFF header"))
        count_format, entry, value_at = "Q", 20, 12
    else:
        (offset,) = struct.unpack(order + "I", start[4:8])
        count_format, entry, value_at = "H", 12, 8
    f.seek(offset)
    size = struct.calcsize(count_format)
    (count,) = struct.unpack(order + count_format, _read(f, size, "TIFF directory"))
    if count > MAX_TIFF_TAGS:
        raise HeaderError(f"its first TIFF directory claims {count} tags",
                          f"его первый каталог TIFF заявляет {count} тегов")
    entries = _read(f, entry * count, "TIFF directory")
    found = {}
    for k in range(count):
        item = entries[k * entry:(k + 1) * entry]
        tag, kind = struct.unpack(order + "HH", item[:4])
        if tag in (256, 257) and kind in _TIFF_TYPES:
            code, nbytes = _TIFF_TYPES[kind]
            (found[tag],) = struct.unpack(order + code, item[value_at:value_at + nbytes])
    kind = "BigTIFF" if big else "TIFF"
    if set(found) != {256, 257}:
        raise HeaderError(f"its first {kind} directory lacks the ImageWidth (256) or "
                          "ImageLength (257) tag", f"в его первом каталоге {kind} нет тега "
                          "ImageWidth (256) или ImageLength (257)")
    return Header(kind, "tags 256/257", found[256], found[257])


def _bmp(f: BinaryIO) -> Header:
    f.seek(14)
    (size,) = struct.unpack("<I", _read(f, 4, "BMP header"))
    if size == 12:
        width, height = struct.unpack("<HH", _read(f, 4, "BMP header"))
        return Header("BMP", "BITMAPCOREHEADER", width, height)
    width, height = struct.unpack("<ii", _read(f, 8, "BMP header"))
    return Header("BMP", "BITMAPINFOHEADER", width, abs(height))
