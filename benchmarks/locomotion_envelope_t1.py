"""Measure the T1's walking envelope under the LIPM walker in native MuJoCo and write it as the
``t1_lipm`` profile (walk numbers kind ``measured-humanoid``; falls/kicks as in ``t1_mj``).

Optionally (``--brax N``) the first N commands also run in brax (generalized pipeline, a short
run each) and the distance walked is compared with native MuJoCo.
"""

from __future__ import annotations

import argparse
import json
import shlex
import sys
import time

from locomotion.humanoid.envelope import (
    DEFAULT_COMMANDS,
    envelope_to_profile,
    measure_command,
    measure_envelope,
)
from locomotion.humanoid.measure import base_profile, write_measured_profile
from locomotion.humanoid.t1 import load_t1
from locomotion.humanoid.walker import WalkParams


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--seconds", type=float, default=15.0, help="length of each run (s)")
    ap.add_argument("--out", default=None, help="profile JSON to write (default: print only)")
    ap.add_argument("--report", default=None, help="also write the raw rows as JSON here")
    ap.add_argument("--base", default="t1_mj")
    ap.add_argument("--brax", type=int, default=0, help="also run the first N commands in brax")
    ap.add_argument("--brax-seconds", type=float, default=2.0)
    ap.add_argument(
        "--brax-timestep",
        type=float,
        default=0.0005,
        help="physics step of the brax/MuJoCo comparison (s); brax's explicit PD at the "
        "walker's gains is unstable at the model's 2 ms",
    )
    args = ap.parse_args()
    command = "python " + " ".join(shlex.quote(x) for x in sys.argv)
    t1 = load_t1()
    params = WalkParams()
    t0 = time.perf_counter()
    env = measure_envelope(DEFAULT_COMMANDS, args.seconds, params, t1)
    print(
        f"native MuJoCo: {len(env['rows'])} commands x {args.seconds:g} s in "
        f"{time.perf_counter() - t0:.0f} s wall"
    )
    print(f"   {'command (vx, vy, w)':24s} {'achieved (vx, vy, w)':28s} result")
    for r in env["rows"]:
        c = "(" + ", ".join(f"{x:5.2f}" for x in r["command"]) + ")"
        a = "-" if r["fell"] else "(" + ", ".join(f"{x:6.3f}" for x in r["achieved"]) + ")"
        res = f"FELL at {r['time']:.1f} s" if r["fell"] else "stood"
        print(f"   {c:24s} {a:28s} {res}")
    if args.brax:
        from locomotion.humanoid.brax_sim import BraxT1

        t1b = load_t1()
        t1b.model.opt.timestep = args.brax_timestep
        b = BraxT1(t1b, every=int(round(params.dt / args.brax_timestep)))
        rows = []
        for cmd in DEFAULT_COMMANDS[: args.brax]:
            tb = time.perf_counter()
            rb = measure_command(t1b, cmd, args.brax_seconds, params, "brax", brax_t1=b, skip_s=1.0)
            rm = measure_command(t1b, cmd, args.brax_seconds, params, "mujoco", skip_s=1.0)
            rows.append({"command": list(cmd), "brax": rb, "mujoco": rm})
            print(
                f"   brax vs mujoco {cmd}: distance {rb['distance']:.3f} vs {rm['distance']:.3f} m, "
                f"turned {rb['turned']:.3f} vs {rm['turned']:.3f} rad, fell {rb['fell']} vs "
                f"{rm['fell']} ({time.perf_counter() - tb:.0f} s wall)"
            )
        env["brax_subset"] = {
            "seconds": args.brax_seconds,
            "timestep": args.brax_timestep,
            "rows": rows,
        }
    prof = envelope_to_profile(base_profile(args.base), env, command)
    for k in (
        "tracking_vx",
        "tracking_vy",
        "tracking_turn",
        "envelope_vx_forward",
        "envelope_vx_backward",
        "envelope_vy",
        "envelope_turn",
    ):
        print(f"   {k:22s} {prof['parameters'][k]['value']}")
    if args.report:
        with open(args.report, "w", encoding="utf-8") as fh:
            json.dump({"command": command, **env}, fh, indent=1)
    if args.out:
        write_measured_profile(prof, args.out)
        print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
