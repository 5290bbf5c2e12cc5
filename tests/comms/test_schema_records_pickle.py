"""A schema's records (namedtuples built at run time) pickle and copy as themselves."""

import copy
import pickle

import cloudpickle

from comms.schema import record_class


def test_records_pickle_copy_and_keep_their_class():
    record = record_class("team_report_7", ("sender", "x", "y"))(3, 1.5, -2.0)
    for clone in (pickle.loads(pickle.dumps(record)), copy.deepcopy(record),
                  cloudpickle.loads(cloudpickle.dumps(record))):
        assert clone == record and type(clone) is type(record)
        assert clone.sender == 3


def test_a_schema_pickles_and_still_encodes_and_decodes():
    from comms.schema import Fixed, Int, Schema

    schema = Schema("pickled_report", [Int("sender", 0, 10), Fixed("x", -5, 5, 0.1)])
    clone = pickle.loads(pickle.dumps(schema))
    text = schema.encode(sender=3, x=1.5)
    assert clone.encode(sender=3, x=1.5) == text
    assert clone.decode(text) == schema.decode(text)
    assert type(clone.decode(text)) is schema.Record
