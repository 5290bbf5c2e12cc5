"""The examples of docs/readme/comms.md, run as tests so the README cannot drift."""

from comms.schema import Bool, Enum, Fixed, Permutation, Schema
from comms.testing import assert_fits, check_corruption, check_roundtrip

MY_MSG = Schema(
    "my_msg",
    [
        Permutation("roles", 11),
        Fixed("ball_x", -16, 16, 0.1, clip=True),
        Fixed("ball_y", -11, 11, 0.1, clip=True),
        Enum("intent", ["hold", "pass", "shoot"]),
        Bool("fallen"),
    ],
    channel="simspark",
    check_bits=6,
)


def test_readme_example_values():
    text = MY_MSG.encode(
        roles=[1, 0, 2, 3, 4, 5, 6, 7, 8, 9, 10],
        ball_x=3.14,
        ball_y=-2.0,
        intent="pass",
        fallen=False,
    )
    assert text == "kK0vw3XwA"
    msg = MY_MSG.decode(text)
    assert msg.roles == (1, 0, 2, 3, 4, 5, 6, 7, 8, 9, 10) and msg.ball_x == 3.1
    layout = MY_MSG.layout()
    assert "52 bits (43.9 bits of information), codec base64, 9 chars, budget 120 bits" in layout
    assert "    46     6  (check)          CRC-32, low 6 bits" in layout


def test_fits_both_channels():
    assert_fits(MY_MSG, channel="simspark")
    assert_fits(MY_MSG, channel="mj")


def test_roundtrip():
    check_roundtrip(MY_MSG, n=500)


def test_corrupt_texts_are_rejected_or_legal():
    assert check_corruption(MY_MSG, n=500)["rejected"] > 450
