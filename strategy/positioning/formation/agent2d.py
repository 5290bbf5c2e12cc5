"""Import agent2d/HELIOS (librcsc) Delaunay formation files into a ``Formation``.

Three on-disk forms are read, detected from the text:

- JSON (today's librcsc): ``{"method": "DelaunayTriangulation", "role": [{"number", "name",
  "type", "pair"}...], "data": [{"index", "ball": {"x", "y"}, "1": {"x", "y"}, ... "11": ...}]}``;
- CSV (librcsc 2021): lines ``Method,DelaunayTriangulation``, ``RoleNumber,...``,
  ``RoleName,...``, ``RoleType,...``, ``SymmetryNumber,...`` (``Marker``/``SetplayMarker``
  ignored), ``SampleData``, optional ``Size,N``, a header ``idx,ballX,ballY,1X,1Y,...`` and one
  row per sample;
- legacy text: ``Formation DelaunayTriangulation 2`` (or ``3``), ``Begin Roles`` ... ``End
  Roles`` (v2 rows ``unum name pair``; v3 rows ``unum type name pair marker setplay_marker``),
  ``Begin Samples <version> <count>``, then per sample ``----- i -----``, ``Ball x y`` and 11 rows
  ``unum x y``. The oldest form (``Formation DelaunayTriangulation`` with no version, a role line
  of ``name pair`` pairs, then one line of 24 numbers per sample) is read too.

Two methods are read: ``DelaunayTriangulation`` (positions interpolated between ball samples)
and ``Static`` (one set of positions, whatever the ball does: agent2d uses it for
``before-kick-off.conf`` and the other set-up formations). A static formation is read in each
form: JSON with ``"method": "Static"`` and one ``data`` entry; CSV ``Method,Static`` with
``RoleNumber``/``RoleName`` rows and one ``Position,1X,1Y,...,11X,11Y`` row; legacy
``Formation Static`` followed by 11 rows ``unum name x y``. It becomes a ``Formation`` with a
single sample (ball at the centre spot), which holds its home positions for every ball.

agent2d works on a 105 x 68 m pitch (rcssserver) with its own team attacking +x, like our team
frame, but its y axis points to the *right* of the attacking direction (rcssserver's screen
axes): the importer negates y by default (``flip_y=True``) so agent2d's "left" roles (pair -1,
negative y) stay on the left in our right-handed frame. Coordinates are then scaled from
105 x 68 m to the target pitch (x by the length ratio, y by the width ratio). Other methods
(agent2d's older ``CDT``, ``KNN``, ...) are refused with an error naming the method.

Role types are librcsc's ``RoleType`` as its writers spell it: ``G``, ``DF``, ``MF``, ``FW`` and
``Unknown`` (HELIOS's ``Static`` files, e.g. ``before-kick-off.conf``, give every role
``Unknown``), in every form. Roles without a type (v1, v2, a CSV file without a ``RoleType``
row) or of type ``Unknown`` get one from the uniform number (1 is the goalie) and the name
(``*Back``/``Sweeper`` DF, ``*Forward``/``*Wing``/``Striker`` FW, otherwise MF). librcsc's own
CSV and v3 readers also take any other word as ``Unknown``; this importer refuses it with an
error naming the word, as a misspelt type is more likely a mistake than a wish.
"""

from __future__ import annotations

import json
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from strategy.positioning.formation.model import Formation, FormationError, Role
from teamenv.errors import value_repr
from teamenv.field import FieldSpec
from teamenv.input_files import read_text

AGENT2D_PITCH_M: tuple[float, float] = (105.0, 68.0)
"""Length and width (metres) of the pitch agent2d formation files are written for."""

AGENT2D_METHOD = "DelaunayTriangulation"
AGENT2D_STATIC_METHOD = "Static"
AGENT2D_METHODS: tuple[str, ...] = (AGENT2D_METHOD, AGENT2D_STATIC_METHOD)
"""The agent2d formation methods ``import_agent2d`` reads."""
AGENT2D_UNKNOWN_TYPE = "Unknown"
AGENT2D_ROLE_TYPES: tuple[str, ...] = ("G", "DF", "MF", "FW", AGENT2D_UNKNOWN_TYPE)
"""The role types read, as librcsc writes its ``RoleType`` (Goalie, Defender, MidFielder,
Forward, Unknown); an ``Unknown`` role gets its type from the uniform number and name."""
_N = 11
# A static formation's positions do not depend on the ball; its one sample puts the ball here.
_STATIC_BALL = [0.0, 0.0]


def import_agent2d(
    source: str | Path,
    *,
    field: str | FieldSpec | tuple[float, float] = "simspark",
    flip_y: bool = True,
    select: Sequence[int] | None = None,
    name: str | None = None,
) -> Formation:
    """Read an agent2d/HELIOS formation (file path, or the file's text) as a ``Formation``.

    A ``DelaunayTriangulation`` file gives a formation whose home positions follow the ball; a
    ``Static`` one (e.g. agent2d's ``before-kick-off.conf``) a single-sample formation whose
    home positions are the same for every ball.

    Args:
        source: a path to a ``.conf``/``.json`` formation file, or its text.
        field: the target pitch (preset name, ``FieldSpec`` or (length, width) in metres);
            coordinates are scaled from agent2d's 105 x 68 m to it.
        flip_y: negate y (agent2d's y points right of the attack; ours points left).
        select: uniform numbers (1..11) to keep, in order, e.g. ``[1, 2, 3, 6, 7, 10, 11]`` for a
            7-a-side team (the first should be 1, the goalie). Default: all 11.
        name: the formation's name (default: the file's stem, or "agent2d").

    Raises:
        FormationError: the text is not one of the three forms, or the data is not valid
            (message names the file, the line or field, and the value).
    """
    text, label, stem = _read_source(source)
    src = f"agent2d formation {label}"
    stripped = text.lstrip()
    if stripped.startswith("{"):
        names, types, ball, players = _parse_json(text, src)
    else:
        first = _first_value_line(text)
        if first is None:
            raise FormationError(f"{src}: empty file")
        if re.match(r"\s*Method\s*,", first):
            names, types, ball, players = _parse_csv(text, src)
        elif re.match(r"\s*Formation\s+", first):
            names, types, ball, players = _parse_legacy(text, src)
        else:
            raise FormationError(
                f"{src}: unknown format: the first line {first.strip()!r} starts none of "
                f"JSON '{{', CSV 'Method,', legacy 'Formation '"
            )
    types = [t if t is not None else _infer_type(i, n) for i, (n, t) in enumerate(zip(names, types, strict=True))]
    roles = [Role(name=n, type=t) for n, t in zip(names, types, strict=True)]
    ball_arr = np.asarray(ball, dtype=np.float64)
    pos_arr = np.asarray(players, dtype=np.float64)
    if select is not None:
        idx = []
        for u in select:
            if not isinstance(u, (int, np.integer)) or not 1 <= int(u) <= _N:
                raise FormationError(f"{src}: select: uniform number {u!r} is not in 1..11")
            idx.append(int(u) - 1)
        if len(set(idx)) != len(idx) or not idx:
            raise FormationError(f"{src}: select: {list(select)!r} must be distinct and non-empty")
        roles = [roles[i] for i in idx]
        pos_arr = pos_arr[:, idx]
    try:
        formation = Formation(
            roles, ball_arr, pos_arr, field=AGENT2D_PITCH_M,
            name=name if name is not None else stem,
            description=f"imported from agent2d formation {label}",
        )
    except FormationError as exc:
        raise FormationError(f"{src}: {exc}") from None
    if flip_y:
        formation = formation.mirrored(flip_x=False, flip_y=True)
    return formation.scaled_to(field)


# ---------------------------------------------------------------------------------- helpers
_Parsed = tuple[list[str], list[str | None], list[list[float]], list[list[list[float]]]]


def _read_source(source: str | Path) -> tuple[str, str, str]:
    if isinstance(source, Path) or ("\n" not in str(source) and len(str(source)) < 4096
                                    and not str(source).lstrip().startswith("{")):
        p = Path(source)
        return read_text(p, f"agent2d formation {p}", FormationError), str(p), p.stem
    return str(source), "<text>", "agent2d"


def _is_comment(line: str) -> bool:
    s = line.strip()
    return not s or s.startswith("#") or s.startswith("//")


def _first_value_line(text: str) -> str | None:
    for line in text.splitlines():
        if not _is_comment(line):
            return line
    return None


def _float(token: str, where: str, src: str) -> float:
    try:
        v = float(token)
    except ValueError:
        raise FormationError(f"{src}: {where}: {token!r} is not a number") from None
    if not np.isfinite(v):
        raise FormationError(f"{src}: {where}: {token!r} is not finite")
    return v


def _check_method(method: Any, src: str) -> str:
    if method not in AGENT2D_METHODS:
        raise FormationError(
            f"{src}: method {method!r} is not supported; only {' and '.join(map(repr, AGENT2D_METHODS))} "
            f"can be imported"
        )
    return method


def _infer_type(index: int, name: str) -> str:
    if index == 0:
        return "G"
    if re.search(r"Back|Sweeper|Stopper|Defender", name):
        return "DF"
    if re.search(r"Forward|Wing|Striker|Attacker", name):
        return "FW"
    return "MF"


def _check_type(t: Any, where: str, src: str) -> str | None:
    """A role type as written in the file: G, DF, MF, FW, or Unknown (None: inferred later)."""
    if t == AGENT2D_UNKNOWN_TYPE:
        return None
    if t not in ("G", "DF", "MF", "FW"):
        raise FormationError(f"{src}: {where}: role type {value_repr(t)} is not one of "
                             f"{', '.join(AGENT2D_ROLE_TYPES)}")
    return t


# ------------------------------------------------------------------------------------ JSON
def _parse_json(text: str, src: str) -> _Parsed:
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as exc:
        raise FormationError(
            f"{src}: not valid JSON (line {exc.lineno}, column {exc.colno}): {exc.msg}"
        ) from None
    except (ValueError, RecursionError) as exc:  # e.g. an integer of over 4300 digits
        raise FormationError(f"{src}: not readable JSON: {exc}") from None
    if not isinstance(doc, dict):
        raise FormationError(f"{src}: the top level must be a JSON object")
    for key in ("method", "role", "data"):
        if key not in doc:
            raise FormationError(f"{src}: missing key {key!r}")
    method = _check_method(doc["method"], src)
    role_list = doc["role"]
    if not isinstance(role_list, list):
        raise FormationError(f"{src}: role must be a list, got {role_list!r}")
    by_number: dict[int, tuple[str, str]] = {}
    for i, r in enumerate(role_list):
        if not isinstance(r, dict) or not all(k in r for k in ("number", "name", "type")):
            raise FormationError(f"{src}: role[{i}] needs number, name and type, got {r!r}")
        num = r["number"]
        if not isinstance(num, int) or not 1 <= num <= _N or num in by_number:
            raise FormationError(f"{src}: role[{i}].number = {num!r} is not a new number in 1..11")
        by_number[num] = (str(r["name"]), _check_type(r["type"], f"role[{i}].type", src))
    if len(by_number) != _N:
        missing = sorted(set(range(1, _N + 1)) - set(by_number))
        raise FormationError(f"{src}: role: uniform numbers {missing} have no role")
    names = [by_number[u][0] for u in range(1, _N + 1)]
    types: list[str | None] = [by_number[u][1] for u in range(1, _N + 1)]
    data = doc["data"]
    if not isinstance(data, list) or not data:
        raise FormationError(f"{src}: data must be a non-empty list")
    if method == AGENT2D_STATIC_METHOD and len(data) != 1:
        raise FormationError(
            f"{src}: a {AGENT2D_STATIC_METHOD!r} formation has one set of positions, but data has "
            f"{len(data)} entries"
        )
    ball, players = [], []
    for i, d in enumerate(data):
        if not isinstance(d, dict):
            raise FormationError(f"{src}: data[{i}] must be an object, got {d!r}")
        ball.append(_STATIC_BALL if method == AGENT2D_STATIC_METHOD and "ball" not in d
                    else _json_xy(d, "ball", i, src))
        players.append([_json_xy(d, str(u), i, src) for u in range(1, _N + 1)])
    return names, types, ball, players


def _json_xy(d: dict[str, Any], key: str, i: int, src: str) -> list[float]:
    v = d.get(key)
    if not isinstance(v, dict) or "x" not in v or "y" not in v:
        raise FormationError(f"{src}: data[{i}].{key} must be {{'x': ..., 'y': ...}}, got {v!r}")
    out = []
    for k in ("x", "y"):
        val = v[k]
        if isinstance(val, bool) or not isinstance(val, (int, float)) or not np.isfinite(val):
            raise FormationError(f"{src}: data[{i}].{key}.{k} = {val!r} is not a finite number")
        out.append(float(val))
    return out


# ------------------------------------------------------------------------------------- CSV
_CSV_IGNORED = {"Marker", "SetplayMarker"}


def _parse_csv(text: str, src: str) -> _Parsed:
    rows: dict[str, list[str]] = {}
    lines = [(n + 1, ln) for n, ln in enumerate(text.splitlines()) if not _is_comment(ln)]
    method = _check_method(lines[0][1].split(",", 1)[1].strip(), src)
    if method == AGENT2D_STATIC_METHOD:
        return _parse_csv_static(lines, src)
    k = 0
    while k < len(lines):
        lineno, line = lines[k]
        cells = [c.strip() for c in line.split(",")]
        key = cells[0]
        if key == "SampleData":
            k += 1
            break
        if key not in ("Method", "RoleNumber", "RoleName", "RoleType", "SymmetryNumber") \
                and key not in _CSV_IGNORED:
            raise FormationError(f"{src}: line {lineno}: unknown row {key!r}")
        rows[key] = cells[1:]
        k += 1
    else:
        raise FormationError(f"{src}: no 'SampleData' line")
    names, types = _csv_roles(rows, src)
    size: int | None = None
    if k < len(lines) and lines[k][1].replace(" ", "").startswith("Size,"):
        lineno, line = lines[k]
        try:
            size = int(line.split(",")[1])
        except (IndexError, ValueError):
            raise FormationError(f"{src}: line {lineno}: bad sample count {line.strip()!r}") from None
        k += 1
    if k >= len(lines) or not lines[k][1].strip().startswith("idx"):
        raise FormationError(f"{src}: the sample header line 'idx,ballX,ballY,...' is missing")
    k += 1
    ball, players = [], []
    for lineno, line in lines[k:]:
        cells = [c.strip() for c in line.split(",")]
        if len(cells) != 3 + 2 * _N:
            raise FormationError(
                f"{src}: line {lineno}: a sample row has {len(cells)} values, expected "
                f"{3 + 2 * _N} (idx, ball x, y, 11 players x, y)"
            )
        vals = [_float(c, f"line {lineno}", src) for c in cells[1:]]
        ball.append(vals[:2])
        players.append([vals[2 + 2 * j: 4 + 2 * j] for j in range(_N)])
    if size is not None and size != len(ball):
        raise FormationError(f"{src}: Size says {size} samples but {len(ball)} rows follow")
    if not ball:
        raise FormationError(f"{src}: no sample rows after the header")
    return names, types, ball, players


def _csv_roles(rows: dict[str, list[str]], src: str) -> tuple[list[str], list[str | None]]:
    """Role names and types (None where the file gives none) from the CSV role rows."""
    for key in ("RoleNumber", "RoleName"):
        if key not in rows:
            raise FormationError(f"{src}: missing row {key!r}")
    numbers = rows["RoleNumber"]
    if numbers != [str(u) for u in range(1, _N + 1)]:
        raise FormationError(f"{src}: RoleNumber must be 1..11 in order, got {numbers!r}")
    names = rows["RoleName"]
    if len(names) != _N:
        raise FormationError(f"{src}: RoleName has {len(names)} names, expected 11")
    types: list[str | None] = [None] * _N
    if "RoleType" in rows:
        if len(rows["RoleType"]) != _N:
            raise FormationError(f"{src}: RoleType has {len(rows['RoleType'])} types, expected 11")
        types = [_check_type(t, f"RoleType[{i}]", src) for i, t in enumerate(rows["RoleType"])]
    return names, types


def _parse_csv_static(lines: list[tuple[int, str]], src: str) -> _Parsed:
    """``Method,Static``: role rows and one ``Position,1X,1Y,...,11X,11Y`` row."""
    rows: dict[str, list[str]] = {}
    position_line = 0
    for lineno, line in lines[1:]:
        cells = [c.strip() for c in line.split(",")]
        key = cells[0]
        if key not in ("RoleNumber", "RoleName", "RoleType", "SymmetryNumber", "Position") \
                and key not in _CSV_IGNORED:
            raise FormationError(f"{src}: line {lineno}: unknown row {key!r} in a Static formation")
        if key in rows:
            raise FormationError(f"{src}: line {lineno}: a second {key!r} row")
        rows[key] = cells[1:]
        if key == "Position":
            position_line = lineno
    names, types = _csv_roles(rows, src)
    if "Position" not in rows:
        raise FormationError(f"{src}: no 'Position' row (a Static formation's 11 x, y pairs)")
    values = rows["Position"]
    if len(values) != 2 * _N:
        raise FormationError(
            f"{src}: line {position_line}: the Position row has {len(values)} values, expected "
            f"{2 * _N} (11 players x, y)"
        )
    xy = [_float(v, f"line {position_line}", src) for v in values]
    return names, types, [list(_STATIC_BALL)], [[xy[2 * j: 2 * j + 2] for j in range(_N)]]


# ---------------------------------------------------------------------------------- legacy
def _parse_legacy(text: str, src: str) -> _Parsed:
    lines = [(n + 1, ln.strip()) for n, ln in enumerate(text.splitlines()) if not _is_comment(ln)]
    lineno, header = lines[0]
    m = re.fullmatch(r"Formation\s+(\S+)(?:\s+(\d+))?", header)
    if not m:
        raise FormationError(f"{src}: line {lineno}: illegal header {header!r}")
    if _check_method(m.group(1), src) == AGENT2D_STATIC_METHOD:
        if m.group(2):
            raise FormationError(f"{src}: line {lineno}: 'Formation Static' takes no version")
        return _parse_legacy_static(lines[1:], src)
    version = int(m.group(2)) if m.group(2) else 1
    if version == 1:
        return _parse_legacy_v1(lines[1:], src)
    if version not in (2, 3):
        raise FormationError(f"{src}: line {lineno}: format version {version} is not 1, 2 or 3")
    it = iter(lines[1:])

    def take(what: str) -> tuple[int, str]:
        try:
            return next(it)
        except StopIteration:
            raise FormationError(f"{src}: unexpected end of file, expected {what}") from None

    lineno, line = take("'Begin Roles'")
    if line != "Begin Roles":
        raise FormationError(f"{src}: line {lineno}: expected 'Begin Roles', got {line!r}")
    names: list[str] = []
    types: list[str | None] = []
    for unum in range(1, _N + 1):
        lineno, line = take(f"the role of uniform number {unum}")
        tok = line.split()
        ok = len(tok) >= (4 if version == 3 else 3) and tok[0] == str(unum)
        if not ok:
            raise FormationError(
                f"{src}: line {lineno}: expected the role of uniform number {unum} "
                f"({'unum type name pair ...' if version == 3 else 'unum name pair'}), got {line!r}"
            )
        if version == 3:
            types.append(_check_type(tok[1], f"line {lineno}", src))
            names.append(tok[2])
        else:
            types.append(None)
            names.append(tok[1])
    lineno, line = take("'End Roles'")
    if line != "End Roles":
        raise FormationError(f"{src}: line {lineno}: expected 'End Roles', got {line!r}")
    lineno, line = take("'Begin Samples'")
    m = re.fullmatch(r"Begin Samples\s+(\d+)\s+(\d+)", line)
    if not m:
        raise FormationError(f"{src}: line {lineno}: expected 'Begin Samples <ver> <n>', got {line!r}")
    count = int(m.group(2))
    ball, players = [], []
    for i in range(count):
        lineno, line = take(f"sample {i}")
        if not re.fullmatch(rf"-+\s*{i}\s*-+", line):
            raise FormationError(f"{src}: line {lineno}: expected '----- {i} -----', got {line!r}")
        lineno, line = take(f"the ball of sample {i}")
        tok = line.split()
        if len(tok) != 3 or tok[0] != "Ball":
            raise FormationError(f"{src}: line {lineno}: expected 'Ball x y', got {line!r}")
        ball.append([_float(t, f"line {lineno}", src) for t in tok[1:]])
        ps = []
        for unum in range(1, _N + 1):
            lineno, line = take(f"player {unum} of sample {i}")
            tok = line.split()
            if len(tok) != 3 or tok[0] != str(unum):
                raise FormationError(f"{src}: line {lineno}: expected '{unum} x y', got {line!r}")
            ps.append([_float(t, f"line {lineno}", src) for t in tok[1:]])
        players.append(ps)
    return names, types, ball, players


def _parse_legacy_static(lines: list[tuple[int, str]], src: str) -> _Parsed:
    """``Formation Static`` then 11 rows ``unum name x y`` (uniform numbers 1..11 in order)."""
    rows = [(n, ln) for n, ln in lines if ln != "End"]
    if len(rows) != _N:
        raise FormationError(
            f"{src}: a 'Formation Static' file needs 11 rows 'unum name x y', got {len(rows)}"
        )
    names: list[str] = []
    positions: list[list[float]] = []
    for unum, (lineno, line) in enumerate(rows, start=1):
        tok = line.split()
        if len(tok) != 4 or tok[0] != str(unum):
            raise FormationError(
                f"{src}: line {lineno}: expected '{unum} name x y', got {line!r}"
            )
        names.append(tok[1])
        positions.append([_float(v, f"line {lineno}", src) for v in tok[2:]])
    return names, [None] * _N, [list(_STATIC_BALL)], [positions]


def _parse_legacy_v1(lines: list[tuple[int, str]], src: str) -> _Parsed:
    if not lines:
        raise FormationError(f"{src}: no role line after the header")
    lineno, line = lines[0]
    tok = line.split()
    if len(tok) != 2 * _N:
        raise FormationError(
            f"{src}: line {lineno}: the role line needs 11 'name pair' pairs, got {len(tok)} tokens"
        )
    names = tok[0::2]
    ball, players = [], []
    for lineno, line in lines[1:]:
        if line == "End":
            break
        vals = [_float(t, f"line {lineno}", src) for t in line.split()]
        if len(vals) != 2 + 2 * _N:
            raise FormationError(
                f"{src}: line {lineno}: a sample line has {len(vals)} numbers, expected 24"
            )
        ball.append(vals[:2])
        players.append([vals[2 + 2 * j: 4 + 2 * j] for j in range(_N)])
    if not ball:
        raise FormationError(f"{src}: no samples")
    return names, [None] * _N, ball, players
