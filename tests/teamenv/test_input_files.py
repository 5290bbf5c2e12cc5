"""teamenv.input_files: damaged text and .npz files become one clear error naming the file."""

from __future__ import annotations

import io
import struct
import zipfile

import numpy as np
import pytest

from teamenv.errors import ConfigError
from teamenv.input_files import read_npz, read_text


def test_read_text_names_line_and_column_of_a_bad_byte(tmp_path):
    path = tmp_path / "f.json"
    path.write_bytes(b'{\n  "a": "ok",\n  "b": "\xff"\n}\n')
    with pytest.raises(ConfigError, match=r"^thing .*f\.json.*: not UTF-8 text: byte 0xff at "
                                          r"line 3, column 9"):
        read_text(path, f"thing {path}")
    with pytest.raises(ConfigError, match="cannot be read"):
        read_text(tmp_path / "missing.json", "thing missing.json")
    good = tmp_path / "g.txt"
    good.write_text("héllo\n", encoding="utf-8")
    assert read_text(good, "thing") == "héllo\n"


def _npz(path, **arrays):
    with open(path, "wb") as fh:
        np.savez(fh, **arrays)
    return path


def test_read_npz_reads_every_array(tmp_path):
    path = _npz(tmp_path / "a.npz", x=np.arange(6.0).reshape(2, 3), y=np.array(["t"]),
                f=np.asfortranarray(np.arange(6).reshape(2, 3)))
    arrays = read_npz(path, "a")
    np.testing.assert_array_equal(arrays["x"], np.arange(6.0).reshape(2, 3))
    np.testing.assert_array_equal(arrays["f"], np.arange(6).reshape(2, 3))
    assert str(arrays["y"][0]) == "t" and arrays["x"].flags.writeable


def test_dropped_directory_entries_are_refused(tmp_path):
    path = _npz(tmp_path / "a.npz", x=np.zeros(3), y=np.ones(3))
    raw = bytearray(path.read_bytes())
    at = raw.rfind(b"PK\x05\x06")
    struct.pack_into("<H", raw, at + 10, 3)  # the end record's total: 3 members, 2 present
    path.write_bytes(bytes(raw))
    with pytest.raises(ConfigError, match="its directory says 3 members but 2 were found"):
        read_npz(path, f"thing {path}")


def test_an_array_header_that_does_not_fit_its_member_is_refused(tmp_path):
    buf = io.BytesIO()
    np.lib.format.write_array(buf, np.zeros(4))
    raw = buf.getvalue().replace(b"(4,)", b"(9,)")
    path = tmp_path / "bad.npz"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("x.npy", raw)
    with pytest.raises(ConfigError, match=r"array 'x': its header says shape \(9,\) of float64 "
                                          r"\(72 bytes\) but 32 bytes follow"):
        read_npz(path, "bad")


def test_truncated_and_flipped_archives_are_one_error(tmp_path):
    path = _npz(tmp_path / "a.npz", x=np.arange(100.0))
    raw = path.read_bytes()
    cut = tmp_path / "cut.npz"
    cut.write_bytes(raw[:len(raw) // 2])
    with pytest.raises(ConfigError, match=r"cut\.npz.*not a readable \.npz file"):
        read_npz(cut, f"thing {cut}")
    flipped = bytearray(raw)
    flipped[200] ^= 0x10  # inside x's data: the CRC-32 tells
    bad = tmp_path / "flipped.npz"
    bad.write_bytes(bytes(flipped))
    with pytest.raises(ConfigError, match="Bad CRC-32"):
        read_npz(bad, f"thing {bad}")
