"""StatePerception.observe (scratch buffers, one rotation for players and ball) gives, bit
for bit, what the plain formulas of the observation layout give."""

import numpy as np
import pytest

from teamenv.box_layout import HEARD_DIM, N_PLAY_MODES, PLAYER_DIM
from teamenv.sim.perception import StatePerception
from teamenv.sim.playmode import PlayMode


def _wrap(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def reference_rows(N, K, poses, vel, ball, fallen, mode, time_s, half, score, sign_of_team,
                   heard_info):
    """The flat rows, written out formula by formula (float64, before the float32 cast)."""
    n = 2 * N
    team_of = np.repeat([0, 1], N)
    sign = np.asarray(sign_of_team, dtype=float)[team_of]
    x, y, h = poses[:, 0], poses[:, 1], poses[:, 2]
    c, s = np.cos(h), np.sin(h)
    cols = [np.arange(n), np.r_[np.arange(N, n), np.arange(N)]]
    rows = []
    for i in range(n):
        me = [sign[i] * x[i], sign[i] * y[i], h[i] if sign[i] > 0 else _wrap(h[i] + np.pi),
              sign[i] * vel[i, 0], sign[i] * vel[i, 1], vel[i, 2], fallen[i]]
        bdx, bdy = ball[0] - x[i], ball[1] - y[i]
        b = [c[i] * bdx + s[i] * bdy, -s[i] * bdx + c[i] * bdy,
             c[i] * ball[2] + s[i] * ball[3], -s[i] * ball[2] + c[i] * ball[3]]
        players = []
        for j in cols[team_of[i]]:
            dx, dy = x[j] - x[i], y[j] - y[i]
            players += [c[i] * dx + s[i] * dy, -s[i] * dx + c[i] * dy,
                        _wrap(h[j] - h[i]), fallen[j], 1.0]
        onehot = [0.0] * N_PLAY_MODES
        onehot[int(mode.for_team(team_of[i]))] = 1.0
        game = [time_s, half, score[team_of[i]], score[1 - team_of[i]]]
        rows.append(np.array(me + b + players + onehot + game
                             + list(heard_info[i].ravel()), dtype=float))
    return np.array(rows)


@pytest.mark.parametrize(("N", "K"), [(11, 3), (7, 8), (1, 3)])
def test_observe_matches_the_formulas(N, K):
    rng = np.random.default_rng(N)
    perception = StatePerception(N, K)
    n = 2 * N
    for it in range(60):
        poses = np.column_stack([rng.uniform(-15, 15, (n, 2)), rng.uniform(-4, 4, n)])
        vel = rng.normal(0, 1, (n, 3))
        ball = rng.normal(0, 5, 4)
        fallen = (rng.random(n) < 0.2).astype(float)
        mode = PlayMode(int(rng.integers(0, len(PlayMode)))) if it % 3 else PlayMode.PlayOn
        sign = [1.0, -1.0] if it < 30 else [-1.0, 1.0]
        score = [int(rng.integers(0, 3)), int(rng.integers(0, 3))]
        heard = rng.normal(0, 1, (n, K, HEARD_DIM))
        texts = [("",) * K] * n
        args = (poses, vel, ball, fallen, mode, it * 0.02, 1 + it % 2, score, sign, heard, texts)
        expected = reference_rows(N, K, *args[:-1]).astype(np.float32)
        flat = np.array(perception.observe(*args, flat=True))
        assert flat.tobytes() == expected.tobytes(), it
        dicts = perception.observe(*args)
        lazy = perception.observe(*args, lazy=True)
        for i in range(n):
            row = expected[i]
            players = row[11:11 + n * PLAYER_DIM].reshape(n, PLAYER_DIM)
            for obs in (dicts[i], lazy[i]):
                assert obs["self"].tobytes() == row[:7].tobytes()
                assert obs["ball"].tobytes() == row[7:11].tobytes()
                assert obs["teammates"].tobytes() == players[:N].tobytes()
                assert obs["opponents"].tobytes() == players[N:].tobytes()
                assert obs["heard"].shape == (K, HEARD_DIM)
