"""Convert the league server's reference walking network (a torch state dict) to the numpy
``.npz`` that ``teamenv.league.network_walk`` loads, so matches run without torch.

The weights are copied unchanged (float32). The source is the rcssservermj repository's
``example/nn_client/locomotion_nn.pth`` (MIT licence, see teamenv/league/data/LICENSE)::

    git -C /work/.mirror/rob450-soccer+RCSSServerMJ/repo show \
        HEAD:example/nn_client/locomotion_nn.pth > /tmp/locomotion_nn.pth
    .venv/bin/python scripts/convert_reference_walk_network.py /tmp/locomotion_nn.pth

Needs torch (the ``rl`` extra), only here.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

#: the state dict's keys, and their shapes (torch's Linear weight is (out, in))
EXPECTED = {
    "fc1.weight": (512, 78), "fc1.bias": (512,),
    "layer_norm.weight": (512,), "layer_norm.bias": (512,),
    "fc2.weight": (256, 512), "fc2.bias": (256,),
    "fc3.weight": (128, 256), "fc3.bias": (128,),
    "fc4.weight": (23, 128), "fc4.bias": (23,),
}
DEFAULT_OUT = Path(__file__).resolve().parents[1] / "teamenv/league/data/t1_reference_walk.npz"


def convert(pth: Path, out: Path) -> dict[str, np.ndarray]:
    import torch

    state = torch.load(pth, map_location="cpu", weights_only=True)
    if set(state) != set(EXPECTED):
        raise SystemExit(f"{pth}: keys {sorted(state)} are not the reference network's "
                         f"{sorted(EXPECTED)}")
    arrays = {}
    for key, shape in EXPECTED.items():
        a = state[key].detach().cpu().numpy()
        if a.shape != shape or a.dtype != np.float32:
            raise SystemExit(f"{pth}: {key} is {a.dtype}{a.shape}, expected float32{shape}")
        arrays[key.replace(".", "_")] = a
    out.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(out, **arrays)
    return arrays


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("pth", type=Path, help="the reference's locomotion_nn.pth")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"default {DEFAULT_OUT}")
    args = ap.parse_args(argv)
    arrays = convert(args.pth, args.out)
    print(f"wrote {args.out} ({sum(a.size for a in arrays.values())} parameters)")


if __name__ == "__main__":
    main()
