"""Reads a usar recording with the `rosbags` package (an independent rosbag2 reader and CDR
deserializer of its own): decodes every message, checks the log times never go back, and
prints the counts per topic as JSON."""
import json
import sys
from pathlib import Path

from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

out = {"counts": {}, "monotonic": True}
last = -1
with AnyReader([Path(sys.argv[1])], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as reader:
    for connection, timestamp, raw in reader.messages():
        reader.deserialize(raw, connection.msgtype)
        out["counts"][connection.topic] = out["counts"].get(connection.topic, 0) + 1
        if timestamp < last:
            out["monotonic"] = False
        last = timestamp
print(json.dumps(out))
