"""Tests of the say-channel profiles and the hearing model (comms.channel, comms.profiles)."""

import math

import numpy as np
import pytest

import comms
from comms import Drop, Utterance, hearing_capacity_trace, make_channel

ILLEGAL_SIMSPARK = [chr(c) for c in range(0, 0x21)] + ["(", ")", "\x7f", "é", "\u20ac"]


def _line(n: int, spacing: float = 1.0) -> np.ndarray:
    return np.stack([np.arange(n) * spacing, np.zeros(n)], axis=1)


# ---------------------------------------------------------------- profiles / legality
def test_profile_fields():
    s = comms.make_channel("simspark", 2, [0, 1]).profile
    assert (s.name, s.max_chars, s.max_heard, len(s.charset)) == ("simspark", 20, 3, 92)
    assert "(" not in s.charset and ")" not in s.charset and " " not in s.charset
    assert s.payload_bits == 130
    m = comms.make_channel("mj", 2, [0, 1]).profile
    assert (m.name, m.max_chars, m.payload_bytes, m.payload_bits) == ("mj", 16, 10, 80)
    assert set(m.charset) == set(comms.BASE64_ALPHABET) | {"="}


@pytest.mark.parametrize("length", range(0, 41))
def test_every_length_simspark(length):
    ch = make_channel("simspark", 2, [0, 1])
    expect = None if length <= 20 else "too_long"
    assert ch.check_message("a" * length) == expect
    assert ch.check_message("~" * length) == expect


@pytest.mark.parametrize("length", range(0, 41))
def test_every_length_mj(length):
    ch = make_channel("mj", 2, [0, 1])
    text = "A" * length
    if length == 0:
        expect = None
    elif length > 16:
        expect = "too_long"
    elif length % 4:
        expect = "bad_base64"
    elif length == 16:
        expect = "too_long"  # 12 bytes > 10
    else:
        expect = None
    assert ch.check_message(text) == expect
    # padded forms
    if length >= 4 and length % 4 == 0 and length <= 16:
        for pad in (1, 2):
            t = "A" * (length - pad) + "=" * pad
            n_bytes = length // 4 * 3 - pad
            assert ch.check_message(t) == (None if n_bytes <= 10 else "too_long"), t


@pytest.mark.parametrize("char", ILLEGAL_SIMSPARK)
def test_every_illegal_character_simspark(char):
    ch = make_channel("simspark", 2, [0, 1])
    assert ch.check_message(char) == "illegal_character"
    assert ch.check_message("ab" + char + "cd") == "illegal_character"


def test_every_legal_character_simspark():
    ch = make_channel("simspark", 2, [0, 1])
    for c in range(0x21, 0x7F):
        ok = chr(c) not in "()"
        assert (ch.check_message(chr(c)) is None) == ok, hex(c)


def test_every_character_mj():
    ch = make_channel("mj", 2, [0, 1])
    legal = set(comms.BASE64_ALPHABET)
    for c in range(0, 0x180):
        text = chr(c) * 4
        if chr(c) in legal:
            assert ch.check_message(text) is None
        elif chr(c) == "=":
            assert ch.check_message(text) == "bad_base64"
        else:
            assert ch.check_message(text) == "illegal_character", hex(c)
    assert ch.check_message("A===") == "bad_base64"
    assert ch.check_message("AB=A") == "bad_base64"
    assert ch.check_message("AAAAAAAAAAAAAA==") is None  # exactly 10 bytes


def test_not_a_string():
    ch = make_channel("simspark", 2, [0, 1])
    assert ch.check_message(b"abc") == "not_a_string"
    assert ch.check_message(None) == "not_a_string"


def test_unknown_profile_and_option():
    with pytest.raises(comms.ChannelError, match="nope"):
        make_channel("nope", 2, [0, 1])
    with pytest.raises(ValueError, match="max_hurd"):
        make_channel("simspark", 2, [0, 1], max_hurd=3)
    with pytest.raises(comms.ChannelError, match="teams"):
        make_channel("simspark", 3, [0, 1])
    with pytest.raises(comms.ChannelError, match="teams"):
        make_channel("simspark", 2, [0, 2])


def test_override():
    ch = make_channel("mj", 4, [0, 0, 1, 1], max_heard=3, arrival_order="index")
    assert ch.profile.max_heard == 3 and ch.profile.arrival_order == "index"
    assert comms.MJ.max_heard == 8  # the shared profile is untouched


# ---------------------------------------------------------------- simspark delivery
def test_no_speakers():
    ch = make_channel("simspark", 22, [0] * 11 + [1] * 11)
    d = ch.deliver([], _line(22), np.zeros(22), np.random.default_rng(0))
    assert d.heard == [[] for _ in range(22)] and d.dropped == []
    d = ch.deliver([Utterance(i, "") for i in range(22)], _line(22), np.zeros(22), None)
    assert d.heard == [[] for _ in range(22)] and d.dropped == []


def test_illegal_dropped_whole_for_everyone():
    ch = make_channel("simspark", 3, [0, 0, 1])
    rng = np.random.default_rng(0)
    d = ch.deliver([Utterance(0, "x" * 21), Utterance(1, "a b")], _line(3), np.zeros(3), rng)
    assert d.heard == [[], [], []]
    assert d.dropped == [Drop(0, -1, "too_long"), Drop(1, -1, "illegal_character")]


def test_self_echo_and_directions():
    ch = make_channel("simspark", 3, [0, 0, 1])
    pos = np.array([[0.0, 0.0], [0.0, 5.0], [-3.0, 0.0]])
    hd = np.array([0.0, math.pi / 2, 0.0])
    d = ch.deliver([Utterance(0, "hi")], pos, hd, np.random.default_rng(0))
    (h0,) = d.heard[0]
    assert h0.is_self and h0.teammate and h0.direction == 0.0 and h0.text == "hi"
    (h1,) = d.heard[1]  # speaker straight below a listener facing +y: behind it
    assert not h1.is_self and h1.teammate
    assert abs(abs(h1.direction) - math.pi) < 1e-12
    (h2,) = d.heard[2]  # speaker ahead (+x) of a listener facing +x
    assert not h2.teammate and abs(h2.direction) < 1e-12
    assert d.dropped == []


def test_direction_left_right():
    ch = make_channel("simspark", 2, [0, 1])
    pos = np.array([[0.0, 0.0], [0.0, 2.0]])
    d = ch.deliver([Utterance(1, "x")], pos, np.zeros(2), np.random.default_rng(0))
    assert d.heard[0][0].direction == pytest.approx(math.pi / 2)
    d = ch.deliver([Utterance(0, "x")], pos, np.array([0.0, math.pi]), np.random.default_rng(0))
    assert d.heard[1][0].direction == pytest.approx(math.pi / 2)  # facing -x, speaker at -y


def test_range_50m():
    ch = make_channel("simspark", 3, [0, 0, 0])
    pos = np.array([[0.0, 0.0], [49.99, 0.0], [-50.01, 0.0]])
    d = ch.deliver([Utterance(0, "x")], pos, np.zeros(3), np.random.default_rng(0))
    assert [len(h) for h in d.heard] == [1, 1, 0]
    assert d.dropped == [Drop(0, 2, "out_of_range")]


@pytest.mark.parametrize(
    "arrivals,expected",
    [
        ([1] * 8, [1, 0, 1, 0, 1, 0, 1, 0]),
        ([5] * 6, [1, 0, 1, 0, 1, 0]),
        ([0, 1, 1, 0, 1], [0, 1, 0, 0, 1]),
        ([0, 0, 0, 3, 3], [0, 0, 0, 1, 0]),  # never more than max 2 banked
    ],
)
def test_capacity_trace_league_numbers(arrivals, expected):
    assert hearing_capacity_trace(arrivals) == expected
    assert sum(hearing_capacity_trace([1] * 100)) == 50  # one message every 2 cycles at most


def test_capacity_counter_values():
    ch = make_channel("simspark", 3, [0, 0, 1])
    rng = np.random.default_rng(0)
    assert ch.capacities.tolist() == [[2, 2, 2], [2, 2, 2]]
    ch.deliver([Utterance(0, "a")], _line(3), np.zeros(3), rng)
    # listener 1 heard a teammate (-2); listener 2 heard an opponent (-2); self not charged
    assert ch.capacities.tolist() == [[2, 0, 2], [2, 2, 0]]
    ch.deliver([], _line(3), np.zeros(3), rng)
    assert ch.capacities.tolist() == [[2, 1, 2], [2, 2, 1]]
    ch.deliver([], _line(3), np.zeros(3), rng)
    assert ch.capacities.tolist() == [[2, 2, 2], [2, 2, 2]]  # max 2
    ch.deliver([Utterance(0, "a")], _line(3), np.zeros(3), rng)
    ch.reset()
    assert ch.capacities.tolist() == [[2, 2, 2], [2, 2, 2]]


def test_full_team_talking_every_cycle():
    n = 22
    teams = [0] * 11 + [1] * 11
    ch = make_channel("simspark", n, teams)
    rng = np.random.default_rng(1)
    pos = rng.uniform([-15, -10], [15, 10], size=(n, 2))
    counts = np.zeros((n, 3), int)
    for _ in range(10):
        utts = [Utterance(i, f"m{i}") for i in range(n)]
        d = ch.deliver(utts, pos, np.zeros(n), rng)
        for i, hs in enumerate(d.heard):
            assert len(hs) <= 3
            assert hs[0].is_self and hs[0].speaker == i  # self first, always
            kinds = [(h.is_self, h.teammate) for h in hs[1:]]
            assert kinds.count((False, True)) <= 1 and kinds.count((False, False)) <= 1
            if len(hs) == 3:
                assert hs[1].teammate and not hs[2].teammate  # teammate before opponent
            counts[i] += [
                1,
                sum(k == (False, True) for k in kinds),
                sum(k == (False, False) for k in kinds),
            ]
        reasons = {x.reason for x in d.dropped}
        assert reasons <= {"capacity"}
        # every (speaker, listener) pair is either heard or dropped, exactly once
        pairs = {(h.speaker, i) for i, hs in enumerate(d.heard) for h in hs}
        dropped = {(x.speaker, x.listener) for x in d.dropped}
        assert not pairs & dropped and len(pairs) + len(d.dropped) == n * n
    assert (counts[:, 0] == 10).all()
    assert (counts[:, 1] == 5).all() and (counts[:, 2] == 5).all()  # one per 2 cycles


def test_arrival_order_index_and_shuffle():
    ch = make_channel("simspark", 4, [0, 0, 0, 0], arrival_order="index")
    utts = [Utterance(3, "c"), Utterance(2, "b"), Utterance(1, "a")]
    d = ch.deliver(utts, _line(4), np.zeros(4), np.random.default_rng(0))
    assert [h.speaker for h in d.heard[0]] == [1]  # lowest index arrives first
    firsts = set()
    for seed in range(20):
        ch = make_channel("simspark", 4, [0, 0, 0, 0])
        d = ch.deliver(utts, _line(4), np.zeros(4), np.random.default_rng(seed))
        firsts.add(d.heard[0][0].speaker)
    assert firsts == {1, 2, 3}


def test_deterministic_given_seed():
    def run(seed):
        ch = make_channel("simspark", 22, [0] * 11 + [1] * 11)
        rng = np.random.default_rng(seed)
        pos = rng.uniform(-15, 15, size=(22, 2))
        out = []
        for t in range(5):
            d = ch.deliver([Utterance(i, f"{t}") for i in range(0, 22, 2)], pos, np.zeros(22), rng)
            out.append((d.heard, d.dropped))
        return out

    assert run(3) == run(3)


def test_bad_speaker():
    ch = make_channel("simspark", 2, [0, 1])
    with pytest.raises(comms.ChannelError, match="speaker index 5"):
        ch.deliver([Utterance(5, "x")], _line(2), np.zeros(2), np.random.default_rng(0))
    with pytest.raises(comms.ChannelError, match="speaker 0"):
        ch.deliver([Utterance(0, "x"), Utterance(0, "y")], _line(2), np.zeros(2), None)
    with pytest.raises(comms.ChannelError, match="positions"):
        ch.deliver([Utterance(0, "x")], np.zeros((3, 2)), np.zeros(2), np.random.default_rng(0))


def test_delay_cycles():
    ch = make_channel("simspark", 2, [0, 0], delay_cycles=3)
    rng = np.random.default_rng(0)
    got = []
    for t in range(5):
        d = ch.deliver([Utterance(0, f"t{t}")], _line(2), np.zeros(2), rng)
        got.append([h.text for h in d.heard[0]])
    assert got == [[], [], ["t0"], ["t1"], ["t2"]]


# ---------------------------------------------------------------- mj delivery
def test_mj_no_self_echo_opponents_hear():
    ch = make_channel("mj", 3, [0, 0, 1])
    d = ch.deliver([Utterance(0, "AAAA")], _line(3), np.zeros(3), np.random.default_rng(0))
    assert d.heard[0] == []
    assert [h.speaker for h in d.heard[1]] == [0] and d.heard[1][0].teammate
    assert [h.speaker for h in d.heard[2]] == [0] and not d.heard[2][0].teammate


def test_mj_three_loudest_always_heard():
    n = 6
    ch = make_channel("mj", n, [0] * n)
    pos = np.array([[0.0, 0.0], [150, 0], [160, 0], [170, 0], [180, 0], [190, 0]])
    for seed in range(20):
        utts = [Utterance(i, "AAAA") for i in range(1, n)]
        d = ch.deliver(utts, pos, np.zeros(n), np.random.default_rng(seed))
        # far away: the 3 loudest (nearest) always arrive, the others are (almost) always lost
        assert [h.speaker for h in d.heard[0]][:3] == [1, 2, 3]
    # a louder far speaker outranks a quieter near one
    pos2 = np.array([[0.0, 0.0], [10, 0], [10, 0], [10, 0], [30, 0]])
    utts = [
        Utterance(1, "AAAA", 10.0),
        Utterance(2, "AAAA", 10.0),
        Utterance(3, "AAAA", 10.0),
        Utterance(4, "AAAA", 100.0),
    ]
    d = make_channel("mj", 5, [0] * 5).deliver(utts, pos2, np.zeros(5), np.random.default_rng(0))
    assert d.heard[0][0].speaker == 4  # loudest first


def test_mj_loss_rate_matches_model():
    n = 60
    ch = make_channel("mj", n, [0] * n, always_heard=0, max_heard=n)
    pos = np.zeros((n, 2))
    pos[1:, 0] = 50.0  # all speakers 50 m from listener 0 -> p_loss 0.5
    pos[1:, 1] = np.linspace(-1e-3, 1e-3, n - 1)
    rng = np.random.default_rng(7)
    heard = 0
    for _ in range(40):
        d = ch.deliver([Utterance(i, "AAAA") for i in range(1, n)], pos, np.zeros(n), rng)
        heard += len(d.heard[0])
    frac = heard / (40 * (n - 1))
    assert 0.45 < frac < 0.55


def test_mj_loss_probability_values():
    p = comms.loss_probability(comms.received_volume(100.0, [25, 40, 50, 60, 75, 100]))
    assert np.allclose(p, [0.041, 0.222, 0.5, 0.778, 0.959, 0.998], atol=1e-3)
    # -6 dB of volume doubles the equivalent distance
    quieter = 100.0 * 10 ** (-6 / 20)
    assert comms.loss_probability(comms.received_volume(quieter, 25.0)) == pytest.approx(0.5)
    assert comms.received_volume(100.0, 0.5) == 100.0  # no gain inside 1 m
    assert comms.received_volume(100.0, 2.0) == pytest.approx(100 * 10 ** (-6 / 20))


def test_mj_max_heard_and_azimuth_integer_degrees():
    n = 12
    ch = make_channel("mj", n, [0] * 6 + [1] * 6)
    rng = np.random.default_rng(0)
    pos = rng.uniform(-3, 3, size=(n, 2))
    d = ch.deliver([Utterance(i, "AAAA") for i in range(n)], pos, rng.uniform(-3, 3, n), rng)
    for hs in d.heard:
        assert len(hs) == 8
        for h in hs:
            deg = math.degrees(h.direction)
            assert abs(deg - round(deg)) < 1e-9 and -180 <= deg < 180
    over = [x for x in d.dropped if x.reason == "max_heard"]
    assert len(over) == n * (n - 1 - 8)


def test_mj_volume_rules():
    ch = make_channel("mj", 2, [0, 1])
    rng = np.random.default_rng(0)
    d = ch.deliver(
        [Utterance(0, "AAAA", 101.0), Utterance(1, "AAAA", float("nan"))],
        _line(2),
        np.zeros(2),
        rng,
    )
    assert d.dropped == [Drop(0, -1, "bad_volume"), Drop(1, -1, "bad_volume")]
    d = ch.deliver([Utterance(0, "AAAA", 0.0)], _line(2), np.zeros(2), rng)
    assert d.dropped == [Drop(0, -1, "inaudible")] and d.heard == [[], []]


def test_lazy_dropped_is_stable():
    ch = make_channel("simspark", 22, [0] * 11 + [1] * 11)
    rng = np.random.default_rng(0)
    d = ch.deliver([Utterance(i, "x") for i in range(22)], _line(22, 0.5), np.zeros(22), rng)
    first = list(d.dropped)
    assert d.dropped == first and len(first) == 22 * 21 - 22 * 2
    assert "Delivery(" in repr(d)


def test_mj_fast_path_matches_generic_order():
    n = 14
    teams = [0] * 7 + [1] * 7
    rng0 = np.random.default_rng(5)
    pos = rng0.uniform(-40, 40, size=(n, 2))
    hd = rng0.uniform(-3, 3, n)
    utts = [Utterance(i, "AAAA", float(rng0.uniform(1, 100))) for i in range(n)]
    fast = make_channel("mj", n, teams, max_heard=6)
    slow = make_channel("mj", n, teams, max_heard=7, self_echo=True)
    for seed in range(10):
        a = fast.deliver(utts, pos, hd, np.random.default_rng(seed))
        b = slow.deliver(utts, pos, hd, np.random.default_rng(seed))
        for i in range(n):
            assert b.heard[i][0].is_self and b.heard[i][0].speaker == i
            assert b.heard[i][1:] == a.heard[i]
            vols = [
                utts[h.speaker].volume / max(1.0, float(np.hypot(*(pos[h.speaker] - pos[i]))))
                for h in a.heard[i]
            ]
            assert vols[:3] == sorted(vols[:3], reverse=True)  # loudest first
        assert {
            (x.speaker, x.listener, x.reason) for x in a.dropped if x.reason != "max_heard"
        } == {(x.speaker, x.listener, x.reason) for x in b.dropped if x.reason != "max_heard"}


def test_drop_counts_match_drop_list():
    for name in ("simspark", "mj"):
        ch = make_channel(name, 22, [0] * 11 + [1] * 11)
        rng = np.random.default_rng(0)
        pos = rng.uniform(-60, 60, size=(22, 2))
        text = "AAAA" if name == "mj" else "x"
        utts = [Utterance(i, text) for i in range(21)] + [Utterance(21, "(" * 30)]
        for _ in range(3):
            d = ch.deliver(utts, pos, np.zeros(22), rng)
            counts = d.drop_counts()
            expected: dict[str, int] = {}
            for x in d.dropped:
                expected[x.reason] = expected.get(x.reason, 0) + 1
            assert counts == expected and d.drop_counts() == expected
