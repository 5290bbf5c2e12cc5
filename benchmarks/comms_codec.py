"""Benchmark: say-message encode/decode and channel delivery cost against one env step.

Target: a whole team's messages for one cycle (11 encodes + 11 x 10 decodes of a role vector)
cost under 5% of one env step (~1 ms unless --env-step-ms or --measure-env says otherwise).

Usage: python benchmarks/comms_codec.py [--repeat 7] [--env-step-ms 1.0] [--measure-env]
                                        [--clock wall|cpu]
"""

import argparse
import platform
import statistics
import time
from collections.abc import Callable

import numpy as np

import comms
from comms import messages

CLOCK = time.perf_counter


def _time(fn: Callable[[], object], number: int, repeat: int) -> tuple[float, float]:
    """(best, median) seconds per call over `repeat` runs of `number` calls, after warm-up."""
    for _ in range(min(number, 200)):
        fn()
    runs = []
    for _ in range(repeat):
        t0 = CLOCK()
        for _ in range(number):
            fn()
        runs.append((CLOCK() - t0) / number)
    return min(runs), statistics.median(runs)


def _us(x: float) -> str:
    return f"{x * 1e6:8.2f} us"


def bench_messages(repeat: int) -> None:
    rng = np.random.default_rng(0)
    print("per message (best / median of runs):")
    cases = [
        ("role vector 11, simspark", messages.ROLE_VECTOR),
        ("role vector 11, mj", messages.role_vector_schema(11, channel="mj")),
        ("team state 11, simspark", messages.TEAM_STATE),
        ("opponents 11, base-92", messages.opponents_schema()),
    ]
    for label, schema in cases:
        vals = [schema.random_values(rng)._asdict() for _ in range(256)]
        texts = [schema.encode(v) for v in vals]
        k = iter(range(1 << 62))

        def enc(vals=vals, schema=schema, k=k):
            schema.encode(vals[next(k) & 255])

        def dec_cold(texts=texts, schema=schema, k=k):
            schema._cache.clear()
            schema.decode(texts[next(k) & 255])

        def dec_warm(texts=texts, schema=schema, k=k):
            schema.decode(texts[next(k) & 255])

        e = _time(enc, 5000, repeat)
        d = _time(dec_cold, 5000, repeat)
        w = _time(dec_warm, 5000, repeat)
        print(
            f"  {label:<26} {schema.bits:>3} bits {schema.codec_name:<12} {schema.chars:>2} chars | "
            f"encode {_us(e[0])} / {_us(e[1])} | decode {_us(d[0])} / {_us(d[1])} | "
            f"decode (cache hit) {_us(w[0])}"
        )


def bench_team_cycle(repeat: int, step_s: float) -> None:
    schema = messages.ROLE_VECTOR
    rng = np.random.default_rng(1)
    # a pool of distinct role vectors, so every cycle encodes and decodes new texts
    pool = [[int(x) for x in rng.permutation(11)] for _ in range(4096)]
    k = iter(range(1 << 62))

    def cycle(cold: bool) -> None:
        schema._cache.clear()  # every cycle's 11 texts are new: 11 misses, then 99 hits
        base = next(k) * 11
        texts = [schema.encode({"roles": pool[(base + i) & 4095]}) for i in range(11)]
        for _listener in range(11):
            for j, t in enumerate(texts):
                if j != _listener:
                    if cold:
                        schema._cache.clear()
                    schema.decode(t)

    print(
        f"team cycle, role vector: 11 encodes + 11 x 10 decodes "
        f"(env step taken as {step_s * 1e3:.3f} ms; target < 5% = {step_s * 0.05 * 1e6:.1f} us):"
    )
    for label, cold in (("decode cache on (default)", False), ("decode cache off", True)):
        best, med = _time(lambda cold=cold: cycle(cold), 300, repeat)
        print(
            f"  {label:<26} best {_us(best)}  median {_us(med)}  = {100 * best / step_s:5.1f}% "
            f"/ {100 * med / step_s:5.1f}% of a step"
        )


def bench_channel(repeat: int, step_s: float) -> None:
    n = 22
    teams = [0] * 11 + [1] * 11
    rng = np.random.default_rng(2)
    pos = rng.uniform([-15, -10], [15, 10], size=(n, 2))
    hd = rng.uniform(-np.pi, np.pi, n)
    print("channel.deliver, 22 agents:")
    for name, text in (("simspark", "abcdefghij0123456789"), ("mj", "AAAAAAAAAAAAAA==")):
        ch = comms.make_channel(name, n, teams)
        everyone = [comms.Utterance(i, text) for i in range(n)]
        silent = [comms.Utterance(i, "") for i in range(n)]
        for label, utts, drops in (
            ("no speakers", [], False),
            ("22 silent utterances", silent, False),
            ("all 22 speak", everyone, False),
            ("all 22 speak + .dropped", everyone, True),
        ):

            def run(ch=ch, utts=utts, drops=drops):
                d = ch.deliver(utts, pos, hd, rng)
                if drops:
                    d.dropped  # noqa: B018 - builds the lazy drop list

            best, med = _time(run, 2000, repeat)
            print(
                f"  {name:<9} {label:<26} best {_us(best)}  median {_us(med)}  "
                f"= {100 * best / step_s:5.1f}% of a step"
            )


def measure_env_step(steps: int = 500) -> float:
    """Seconds per step of the teamenv ParallelEnv (11 v 11, silent random walking)."""
    import teamenv  # only here: comms itself never imports teamenv

    env = teamenv.parallel_env(team_size=11, rules={"half_time_s": 1e6})
    env.reset(seed=0)
    actions = {a: {} for a in env.agents}
    for _ in range(50):
        env.step(actions)
    t0 = CLOCK()
    for _ in range(steps):
        env.step(actions)
    return (CLOCK() - t0) / steps


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--env-step-ms", type=float, default=1.0)
    ap.add_argument("--measure-env", action="store_true", help="time a real teamenv step")
    ap.add_argument(
        "--clock",
        choices=["wall", "cpu"],
        default="wall",
        help="wall: perf_counter; cpu: process_time (ignores time lost to other processes "
        "on a busy machine)",
    )
    args = ap.parse_args()
    global CLOCK
    CLOCK = time.perf_counter if args.clock == "wall" else time.process_time
    step_s = args.env_step_ms / 1e3
    if args.measure_env:
        step_s = measure_env_step()
        print(f"measured env step: {step_s * 1e3:.3f} ms")
    print(
        f"python {platform.python_version()}, numpy {np.__version__}, {platform.machine()}, "
        f"clock {args.clock}"
    )
    bench_messages(args.repeat)
    bench_team_cycle(args.repeat, step_s)
    bench_channel(args.repeat, step_s)


if __name__ == "__main__":
    main()
