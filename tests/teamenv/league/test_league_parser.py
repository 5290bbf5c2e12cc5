"""League client, offline: S-expressions, every perceptor on recorded real server messages,
framing, effector encoding; fuzzed with hypothesis."""

from __future__ import annotations

import base64
import math
import socket
import threading
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from teamenv.league import effectors
from teamenv.league.errors import ProtocolError, ServerDiedError, UnknownPerceptorError
from teamenv.league.framing import MAX_FRAME_BYTES, encode_frame, read_frame, split_frames
from teamenv.league.perception import PERCEPTORS, parse_perception
from teamenv.league.sexp import parse_all, to_text

DATA = Path(__file__).resolve().parents[1] / "league_data"
RECORDED = sorted(DATA.glob("*.txt"))
T1_JOINTS = 23


def _recorded(name: str) -> str:
    return (DATA / name).read_text().strip()


# -- recorded real messages (python -m teamenv.league.record tests/teamenv/league_data) -----
def test_recorded_messages_exist():
    assert {p.name for p in RECORDED} >= {"first.txt", "heard.txt", "kick_off.txt",
                                         "no_vision.txt", "vision_players_ball.txt"}


@pytest.mark.parametrize("path", RECORDED, ids=lambda p: p.name)
def test_every_recorded_message_parses_strictly(path):
    p = parse_perception(path.read_text().strip(), strict=True)
    assert p.time is not None and p.time > 0
    assert p.game is not None and p.game.team_left == "Alpha"
    assert set(p.positions) == {"torso_pos"} and set(p.orientations) == {"torso_quat"}
    assert set(p.gyros) == {"torso_gyro"} and set(p.accelerometers) == {"torso_acc"}
    assert len(p.joints) == T1_JOINTS and all(name.startswith("q_") for name in p.joints)
    w, x, y, z = p.orientations["torso_quat"]
    assert math.isclose(w * w + x * x + y * y + z * z, 1.0, abs_tol=0.01)
    assert p.unknown == []


def test_first_message_values():
    p = parse_perception(_recorded("first.txt"))
    assert p.game.play_mode == "BeforeKickOff" and (p.game.score_left, p.game.score_right) == (0, 0)
    assert p.vision is not None and p.vision.ball is not None
    # the server sends degrees; we hold radians
    text = _recorded("first.txt")
    ball_deg = float(text.split("(B (pol ")[1].split()[1])
    assert math.isclose(p.vision.ball.azimuth, math.radians(ball_deg))
    assert all(abs(o.azimuth) <= math.radians(60.0) + 1e-9 for o in p.vision.objects.values())


def test_vision_with_a_player_and_the_ball():
    p = parse_perception(_recorded("vision_players_ball.txt"))
    seen = {(s.team, s.unum): s for s in p.vision.players}
    assert set(seen) <= {("Alpha", 1), ("Alpha", 2)} and ("Alpha", 1) in seen
    seen = seen[("Alpha", 1)]
    assert set(seen.parts) == {"head", "lfoot", "rfoot"}
    assert 10 < seen.parts["head"].distance < 40
    assert p.game.team_right == "Beta"


def test_heard_message_is_decoded_with_its_direction():
    p = parse_perception(_recorded("heard.txt"))
    (heard,) = p.heard
    assert heard.payload == b"hello"
    assert math.isclose(heard.azimuth, math.radians(174.0))


def test_vision_comes_every_second_cycle_and_kick_off_is_seen():
    assert parse_perception(_recorded("no_vision.txt")).vision is None
    assert parse_perception(_recorded("kick_off.txt")).game.play_mode == "KickOff_Left"


# -- every perceptor kind, including those the T1 does not send --------------------------
def test_touch_and_joint_state_forms():
    p = parse_perception("(TCH n lf val 1)(TCH n rf val 0)"
                         "(JS (names a b) (axs 90 -45) (vxs 0 180))")
    assert p.touches == {"lf": True, "rf": False}
    assert math.isclose(p.joints["a"].angle, math.pi / 2)
    assert math.isclose(p.joints["b"].velocity, math.pi)
    assert set(PERCEPTORS) == {"time", "GS", "pos", "quat", "GYR", "ACC", "TCH", "HJ", "JS",
                               "See", "MIC"}


def test_unknown_perceptor_strict_and_lenient():
    text = _recorded("first.txt") + "(FRP (n lf) (c 0 0 0) (f 0 0 1))"
    with pytest.raises(UnknownPerceptorError, match="agent left_3: unknown perceptor 'FRP'"):
        parse_perception(text, who="agent left_3")
    p = parse_perception(text, strict=False)
    assert p.unknown == [["FRP", ["n", "lf"], ["c", "0", "0", "0"], ["f", "0", "0", "1"]]]
    assert len(p.joints) == T1_JOINTS


@pytest.mark.parametrize("text, needle", [
    ("(time (now abc))", "perceptor time: expected a number, got 'abc'"),
    ("(GS (t 0)(pm PlayOn)(sl 0))", r"missing \(sr"),
    ("(HJ (n he1)(ax nan)(vx 0))", "not finite"),
    ("(See (B (pol 1 2)))", r"perceptor See B: expected \(pol \+ 3 values\)"),
    ("(See (P (id 3)(head (pol 1 2 3))))", "player without"),
    ("(MIC hear (10 !!notbase64))", "is not base64"),
    ("(time (now 1)", "unclosed"),
    ("(time (now 1)))", "unbalanced"),
    ("time", "is not a"),
])
def test_malformed_perceptors_name_the_perceptor(text, needle):
    with pytest.raises(ProtocolError, match=needle):
        parse_perception(text)


# -- fuzzing --------------------------------------------------------------------------------
_atoms = st.text(alphabet=st.characters(min_codepoint=33, max_codepoint=126,
                                        blacklist_characters="()"), min_size=1, max_size=8)
_trees = st.recursive(_atoms, lambda kids: st.lists(kids, max_size=4), max_leaves=12)
# the machine is shared and slow: data generation time is not what these tests check
_relaxed = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@_relaxed
@given(st.lists(_trees.filter(lambda t: isinstance(t, list)), max_size=4))
def test_sexp_round_trip(exprs):
    text = "".join(to_text(e) for e in exprs)
    assert parse_all(text) == exprs


@_relaxed
@given(st.text(alphabet="() abc1.-\n", max_size=60))
def test_sexp_reader_raises_only_protocol_errors(text):
    try:
        parse_all(text)
    except ProtocolError:
        pass


_finite = st.floats(-1e4, 1e4, allow_nan=False).map(lambda v: round(v, 2))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(t=st.floats(0, 600).map(lambda v: round(v, 2)), gyro=st.tuples(_finite, _finite, _finite),
       joint=st.tuples(_finite, _finite), ball=st.tuples(st.floats(0, 80).map(lambda v: round(v, 2)),
                                                        _finite, _finite),
       payload=st.binary(min_size=1, max_size=10), az=st.integers(-180, 180),
       unum=st.integers(1, 99), mode=st.sampled_from(["BeforeKickOff", "PlayOn", "Goal_Left"]))
def test_generated_messages_in_the_server_format_parse_to_their_values(
        t, gyro, joint, ball, payload, az, unum, mode):
    b64 = base64.b64encode(payload).decode()
    text = (f"(time (now {t}))(GS (t {t})(pm {mode})(tl A)(tr B)(sl 1)(sr 2))"
            f"(GYR (n torso_gyro) (rt {gyro[0]} {gyro[1]} {gyro[2]}))"
            f"(HJ (n q_hj1)(ax {joint[0]})(vx {joint[1]}))"
            f"(See (B (pol {ball[0]} {ball[1]} {ball[2]}))(P (team B)(id {unum})"
            f"(head (pol 1.0 2.0 3.0))))(MIC hear ({az} {b64}))")
    p = parse_perception(text)
    assert p.time == t and p.game.play_mode == mode and p.game.score_right == 2
    assert p.gyros["torso_gyro"] == tuple(math.radians(g) for g in gyro)
    assert p.joints["q_hj1"].angle == math.radians(joint[0])
    assert p.vision.ball.distance == ball[0]
    assert p.vision.ball.azimuth == math.radians(ball[1])
    assert p.vision.players[0].unum == unum
    assert p.heard[0].payload == payload and p.heard[0].azimuth == math.radians(az)


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_mutated_real_messages_parse_or_raise_protocol_errors(data):
    text = _recorded(data.draw(st.sampled_from([p.name for p in RECORDED])))
    i = data.draw(st.integers(0, len(text) - 1))
    j = data.draw(st.integers(i, min(len(text), i + 20)))
    junk = data.draw(st.text(alphabet="() abcXYZ019.-e", max_size=6))
    try:
        parse_perception(text[:i] + junk + text[j:], strict=data.draw(st.booleans()))
    except ProtocolError:
        pass


# -- framing --------------------------------------------------------------------------------
@_relaxed
@given(st.lists(st.binary(max_size=300), max_size=6), st.integers(0, 8))
def test_frames_split_back_into_their_payloads(payloads, cut):
    stream = b"".join(encode_frame(p) for p in payloads)
    head, rest = split_frames(stream[:len(stream) - cut] if cut else stream)
    assert head == (payloads if not cut else head) and payloads[:len(head)] == head
    if not cut:
        assert rest == b""


def test_frame_prefix_is_four_byte_big_endian():
    assert encode_frame(b"(syn)") == b"\x00\x00\x00\x05(syn)"
    with pytest.raises(ProtocolError, match="exceeds"):
        split_frames((MAX_FRAME_BYTES + 1).to_bytes(4, "big") + b"x")


def _served(data: bytes):
    a, b = socket.socketpair()
    threading.Thread(target=lambda: (b.sendall(data), b.close()), daemon=True).start()
    return a


def test_read_frame_reports_truncation_and_closing():
    with _served(encode_frame(b"(time (now 1))")) as s:
        assert read_frame(s) == b"(time (now 1))"
        with pytest.raises(ServerDiedError, match="closed the connection"):
            read_frame(s, "agent A_1")
    with _served(encode_frame(b"(time (now 1))")[:9]) as s, \
            pytest.raises(ProtocolError, match="agent A_1: truncated frame: the payload ended after 5 of 14"):
        read_frame(s, "agent A_1")
    with _served(b"\x00\x00") as s, pytest.raises(ProtocolError, match="length prefix ended after 2"):
        read_frame(s)
    with _served(b"\xff\xff\xff\xff") as s, pytest.raises(ProtocolError, match="exceeds"):
        read_frame(s)


# -- effectors ------------------------------------------------------------------------------
def test_effector_encoding():
    assert effectors.init("Alpha", 7) == "(init T1 Alpha 7)"
    assert effectors.beam(-3.0, 1.5, math.pi / 6) == "(beam -3 1.5 30)"
    assert effectors.motor("lle4", math.pi / 2, 0.0, 50.0, 1.5) == "(lle4 90 0 50 1.5 0)"
    assert effectors.say(b"hello") == "(SPK say 100 aGVsbG8=)"
    assert effectors.message() == "(syn)"
    assert effectors.message(effectors.beam(0, 0, 0), "(syn)") == "(beam 0 0 0)(syn)"
    # the server's own parser reads what we write
    assert parse_all(effectors.motor("he1", 0.1, 0.2, 1, 2, 3))[0][0] == "he1"


@pytest.mark.parametrize("call, needle", [
    (lambda: effectors.say(b"12345678901"), "payload of 11 bytes"),
    (lambda: effectors.say(b""), "payload of 0 bytes"),
    (lambda: effectors.say("text"), "must be bytes"),
    (lambda: effectors.say(b"x", volume=101), "volume 101"),
    (lambda: effectors.beam(float("nan"), 0, 0), "beam x: nan is not finite"),
    (lambda: effectors.motor("he1 (x)", 0), "motor name"),
    (lambda: effectors.motor("he1", "a"), "motor 'he1' q: 'a' is not a number"),
    (lambda: effectors.init("Alpha", 0), "uniform number 0"),
    (lambda: effectors.init("Al pha", 1), "init team"),
    (lambda: effectors.init("Alpha", 1, model="NAO"), "model 'NAO'"),
])
def test_bad_effector_requests_name_field_and_value(call, needle):
    with pytest.raises(effectors.EffectorError, match=needle):
        call()


@_relaxed
@given(st.binary(min_size=1, max_size=10), st.floats(0, 100))
def test_say_round_trips_through_the_servers_format(payload, volume):
    _, name, vol, b64 = parse_all(effectors.say(payload, volume))[0]
    assert name == "say" and 0 <= float(vol) <= 100
    assert base64.b64decode(b64, validate=True) == payload
