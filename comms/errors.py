"""Exception types of the comms package (all subclass ValueError)."""


class CommsError(ValueError):
    """Base class of every error raised by the comms package."""


class ChannelError(CommsError):
    """A channel was built or driven with invalid arguments (unknown profile, bad speaker id...)."""


class SchemaError(CommsError):
    """A message schema or one of its fields is declared inconsistently."""


class BudgetError(SchemaError):
    """A schema needs more bits than the channel's budget allows (raised at declaration)."""


class EncodeError(CommsError):
    """A value cannot be encoded by a field (out of range, wrong type, not a permutation...)."""


class DecodeError(CommsError):
    """A received text is not a valid encoding of the expected message (corrupt or foreign)."""
