"""An independent ROS 2 peer without ROS: Eclipse Cyclone DDS (the PyPI `cyclonedds`
package, the DDS under ROS 2's default rmw) with ROS 2's DDS names ("rt/scan") and types
("sensor_msgs::msg::dds_::LaserScan_"), declared here from the .msg definitions.

    python dds_peer.py sim SECONDS
        counts /scan for SECONDS and prints the rate; meanwhile sends Twist on /cmd_vel
        (0.3 m/s, 0.2 rad/s) at 10 Hz; prints one JSON line.
    python dds_peer.py replay LOG HZ
        replays a DP-SLAM log (Odometry / Laser pairs) as /odom and /scan at HZ and counts
        the geometry_msgs/PoseStamped received on /goal_pose; prints one JSON line.

Run it with CYCLONEDDS_URI pointing at cyclone-loopback.xml and ROS_DOMAIN_ID set.
"""

import json
import math
import os
import sys
import time
from dataclasses import dataclass

from cyclonedds.core import Policy, Qos
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.idl.types import array, float32, float64, int32, sequence, uint32
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration


@dataclass
class Time(IdlStruct, typename="builtin_interfaces.msg.dds_.Time_"):
    sec: int32
    nanosec: uint32


@dataclass
class Header(IdlStruct, typename="std_msgs.msg.dds_.Header_"):
    stamp: Time
    frame_id: str


@dataclass
class LaserScan(IdlStruct, typename="sensor_msgs.msg.dds_.LaserScan_"):
    header: Header
    angle_min: float32
    angle_max: float32
    angle_increment: float32
    time_increment: float32
    scan_time: float32
    range_min: float32
    range_max: float32
    ranges: sequence[float32]
    intensities: sequence[float32]


@dataclass
class Vector3(IdlStruct, typename="geometry_msgs.msg.dds_.Vector3_"):
    x: float64
    y: float64
    z: float64


@dataclass
class Point(IdlStruct, typename="geometry_msgs.msg.dds_.Point_"):
    x: float64
    y: float64
    z: float64


@dataclass
class Quaternion(IdlStruct, typename="geometry_msgs.msg.dds_.Quaternion_"):
    x: float64
    y: float64
    z: float64
    w: float64


@dataclass
class Pose(IdlStruct, typename="geometry_msgs.msg.dds_.Pose_"):
    position: Point
    orientation: Quaternion


@dataclass
class PoseWithCovariance(IdlStruct, typename="geometry_msgs.msg.dds_.PoseWithCovariance_"):
    pose: Pose
    covariance: array[float64, 36]


@dataclass
class Twist(IdlStruct, typename="geometry_msgs.msg.dds_.Twist_"):
    linear: Vector3
    angular: Vector3


@dataclass
class TwistWithCovariance(IdlStruct, typename="geometry_msgs.msg.dds_.TwistWithCovariance_"):
    twist: Twist
    covariance: array[float64, 36]


@dataclass
class Odometry(IdlStruct, typename="nav_msgs.msg.dds_.Odometry_"):
    header: Header
    child_frame_id: str
    pose: PoseWithCovariance
    twist: TwistWithCovariance


@dataclass
class PoseStamped(IdlStruct, typename="geometry_msgs.msg.dds_.PoseStamped_"):
    header: Header
    pose: Pose


SENSOR = Qos(Policy.Reliability.BestEffort, Policy.Durability.Volatile, Policy.History.KeepLast(5))
RELIABLE = Qos(
    Policy.Reliability.Reliable(duration(milliseconds=100)),
    Policy.Durability.Volatile,
    Policy.History.KeepLast(10),
)


def stamp(t):
    return Time(sec=int(t), nanosec=int((t - int(t)) * 1e9))


def sim(dp, seconds):
    scans = DataReader(dp, Topic(dp, "rt/scan", LaserScan), qos=SENSOR)
    cmd = DataWriter(dp, Topic(dp, "rt/cmd_vel", Twist), qos=RELIABLE)
    t0 = time.monotonic()
    first = None
    while time.monotonic() - t0 < 20 and first is None:
        got = scans.take(N=100)
        first = got[-1] if got else None
        time.sleep(0.01)
    if first is None:
        print(json.dumps({"error": "no /scan within 20 s"}))
        return
    count, beams, t1 = 0, len(first.ranges), time.monotonic()
    next_cmd = t1
    while time.monotonic() - t1 < seconds:
        count += len(scans.take(N=100))
        if time.monotonic() >= next_cmd:
            cmd.write(Twist(linear=Vector3(0.3, 0.0, 0.0), angular=Vector3(0.0, 0.0, 0.2)))
            next_cmd += 0.1
        time.sleep(0.005)
    rate = count / (time.monotonic() - t1)
    print(json.dumps({"scan_hz": rate, "beams": beams, "frame": first.header.frame_id}))


def replay(dp, log, hz):
    odom_w = DataWriter(dp, Topic(dp, "rt/odom", Odometry), qos=RELIABLE)
    scan_w = DataWriter(dp, Topic(dp, "rt/scan", LaserScan), qos=SENSOR)
    goals = DataReader(dp, Topic(dp, "rt/goal_pose", PoseStamped), qos=RELIABLE)
    t0 = time.monotonic()
    while not scan_w.get_matched_subscriptions() and time.monotonic() - t0 < 20:
        time.sleep(0.05)
    received = []
    k = 0
    odom = None
    for line in open(log):
        f = line.split()
        if not f:
            continue
        if f[0] == "Odometry":
            x, y, th = map(float, f[1:4])
            q = Quaternion(0.0, 0.0, math.sin(th / 2), math.cos(th / 2))
            odom = Odometry(
                header=Header(stamp=stamp(k / hz), frame_id="odom"),
                child_frame_id="base_link",
                pose=PoseWithCovariance(pose=Pose(Point(x, y, 0.0), q), covariance=[0.0] * 36),
                twist=TwistWithCovariance(
                    twist=Twist(Vector3(0.0, 0.0, 0.0), Vector3(0.0, 0.0, 0.0)), covariance=[0.0] * 36
                ),
            )
        elif f[0] == "Laser" and odom is not None:
            n = int(f[1])
            ranges = [float(v) for v in f[2 : 2 + n]]
            odom_w.write(odom)
            time.sleep(0.002)
            scan_w.write(
                LaserScan(
                    header=Header(stamp=stamp(k / hz), frame_id="laser"),
                    angle_min=-math.pi / 2,
                    angle_max=math.pi / 2,
                    angle_increment=math.pi / (n - 1),
                    time_increment=0.0,
                    scan_time=1.0 / hz,
                    range_min=0.05,
                    range_max=8.1,
                    ranges=ranges,
                    intensities=[],
                )
            )
            k += 1
            received += goals.take(N=100)
            time.sleep(1.0 / hz)
    end = time.monotonic() + 3
    while time.monotonic() < end:
        received += goals.take(N=100)
        time.sleep(0.05)
    last = received[-1] if received else None
    print(
        json.dumps(
            {
                "scans_sent": k,
                "goals": len(received),
                "frame": last.header.frame_id if last else None,
                "last_goal": [last.pose.position.x, last.pose.position.y] if last else None,
            }
        )
    )


def main():
    dp = DomainParticipant(int(os.environ.get("ROS_DOMAIN_ID", "0")))
    if sys.argv[1] == "sim":
        sim(dp, float(sys.argv[2]))
    else:
        replay(dp, sys.argv[2], float(sys.argv[3]))


if __name__ == "__main__":
    main()
