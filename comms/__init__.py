"""Say-channel rules, hearing model and bit-packing codecs; must not import teamenv, strategy or locomotion.

A leaf package (numpy only). Public API: `make_channel`, `Channel`, `Utterance`, `Heard`,
`Drop`, `Delivery`, the profiles `SIMSPARK` / `MJ` (`PROFILES`, `get_profile`), and the
exception types; schemas (`Schema`, `Int`, `Bool`, `Enum`, `Fixed`, `Permutation`, `Array`,
`decode_any`); the shipped message types in `comms.messages` (e.g.
`comms.messages.role_vector_schema(11)`); the seed-002 grid world in `comms.gridworld`; test
helpers in `comms.testing` and the pytest plugin `comms.pytest_plugin`.
"""

from comms import messages  # declares the shipped schemas
from comms.channel import (
    REASON_CAPACITY,
    REASON_INAUDIBLE,
    REASON_LOST,
    REASON_MAX_HEARD,
    REASON_OUT_OF_RANGE,
    Channel,
    make_channel,
)
from comms.delivery import Delivery, Drop, Heard, Utterance
from comms.errors import (
    BudgetError,
    ChannelError,
    CommsError,
    DecodeError,
    EncodeError,
    SchemaError,
)
from comms.hearing import hearing_capacity_trace, loss_probability, received_volume
from comms.profiles import (
    BASE64_ALPHABET,
    MJ,
    PROFILES,
    REASON_BAD_BASE64,
    REASON_BAD_VOLUME,
    REASON_ILLEGAL_CHARACTER,
    REASON_NOT_A_STRING,
    REASON_TOO_LONG,
    SIMSPARK,
    SIMSPARK_CHARSET,
    ChannelProfile,
    HearingCapacity,
    get_profile,
)
from comms.schema import Array, Bool, Enum, Field, Fixed, Int, Permutation, Schema, decode_any

__all__ = [
    "Array",
    "Bool",
    "Enum",
    "Field",
    "Fixed",
    "Int",
    "Permutation",
    "Schema",
    "decode_any",
    "messages",
    "BASE64_ALPHABET",
    "MJ",
    "PROFILES",
    "REASON_BAD_BASE64",
    "REASON_BAD_VOLUME",
    "REASON_CAPACITY",
    "REASON_ILLEGAL_CHARACTER",
    "REASON_INAUDIBLE",
    "REASON_LOST",
    "REASON_MAX_HEARD",
    "REASON_NOT_A_STRING",
    "REASON_OUT_OF_RANGE",
    "REASON_TOO_LONG",
    "SIMSPARK",
    "SIMSPARK_CHARSET",
    "BudgetError",
    "Channel",
    "ChannelError",
    "ChannelProfile",
    "CommsError",
    "DecodeError",
    "Delivery",
    "Drop",
    "EncodeError",
    "HearingCapacity",
    "Heard",
    "SchemaError",
    "Utterance",
    "get_profile",
    "hearing_capacity_trace",
    "loss_probability",
    "make_channel",
    "received_volume",
]
