"""Reads a usar recording with the MCAP project's own Python readers (mcap and
mcap-ros2-support, independent of usar): decodes every message and prints what it found as
JSON."""
import json
import sys

from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

out = {"counts": {}}
with open(sys.argv[1], "rb") as f:
    reader = make_reader(f, decoder_factories=[DecoderFactory()])
    out["profile"] = reader.get_header().profile
    for schema, channel, message, msg in reader.iter_decoded_messages():
        topic = channel.topic
        out["counts"][topic] = out["counts"].get(topic, 0) + 1
        out.setdefault("schemas", {})[topic] = schema.name
        if topic == "/clock":
            out["last_clock_s"] = msg.clock.sec + msg.clock.nanosec * 1e-9
            out["last_log_time_s"] = message.log_time * 1e-9
        elif topic == "/tf" and "tf" not in out:
            out["tf"] = {
                "parents": sorted({t.header.frame_id for t in msg.transforms}),
                "children": sorted(t.child_frame_id for t in msg.transforms),
                "unit_quaternions": all(
                    abs(t.transform.rotation.z ** 2 + t.transform.rotation.w ** 2 - 1) < 1e-9
                    for t in msg.transforms
                ),
            }
        elif topic.endswith("/scan") and "scan" not in out:
            out["scan"] = {
                "frame": msg.header.frame_id,
                "beams": len(msg.ranges),
                "range_max": msg.range_max,
                "returns": sum(1 for r in msg.ranges if r <= msg.range_max),
            }
        elif topic == "/map":
            out["map"] = {
                "width": msg.info.width,
                "height": msg.info.height,
                "cells": len(msg.data),
                "resolution": msg.info.resolution,
                "known": sum(1 for v in msg.data if v >= 0),
                "values": sorted(set(msg.data)),
            }
        elif topic == "/btm":
            out["btm_markers"] = len(msg.markers)
        elif topic.endswith("/odom") and "odom" not in out:
            out["odom"] = {"frame": msg.header.frame_id, "child": msg.child_frame_id}
print(json.dumps(out))
