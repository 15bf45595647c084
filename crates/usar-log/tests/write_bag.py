"""Writes a rosbag2 (MCAP storage) from a DP-SLAM text log with the `rosbags` package, an
independent writer: /scan (sensor_msgs/LaserScan, frame `laser`), /odom (nav_msgs/Odometry,
`odom` -> `base_link`), /tf_static (`base_link` -> `laser`, 0.2 m ahead). Scan k is stamped
k * 0.2 s, its odometry 1 ms before it.

    python write_bag.py LOG BAG_FOLDER
"""

import math
import sys
from pathlib import Path

import numpy as np
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

ts = get_typestore(Stores.ROS2_HUMBLE)
T = ts.types
Time = T["builtin_interfaces/msg/Time"]
Header = T["std_msgs/msg/Header"]
Point = T["geometry_msgs/msg/Point"]
Quaternion = T["geometry_msgs/msg/Quaternion"]
Vector3 = T["geometry_msgs/msg/Vector3"]
Pose = T["geometry_msgs/msg/Pose"]
LaserScan = T["sensor_msgs/msg/LaserScan"]
Odometry = T["nav_msgs/msg/Odometry"]
TFMessage = T["tf2_msgs/msg/TFMessage"]
Transform = T["geometry_msgs/msg/Transform"]
TransformStamped = T["geometry_msgs/msg/TransformStamped"]
PoseWithCovariance = T["geometry_msgs/msg/PoseWithCovariance"]
Twist = T["geometry_msgs/msg/Twist"]
TwistWithCovariance = T["geometry_msgs/msg/TwistWithCovariance"]


def header(ns, frame):
    return Header(stamp=Time(sec=ns // 10**9, nanosec=ns % 10**9), frame_id=frame)


def yaw_quaternion(yaw):
    return Quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2), w=math.cos(yaw / 2))


def main(log, out):
    records = [line.split() for line in Path(log).read_text().splitlines() if line.strip()]
    with Writer(Path(out), version=8, storage_plugin=StoragePlugin.MCAP) as w:
        scan_c = w.add_connection("/scan", LaserScan.__msgtype__, typestore=ts)
        odom_c = w.add_connection("/odom", Odometry.__msgtype__, typestore=ts)
        tf_c = w.add_connection("/tf_static", TFMessage.__msgtype__, typestore=ts)
        mount = TransformStamped(
            header=header(0, "base_link"),
            child_frame_id="laser",
            transform=Transform(translation=Vector3(x=0.2, y=0.0, z=0.3), rotation=yaw_quaternion(0.0)),
        )
        w.write(tf_c, 0, ts.serialize_cdr(TFMessage(transforms=[mount]), TFMessage.__msgtype__))
        k = 0
        for rec in records:
            ns = 10**9 + k * 200_000_000
            if rec[0] == "Odometry":
                x, y, theta = map(float, rec[1:4])
                pose = Pose(position=Point(x=x, y=y, z=0.0), orientation=yaw_quaternion(theta))
                msg = Odometry(
                    header=header(ns - 1_000_000, "odom"),
                    child_frame_id="base_link",
                    pose=PoseWithCovariance(pose=pose, covariance=np.zeros(36)),
                    twist=TwistWithCovariance(
                        twist=Twist(linear=Vector3(x=0.0, y=0.0, z=0.0), angular=Vector3(x=0.0, y=0.0, z=0.0)),
                        covariance=np.zeros(36),
                    ),
                )
                w.write(odom_c, ns - 1_000_000, ts.serialize_cdr(msg, Odometry.__msgtype__))
            elif rec[0] == "Laser":
                n = int(rec[1])
                ranges = np.array([float(v) for v in rec[2 : 2 + n]], dtype=np.float32)
                msg = LaserScan(
                    header=header(ns, "laser"),
                    angle_min=-math.pi / 2,
                    angle_max=math.pi / 2,
                    angle_increment=math.pi / (n - 1),
                    time_increment=0.0,
                    scan_time=0.2,
                    range_min=0.05,
                    range_max=8.1,
                    ranges=ranges,
                    intensities=np.zeros(0, dtype=np.float32),
                )
                w.write(scan_c, ns, ts.serialize_cdr(msg, LaserScan.__msgtype__))
                k += 1


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
