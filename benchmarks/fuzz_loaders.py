"""Feed the file loaders corrupted files and count how each one ends.

Kinds: a replay (``teamenv.replay.load_replay``, .npz), a locomotion profile
(``locomotion.load_profile``, JSON), a formation file (``read_formation``, JSON), agent2d
formation files in their JSON, CSV and legacy (v3) forms (``import_agent2d``) and an MLP policy
file (``teamenv.policy_team.load_policy``, .npz). Each corrupted
copy comes from a seeded mutator: bit flips, overwritten bytes, truncation, spliced junk
(random bytes inserted or written over a span), a deleted span, a duplicated span.

Every load ends one of five ways:

- ``foreign``: an exception that is not the loader's own error type (a failure);
- ``unnamed``: the loader's own error, but its message does not name the file (a failure);
- ``error``: the loader's own error naming the file (what should happen);
- ``same``: loaded, and what was loaded equals the original (the bytes changed where the
  loader reads nothing that matters: the zip's timestamps, JSON whitespace, a comment);
- ``changed``: loaded, and what was loaded differs from the original. For a replay this is a
  failure (its checksum must refuse it); for the text formats it is what a checksum-less text
  format cannot see (e.g. a digit of an in-range number, a letter of a free-text field).

    OPENBLAS_NUM_THREADS=1 python benchmarks/fuzz_loaders.py --count 10000 --seed 0
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, fields, is_dataclass
from pathlib import Path
from typing import Any

import numpy as np

OUTCOMES = ("foreign", "unnamed", "error", "same", "changed")


# ------------------------------------------------------------------------------- mutator
def mutate(data: bytes, rng: np.random.Generator) -> bytes:
    """One corrupted copy of ``data`` (never equal to it), drawn from ``rng``."""
    for _ in range(100):
        out = _mutate_once(bytearray(data), rng)
        if out != data:
            return bytes(out)
    raise RuntimeError("mutate: could not change the data")  # pragma: no cover


def _mutate_once(buf: bytearray, rng: np.random.Generator) -> bytearray:
    n = len(buf)
    kind = int(rng.integers(7))
    if kind == 0:  # flip 1-8 bits
        for _ in range(int(rng.integers(1, 9))):
            i = int(rng.integers(n))
            buf[i] ^= 1 << int(rng.integers(8))
    elif kind == 1:  # overwrite 1-4 bytes with random values
        for _ in range(int(rng.integers(1, 5))):
            buf[int(rng.integers(n))] = int(rng.integers(256))
    elif kind == 2:  # truncate
        del buf[int(rng.integers(n)):]
    elif kind == 3:  # splice junk in
        i = int(rng.integers(n + 1))
        buf[i:i] = _junk(rng)
    elif kind == 4:  # write junk over a span
        junk = _junk(rng)
        i = int(rng.integers(n))
        buf[i:i + len(junk)] = junk
    elif kind == 5:  # delete a span
        i = int(rng.integers(n))
        del buf[i:i + int(rng.integers(1, 65))]
    else:  # duplicate a span elsewhere
        i, j = int(rng.integers(n)), int(rng.integers(n + 1))
        buf[j:j] = buf[i:i + int(rng.integers(1, 65))]
    return buf


def _junk(rng: np.random.Generator) -> bytes:
    """1-64 random bytes, or text-like junk (digits, JSON punctuation, letters, newlines)."""
    size = int(rng.integers(1, 65))
    if rng.random() < 0.5:
        return rng.integers(0, 256, size, dtype=np.uint8).tobytes()
    alphabet = np.frombuffer(b'0123456789.-+eE,:;{}[]"\' \n\tabcxyzUnknownMethod#/', np.uint8)
    return alphabet[rng.integers(0, len(alphabet), size)].tobytes()


# --------------------------------------------------------------------------------- kinds
@dataclass(frozen=True)
class Kind:
    """A loader under test: ``make(dir) -> path`` writes a valid original file,
    ``load(path)`` reads one, ``errors`` are its own error types, ``changed_fails``: a
    silent load of other content counts as a failure (the format carries a checksum)."""

    name: str
    make: Callable[[Path], Path]
    load: Callable[[Path], Any]
    errors: tuple[type[BaseException], ...]
    changed_fails: bool


def _make_replay(directory: Path) -> Path:
    import teamenv
    from teamenv.replay import ReplayRecorder

    env = teamenv.parallel_env(team_size=2)
    env.reset(seed=0)
    recorder = ReplayRecorder(env, extras=True)
    recorder.record()
    for _ in range(40):
        env.step({a: {"walk": [0.5, 0.0, 0.2]} for a in env.agents})
        recorder.record()
    env.close()
    return recorder.save(directory / "original.npz", {"seed": 0, "left": "a", "right": "b"})


def _make_profile(directory: Path) -> Path:
    from locomotion.profile import PROFILE_DIR

    path = directory / "original.json"
    path.write_bytes((PROFILE_DIR / "t1_mj.json").read_bytes())
    return path


def _make_formation(directory: Path) -> Path:
    import strategy.positioning.formation as formation_package

    path = directory / "original.json"
    data = Path(formation_package.__file__).parent / "data" / "7v7-defend.json"
    path.write_bytes(data.read_bytes())
    return path


_AGENT2D_NAMES = ["Goalie", "CenterBack", "CenterBack", "SideBack", "SideBack", "DefensiveHalf",
                  "DefensiveHalf", "SideHalf", "SideHalf", "Forward", "Forward"]
_AGENT2D_TYPES = ["G", "DF", "DF", "DF", "DF", "MF", "MF", "MF", "MF", "FW", "FW"]
_AGENT2D_PAIRS = [0, -1, 2, -1, 4, -1, 6, -1, 8, -1, 10]


def _agent2d_samples() -> tuple[list[list[float]], list[list[list[float]]]]:
    """A real-sized agent2d formation: the built-in 11 v 11 defence on 105 x 68 m, in
    agent2d's frame (y to the right of the attack), rounded to its 0.01 m."""
    from strategy.positioning.formation import builtin_formation

    f = builtin_formation("11v11-defend", "fifa").mirrored(flip_x=False, flip_y=True)
    return np.round(f.ball_samples, 2).tolist(), np.round(f.sample_positions, 2).tolist()


def _agent2d_text(form: str) -> str:
    ball, players = _agent2d_samples()
    roles = list(zip(_AGENT2D_NAMES, _AGENT2D_TYPES, _AGENT2D_PAIRS, strict=True))
    if form == "json":
        return json.dumps({
            "version": "", "method": "DelaunayTriangulation",
            "role": [{"number": u + 1, "name": n, "type": t, "side": "C", "pair": p}
                     for u, (n, t, p) in enumerate(roles)],
            "data": [{"index": k, "ball": {"x": b[0], "y": b[1]},
                      **{str(u + 1): {"x": xy[0], "y": xy[1]} for u, xy in enumerate(pl)}}
                     for k, (b, pl) in enumerate(zip(ball, players, strict=True))],
        }, indent=2)
    if form == "csv":
        lines = ["Method,DelaunayTriangulation",
                 "RoleNumber," + ",".join(str(u) for u in range(1, 12)),
                 "RoleName," + ",".join(_AGENT2D_NAMES),
                 "RoleType," + ",".join(_AGENT2D_TYPES),
                 "SymmetryNumber," + ",".join(str(p) for p in _AGENT2D_PAIRS),
                 "Marker," + ",".join("0" for _ in range(11)),
                 "SetplayMarker," + ",".join("0" for _ in range(11)),
                 "SampleData", f"Size,{len(ball)}",
                 "idx,ballX,ballY," + ",".join(f"{u}X,{u}Y" for u in range(1, 12))]
        lines += [",".join([str(k), f"{b[0]:g}", f"{b[1]:g}"] + [f"{v:g}" for xy in pl for v in xy])
                  for k, (b, pl) in enumerate(zip(ball, players, strict=True))]
        return "\n".join(lines) + "\n"
    lines = ["# agent2d formation", "Formation DelaunayTriangulation 3", "Begin Roles"]
    lines += [f"{u + 1} {t} {n} {p} 0 0" for u, (n, t, p) in enumerate(roles)]
    lines += ["End Roles", f"Begin Samples 2 {len(ball)}"]
    for k, (b, pl) in enumerate(zip(ball, players, strict=True)):
        lines += [f"----- {k} -----", f"Ball {b[0]:g} {b[1]:g}"]
        lines += [f"{u + 1} {xy[0]:g} {xy[1]:g}" for u, xy in enumerate(pl)]
    lines.append("End Samples")
    return "\n".join(lines) + "\n"


def _make_policy(directory: Path) -> Path:
    from teamenv.policy_team import save_mlp_policy

    rng = np.random.default_rng(0)
    layers = [(rng.normal(size=(12, 16)), rng.normal(size=16)),
              (rng.normal(size=(16, 9)), rng.normal(size=9))]
    return save_mlp_policy(directory / "original.npz", layers, obs_mean=np.zeros(12),
                           obs_std=np.ones(12), kick_gate_m=0.3)


def _agent2d_maker(form: str) -> Callable[[Path], Path]:
    def make(directory: Path) -> Path:
        path = directory / f"original-{form}.conf"
        path.write_text(_agent2d_text(form))
        return path

    return make


def kinds() -> dict[str, Kind]:
    from locomotion.errors import LocomotionError
    from locomotion.profile import load_profile
    from strategy.positioning.formation import FormationError, import_agent2d
    from strategy.positioning.formation.fileformat import read_formation
    from teamenv.errors import TeamEnvError
    from teamenv.policy_team import load_policy
    from teamenv.replay import load_replay

    out = {
        "replay": Kind("replay", _make_replay, load_replay, (TeamEnvError,), True),
        "profile": Kind("profile", _make_profile, load_profile, (LocomotionError,), False),
        "formation": Kind("formation", _make_formation, read_formation, (FormationError,),
                          False),
    }
    for form in ("json", "csv", "v3"):
        out[f"agent2d-{form}"] = Kind(f"agent2d-{form}", _agent2d_maker(form),
                                      lambda p: import_agent2d(Path(p)), (FormationError,),
                                      False)
    out["policy"] = Kind("policy", _make_policy, load_policy, (TeamEnvError,), False)
    return out


# ---------------------------------------------------------------------------- comparing
def same(a: Any, b: Any) -> bool:
    """Deep equality of what two loads gave (arrays with NaN == NaN, dataclasses field by
    field, a Formation by its roles, samples and settings)."""
    if type(a) is not type(b):
        return False
    if isinstance(a, np.ndarray):
        return a.shape == b.shape and a.dtype == b.dtype and bool(
            np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"))
    if is_dataclass(a):
        return all(same(getattr(a, f.name), getattr(b, f.name)) for f in fields(a))
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=True))
    if type(a).__name__ == "Formation":
        return (a.name == b.name and a.description == b.description
                and a.outside == b.outside and a.field_size == b.field_size
                and a.roles == b.roles and same(a.ball_samples, b.ball_samples)
                and same(a.sample_positions, b.sample_positions))
    if isinstance(a, float) and isinstance(b, float) and a != a and b != b:
        return True
    if hasattr(a, "__dict__") and not isinstance(a, type):  # e.g. an MLPPolicy: its attributes
        return same(vars(a), vars(b))
    return bool(a == b)


def _content(kind: Kind, loaded: Any) -> Any:
    """What to compare: a replay without its metadata's checksum (it names the content)."""
    if kind.name == "replay":
        meta = {k: v for k, v in loaded.metadata.items() if k != "sha256"}
        return {**{f.name: getattr(loaded, f.name) for f in fields(loaded)
                   if f.name != "metadata"}, "metadata": meta}
    return loaded


# -------------------------------------------------------------------------------- fuzzing
@dataclass
class Tally:
    counts: Counter
    examples: dict[str, list[str]]
    seconds: float


def fuzz(kind: Kind, count: int, seed: int, directory: Path, keep_examples: int = 3) -> Tally:
    """Load ``count`` corrupted copies of ``kind``'s original; count the outcomes."""
    original_path = kind.make(directory)
    data = original_path.read_bytes()
    path = directory / f"corrupt-{kind.name}{original_path.suffix}"
    path.write_bytes(data)  # the reference load, from the same path (a name may come from it)
    original = _content(kind, kind.load(path))
    rng = np.random.default_rng([seed, sum(kind.name.encode())])
    counts: Counter = Counter({o: 0 for o in OUTCOMES})
    examples: dict[str, list[str]] = {o: [] for o in OUTCOMES}
    start = time.perf_counter()
    for _ in range(count):
        corrupted = mutate(data, rng)
        path.write_bytes(corrupted)
        try:
            loaded = kind.load(path)
        except kind.errors as exc:
            outcome = "error" if str(path) in str(exc) else "unnamed"
            note = f"{type(exc).__name__}: {exc}"
        except Exception as exc:  # noqa: BLE001 - counting what escapes is the point
            outcome, note = "foreign", f"{type(exc).__name__}: {exc}"
        else:
            outcome = "same" if same(original, _content(kind, loaded)) else "changed"
            note = f"loaded: {_difference(data, corrupted)}"
        counts[outcome] += 1
        if len(examples[outcome]) < keep_examples:
            examples[outcome].append(note[:300])
    return Tally(counts, examples, time.perf_counter() - start)


def _difference(original: bytes, corrupted: bytes, context: int = 12) -> str:
    """Where two byte strings first differ, as ``...before... -> ...after...``."""
    i = next((k for k, (a, b) in enumerate(zip(original, corrupted, strict=False)) if a != b),
             min(len(original), len(corrupted)))
    lo = max(0, i - context)
    return (f"at byte {i}: {original[lo:i + context]!r} -> {corrupted[lo:i + context]!r}"
            + ("" if len(original) == len(corrupted) else
               f" (length {len(original)} -> {len(corrupted)})"))


def failures(kind: Kind, tally: Tally) -> int:
    """Foreign and unnamed errors, and for a checksummed format the changed loads."""
    c = tally.counts
    return c["foreign"] + c["unnamed"] + (c["changed"] if kind.changed_fails else 0)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--count", type=int, default=10_000,
                        help="corrupted files per kind (default 10000)")
    parser.add_argument("--seed", type=int, default=0, help="the mutator's seed (default 0)")
    parser.add_argument("--kinds", default=None,
                        help="comma-separated kinds (default all: replay, profile, formation, "
                             "agent2d-json, agent2d-csv, agent2d-v3, policy)")
    parser.add_argument("--examples", type=int, default=2,
                        help="example messages printed per outcome (default 2)")
    parser.add_argument("--json", type=Path, default=None, help="also write the counts here")
    args = parser.parse_args(argv)
    available = kinds()
    chosen = list(available) if args.kinds is None else args.kinds.split(",")
    unknown = [k for k in chosen if k not in available]
    if unknown:
        parser.error(f"unknown kind(s) {unknown}; choose from {list(available)}")
    rows = {}
    bad = 0
    print(f"{'kind':14s} {'files':>6s} " + " ".join(f"{o:>8s}" for o in OUTCOMES)
          + f" {'failures':>8s} {'s':>6s}")
    with tempfile.TemporaryDirectory() as tmp:
        for name in chosen:
            kind = available[name]
            tally = fuzz(kind, args.count, args.seed, Path(tmp), keep_examples=args.examples)
            fails = failures(kind, tally)
            bad += fails
            rows[name] = {**dict(tally.counts), "failures": fails,
                          "seconds": round(tally.seconds, 1)}
            print(f"{name:14s} {args.count:6d} "
                  + " ".join(f"{tally.counts[o]:8d}" for o in OUTCOMES)
                  + f" {fails:8d} {tally.seconds:6.1f}", flush=True)
            for outcome in ("foreign", "unnamed", "changed", "error"):
                for note in tally.examples[outcome][:args.examples]:
                    print(f"    {outcome}: {note}")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"command": " ".join(["python",
                                                              "benchmarks/fuzz_loaders.py",
                                                              *(argv or sys.argv[1:])]),
                                         "count": args.count, "seed": args.seed,
                                         "kinds": rows}, indent=2) + "\n")
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
