"""Channel.deliver_texts (one text per agent) gives what deliver() gives for the same
utterances: heard lists, drops, capacities and draws from the Generator; and a Delivery's
`pairs` arrays hold exactly its heard lists."""

import base64

import numpy as np
import pytest

from comms.channel import Utterance, make_channel

CASES = [("simspark", {}), ("mj", {}), ("simspark", {"max_heard": 2}),
         ("simspark", {"capacity": None}), ("simspark", {"self_echo": False}),
         ("mj", {"self_echo": True}), ("simspark", {"hearing_range_m": 10.0}),
         ("simspark", {"arrival_order": "index"}), ("simspark", {"delay_cycles": 2}),
         ("mj", {"max_heard": 21}), ("mj", {"max_volume": 50.0})]


def _pairs_as_heard(delivery, n):
    out = [[] for _ in range(n)]
    if delivery.pairs is None:
        return out
    for li, spk, text, direction, me, mate in zip(*(a.tolist() for a in delivery.pairs), strict=True):
        out[li].append((spk, text, direction, me, mate))
    return out


@pytest.mark.parametrize(("name", "overrides"), CASES)
def test_deliver_texts_equals_deliver(name, overrides):
    n = 10
    teams = np.repeat([0, 1], n // 2)
    a = make_channel(name, n, teams, **overrides)
    b = make_channel(name, n, teams, **overrides)
    ra, rb = np.random.default_rng(4), np.random.default_rng(4)
    data = np.random.default_rng(9)
    for cycle in range(200):
        pos = data.uniform(-30, 30, (n, 2))
        hd = data.uniform(-4, 4, n)
        texts = []
        for _ in range(n):
            if data.random() < 0.2:
                texts.append("")
            elif a.profile.base64_payload:
                texts.append(base64.b64encode(data.bytes(int(data.integers(1, 11)))).decode())
            else:
                texts.append("t" * int(data.integers(1, 21)))
            if data.random() < 0.02:
                texts[-1] += "(("  # illegal: dropped whole
        da = a.deliver_texts(texts, pos, hd, ra)
        db = b.deliver([Utterance(i, t, 100.0) for i, t in enumerate(texts) if t], pos, hd, rb)
        assert da.heard == db.heard, cycle
        assert [[tuple(h) for h in row] for row in da.heard] == _pairs_as_heard(da, n) or \
            da.pairs is None
        assert da.dropped == db.dropped, cycle
        assert (a.capacities == b.capacities).all()
    assert ra.random() == rb.random()


@pytest.mark.parametrize(("name", "overrides"), CASES)
def test_drop_arrays_list_the_drops_in_order(name, overrides):
    n = 10
    channel = make_channel(name, n, np.repeat([0, 1], n // 2), **overrides)
    rng, data = np.random.default_rng(1), np.random.default_rng(2)
    for _ in range(50):
        texts = ["QUJD" if data.random() < 0.9 else "((" for _ in range(n)]
        d = channel.deliver_texts(texts, data.uniform(-40, 40, (n, 2)), np.zeros(n), rng)
        speaker, listener, reason = d.drop_arrays()
        assert list(zip(speaker.tolist(), listener.tolist(), reason.tolist(), strict=True)) \
            == [tuple(x) for x in d.dropped]
        assert d.drop_arrays()[0].tolist() == speaker.tolist()  # also once `dropped` is built
