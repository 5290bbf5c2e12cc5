"""ChannelProfile.all_legal (one regex over a batch of texts) agrees with check_message."""

import base64

import numpy as np
import pytest

from comms.profiles import MJ, SIMSPARK, get_profile


def _texts(rng, profile, k):
    pool = profile.charset + "()\n =é"
    out = []
    for _ in range(k):
        kind = rng.integers(0, 3)
        if kind == 0 and profile.base64_payload:
            out.append(base64.b64encode(rng.bytes(int(rng.integers(0, 13)))).decode())
        else:
            n = int(rng.integers(0, profile.max_chars + 4))
            out.append("".join(pool[j] for j in rng.integers(0, len(pool), n)))
    return out


@pytest.mark.parametrize("profile", [SIMSPARK, MJ, get_profile("simspark", max_chars=3),
                                     get_profile("mj", payload_bytes=4, max_chars=8)],
                         ids=["simspark", "mj", "short", "mj-short"])
def test_all_legal_agrees_with_check_message(profile):
    rng = np.random.default_rng(0)
    for _ in range(3000):
        texts = _texts(rng, profile, int(rng.integers(1, 4)))
        expected = all(t != "" and profile.check_message(t) is None for t in texts)
        assert profile.all_legal(texts) == expected, texts
    assert profile.all_legal([])
    assert not profile.all_legal(["ok", 3])
    assert not profile.all_legal([""])
