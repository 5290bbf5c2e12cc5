"""Reading the files users hand teamenv (replays, policies, formations): text or ``.npz``
arrays, or one clear error naming the file and what is wrong with it.

A damaged file must never surface as a foreign exception from the layers below
(``UnicodeDecodeError``, ``zlib.error``, ``NotImplementedError`` from ``zipfile``, numpy's
``allow_pickle`` advice for a file that is not an archive at all): each reader here turns every
way a file can be unreadable into the caller's error type.
"""

from __future__ import annotations

import io
import math
import struct
import zipfile
import zlib
from collections.abc import Callable
from pathlib import Path

import numpy as np

from teamenv.errors import ConfigError

#: The first bytes of a zip archive (an .npz is one): a local file header, or the end
#: record of an empty archive.
_ZIP_MAGIC = (b"PK\x03\x04", b"PK\x05\x06")
#: What ``zipfile``, ``zlib`` and ``numpy.lib.format`` raise on damaged bytes.
_DAMAGE = (zipfile.BadZipFile, zipfile.LargeZipFile, zlib.error, NotImplementedError,
           RuntimeError, OSError, EOFError, ValueError, KeyError, IndexError, TypeError,
           struct.error, OverflowError, MemoryError, UnicodeDecodeError)
#: The end-of-central-directory record (signature, disk numbers, entries on this disk, total
#: entries, directory size and offset, comment length) and how far back from the end it can be.
_EOCD = struct.Struct("<4s4H2LH")
_EOCD_SEARCH = _EOCD.size + 0xFFFF
#: An array member larger than this (uncompressed) is refused before it is read.
MAX_MEMBER_BYTES = 1 << 32


def read_text(path: str | Path, describe: str,
              error: Callable[[str], Exception] = ConfigError) -> str:
    """The UTF-8 text of ``path``; ``error(f"{describe}: ...")`` if it cannot be read or is
    not UTF-8 (naming the line and column of the first bad byte)."""
    p = Path(path)
    try:
        raw = p.read_bytes()
    except OSError as exc:
        raise error(f"{describe}: cannot be read: {exc.strerror or exc}") from None
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw.count(b"\n", 0, exc.start) + 1
        column = exc.start - (raw.rfind(b"\n", 0, exc.start) + 1) + 1
        raise error(f"{describe}: not UTF-8 text: byte {raw[exc.start]:#04x} at line {line}, "
                    f"column {column} ({exc.reason})") from None


def read_npz(path: str | Path, describe: str,
             error: Callable[[str], Exception] = ConfigError,
             what: str = ".npz file") -> dict[str, np.ndarray]:
    """Every array of the ``.npz`` file ``path``, read in full (each member's CRC-32 checked,
    each array's header checked against the member's size, no Python objects), or
    ``error(f"{describe}: ...")`` saying what is wrong (``what`` names the kind of file)."""
    p = Path(path)
    try:
        with p.open("rb") as fh:
            head = fh.read(4)
    except OSError as exc:
        raise error(f"{describe}: cannot be read: {exc.strerror or exc}") from None
    if head not in _ZIP_MAGIC:
        raise error(f"{describe}: not a {what}: not an .npz archive (a zip of .npy arrays; "
                    f"this file starts with {head!r})")
    arrays: dict[str, np.ndarray] = {}
    try:
        listed = _listed_members(p)
        with zipfile.ZipFile(p) as archive:
            members = archive.infolist()
            # zipfile stops reading the directory where its stated size ends: a damaged size
            # would silently drop the members after it
            if listed is not None and listed != len(members):
                raise _Refused(f"its directory says {listed} members but {len(members)} were "
                               "found")
            for info in members:
                name = info.filename
                if not name.endswith(".npy"):
                    raise _Refused(f"member {name!r} is not an .npy array")
                key = name[:-len(".npy")]
                if key in arrays:
                    raise _Refused(f"two members named {name!r}")
                if info.file_size > MAX_MEMBER_BYTES:
                    raise _Refused(f"member {name!r} says it holds {info.file_size} bytes "
                                   f"(more than {MAX_MEMBER_BYTES})")
                arrays[key] = _parse_npy(archive.read(info), key)
    except _Refused as exc:
        raise error(f"{describe}: not a readable {what}: {exc}") from None
    except _DAMAGE as exc:
        detail = f"{type(exc).__name__}: {exc}" if str(exc) else f"{type(exc).__name__}: " \
            "the data ends early" if isinstance(exc, EOFError) else type(exc).__name__
        raise error(f"{describe}: not a readable {what}: the .npz archive is damaged "
                    f"({detail})") from exc
    return arrays


def _listed_members(path: Path) -> int | None:
    """The member count in the zip's end-of-central-directory record (None: a zip64
    archive, whose count lives elsewhere; zipfile reports a missing record itself)."""
    with path.open("rb") as fh:
        fh.seek(0, 2)
        size = fh.tell()
        fh.seek(max(0, size - _EOCD_SEARCH))
        tail = fh.read()
    at = tail.rfind(b"PK\x05\x06")
    if at < 0 or len(tail) - at < _EOCD.size:
        return None
    total = _EOCD.unpack_from(tail, at)[4]
    return None if total == 0xFFFF else total


class _Refused(Exception):
    """A problem ``read_npz`` names itself (raised inside its damage handler's reach)."""


def _parse_npy(raw: bytes, key: str) -> np.ndarray:
    """One .npy member's array (a copy the caller owns), its header checked first."""
    buf = io.BytesIO(raw)
    version = np.lib.format.read_magic(buf)
    if version == (1, 0):
        shape, fortran, dtype = np.lib.format.read_array_header_1_0(buf)
    elif version == (2, 0):
        shape, fortran, dtype = np.lib.format.read_array_header_2_0(buf)
    else:
        raise _Refused(f"array {key!r} is in .npy format {version}, not 1.0 or 2.0")
    if dtype.hasobject:
        raise _Refused(f"array {key!r} holds Python objects (not read: unsafe)")
    count = math.prod(shape)
    offset = buf.tell()
    if count * dtype.itemsize != len(raw) - offset:
        raise _Refused(f"array {key!r}: its header says shape {shape} of {dtype} "
                       f"({count * dtype.itemsize} bytes) but {len(raw) - offset} bytes follow")
    array = np.frombuffer(raw, dtype=dtype, count=count, offset=offset)
    return array.reshape(shape, order="F" if fortran else "C").copy()
