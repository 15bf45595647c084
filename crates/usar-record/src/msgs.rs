//! The ROS 2 messages a recording holds: their definitions (`ros2msg` schemas, each with its
//! dependencies after a line of `=` and `MSG: package/Type`, as `ros2 bag` and Foxglove write
//! them) and their encoders. Field for field the definitions of ROS 2 (Foxy's `Marker`, without
//! the later texture and mesh-file fields).

use crate::cdr::CdrWriter;

const TIME: &str = "int32 sec\nuint32 nanosec\n";
const DURATION: &str = "int32 sec\nuint32 nanosec\n";
const HEADER: &str = "builtin_interfaces/Time stamp\nstring frame_id\n";
const VECTOR3: &str = "float64 x\nfloat64 y\nfloat64 z\n";
const POINT: &str = "float64 x\nfloat64 y\nfloat64 z\n";
const QUATERNION: &str = "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n";
const POSE: &str = "Point position\nQuaternion orientation\n";
const TRANSFORM: &str = "Vector3 translation\nQuaternion rotation\n";
const TRANSFORM_STAMPED: &str =
    "std_msgs/Header header\nstring child_frame_id\nTransform transform\n";
const COLOR: &str = "float32 r\nfloat32 g\nfloat32 b\nfloat32 a\n";

/// A message type: its name and its full definition.
pub struct MsgType {
    pub name: &'static str,
    pub definition: String,
}

fn definition(main: &str, deps: &[(&str, &str)]) -> String {
    let mut text = main.to_string();
    for (name, def) in deps {
        text.push_str(&"=".repeat(80));
        text.push_str(&format!("\nMSG: {name}\n{def}"));
    }
    text
}

pub fn clock_type() -> MsgType {
    MsgType {
        name: "rosgraph_msgs/msg/Clock",
        definition: definition(
            "builtin_interfaces/Time clock\n",
            &[("builtin_interfaces/Time", TIME)],
        ),
    }
}

pub fn tf_type() -> MsgType {
    MsgType {
        name: "tf2_msgs/msg/TFMessage",
        definition: definition(
            "geometry_msgs/TransformStamped[] transforms\n",
            &[
                ("geometry_msgs/TransformStamped", TRANSFORM_STAMPED),
                ("std_msgs/Header", HEADER),
                ("builtin_interfaces/Time", TIME),
                ("geometry_msgs/Transform", TRANSFORM),
                ("geometry_msgs/Vector3", VECTOR3),
                ("geometry_msgs/Quaternion", QUATERNION),
            ],
        ),
    }
}

pub fn laser_scan_type() -> MsgType {
    MsgType {
        name: "sensor_msgs/msg/LaserScan",
        definition: definition(
            "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n\
             float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\n\
             float32[] ranges\nfloat32[] intensities\n",
            &[
                ("std_msgs/Header", HEADER),
                ("builtin_interfaces/Time", TIME),
            ],
        ),
    }
}

pub fn odometry_type() -> MsgType {
    MsgType {
        name: "nav_msgs/msg/Odometry",
        definition: definition(
            "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n\
             geometry_msgs/TwistWithCovariance twist\n",
            &[
                ("std_msgs/Header", HEADER),
                ("builtin_interfaces/Time", TIME),
                (
                    "geometry_msgs/PoseWithCovariance",
                    "Pose pose\nfloat64[36] covariance\n",
                ),
                ("geometry_msgs/Pose", POSE),
                ("geometry_msgs/Point", POINT),
                ("geometry_msgs/Quaternion", QUATERNION),
                (
                    "geometry_msgs/TwistWithCovariance",
                    "Twist twist\nfloat64[36] covariance\n",
                ),
                ("geometry_msgs/Twist", "Vector3 linear\nVector3 angular\n"),
                ("geometry_msgs/Vector3", VECTOR3),
            ],
        ),
    }
}

pub fn occupancy_grid_type() -> MsgType {
    MsgType {
        name: "nav_msgs/msg/OccupancyGrid",
        definition: definition(
            "std_msgs/Header header\nMapMetaData info\nint8[] data\n",
            &[
                ("std_msgs/Header", HEADER),
                ("builtin_interfaces/Time", TIME),
                (
                    "nav_msgs/MapMetaData",
                    "builtin_interfaces/Time map_load_time\nfloat32 resolution\nuint32 width\n\
                     uint32 height\ngeometry_msgs/Pose origin\n",
                ),
                ("geometry_msgs/Pose", POSE),
                ("geometry_msgs/Point", POINT),
                ("geometry_msgs/Quaternion", QUATERNION),
            ],
        ),
    }
}

pub fn marker_array_type() -> MsgType {
    MsgType {
        name: "visualization_msgs/msg/MarkerArray",
        definition: definition(
            "Marker[] markers\n",
            &[
                (
                    "visualization_msgs/Marker",
                    "int32 ARROW=0\nint32 CUBE=1\nint32 SPHERE=2\nint32 CYLINDER=3\n\
                     int32 LINE_STRIP=4\nint32 LINE_LIST=5\nint32 CUBE_LIST=6\n\
                     int32 SPHERE_LIST=7\nint32 POINTS=8\nint32 TEXT_VIEW_FACING=9\n\
                     int32 MESH_RESOURCE=10\nint32 TRIANGLE_LIST=11\nint32 ADD=0\n\
                     int32 MODIFY=0\nint32 DELETE=2\nint32 DELETEALL=3\n\
                     std_msgs/Header header\nstring ns\nint32 id\nint32 type\nint32 action\n\
                     geometry_msgs/Pose pose\ngeometry_msgs/Vector3 scale\n\
                     std_msgs/ColorRGBA color\nbuiltin_interfaces/Duration lifetime\n\
                     bool frame_locked\ngeometry_msgs/Point[] points\n\
                     std_msgs/ColorRGBA[] colors\nstring text\nstring mesh_resource\n\
                     bool mesh_use_embedded_materials\n",
                ),
                ("std_msgs/Header", HEADER),
                ("builtin_interfaces/Time", TIME),
                ("geometry_msgs/Pose", POSE),
                ("geometry_msgs/Point", POINT),
                ("geometry_msgs/Quaternion", QUATERNION),
                ("geometry_msgs/Vector3", VECTOR3),
                ("std_msgs/ColorRGBA", COLOR),
                ("builtin_interfaces/Duration", DURATION),
            ],
        ),
    }
}

/// A `builtin_interfaces/Time` from simulated seconds.
pub fn stamp(w: &mut CdrWriter, t_s: f64) {
    let t = t_s.max(0.0);
    let sec = t.floor();
    let nanosec = ((t - sec) * 1e9).round().min(999_999_999.0);
    w.i32(sec as i32).u32(nanosec as u32);
}

fn header(w: &mut CdrWriter, t_s: f64, frame: &str) {
    stamp(w, t_s);
    w.string(frame);
}

/// A planar pose as `geometry_msgs/Pose` (z = 0, a yaw quaternion).
fn pose(w: &mut CdrWriter, x: f64, y: f64, yaw: f64) {
    w.f64(x).f64(y).f64(0.0);
    quaternion(w, yaw);
}

fn quaternion(w: &mut CdrWriter, yaw: f64) {
    let (s, c) = (yaw / 2.0).sin_cos();
    w.f64(0.0).f64(0.0).f64(s).f64(c);
}

pub fn clock(t_s: f64) -> Vec<u8> {
    let mut w = CdrWriter::new();
    stamp(&mut w, t_s);
    w.finish()
}

/// A transform of `child` under `parent`: planar, at (x, y) with yaw.
pub struct Frame<'a> {
    pub parent: &'a str,
    pub child: &'a str,
    pub x: f64,
    pub y: f64,
    pub yaw: f64,
}

pub fn tf(t_s: f64, frames: &[Frame<'_>]) -> Vec<u8> {
    let mut w = CdrWriter::new();
    w.len(frames.len());
    for f in frames {
        header(&mut w, t_s, f.parent);
        w.string(f.child);
        w.f64(f.x).f64(f.y).f64(0.0);
        quaternion(&mut w, f.yaw);
    }
    w.finish()
}

/// A scan in `frame`: beams from `angle_min` by `increment`, +∞ for no return (as REP 117 asks).
pub fn laser_scan(
    t_s: f64,
    frame: &str,
    angle_min: f64,
    increment: f64,
    range_max: f64,
    ranges: &[f32],
) -> Vec<u8> {
    let mut w = CdrWriter::new();
    header(&mut w, t_s, frame);
    let angle_max = angle_min + increment * (ranges.len().max(1) - 1) as f64;
    w.f32(angle_min as f32)
        .f32(angle_max as f32)
        .f32(increment as f32)
        .f32(0.0)
        .f32(0.0)
        .f32(0.0)
        .f32(range_max as f32)
        .f32s(ranges)
        .f32s(&[]);
    w.finish()
}

/// Odometry of `child` in `frame`: a planar pose and velocity, covariances unknown (zero).
pub fn odometry(
    t_s: f64,
    frame: &str,
    child: &str,
    at: (f64, f64, f64),
    velocity: (f64, f64),
) -> Vec<u8> {
    let mut w = CdrWriter::new();
    header(&mut w, t_s, frame);
    w.string(child);
    pose(&mut w, at.0, at.1, at.2);
    for _ in 0..36 {
        w.f64(0.0);
    }
    w.f64(velocity.0).f64(0.0).f64(0.0);
    w.f64(0.0).f64(0.0).f64(velocity.1);
    for _ in 0..36 {
        w.f64(0.0);
    }
    w.finish()
}

/// A grid in `frame`: `data` row-major from the cell at `origin` (its lower-left corner), −1
/// unknown, 0 free to 100 occupied.
pub fn occupancy_grid(
    t_s: f64,
    frame: &str,
    resolution: f64,
    (width, height): (u32, u32),
    origin: (f64, f64),
    data: &[i8],
) -> Vec<u8> {
    let mut w = CdrWriter::new();
    header(&mut w, t_s, frame);
    stamp(&mut w, t_s);
    w.f32(resolution as f32).u32(width).u32(height);
    pose(&mut w, origin.0, origin.1, 0.0);
    w.i8s(data);
    w.finish()
}

/// The shapes the recording draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    Arrow = 0,
    Cube = 1,
    Sphere = 2,
    LineList = 5,
}

/// One marker (all in one frame).
pub struct Marker<'a> {
    pub ns: &'a str,
    pub id: i32,
    pub shape: Shape,
    pub at: (f64, f64, f64),
    pub scale: (f64, f64, f64),
    pub rgba: [f32; 4],
    /// Line-list points (pairs).
    pub points: Vec<(f64, f64)>,
    pub text: String,
}

/// A `MarkerArray` in `frame`; the first marker deletes those of the last array (DELETEALL),
/// so the array replaces what was shown.
pub fn marker_array(t_s: f64, frame: &str, markers: &[Marker<'_>]) -> Vec<u8> {
    let mut w = CdrWriter::new();
    w.len(markers.len() + 1);
    let one = |w: &mut CdrWriter, m: &Marker<'_>, action: i32| {
        header(w, t_s, frame);
        w.string(m.ns).i32(m.id).i32(m.shape as i32).i32(action);
        pose(w, m.at.0, m.at.1, m.at.2);
        w.f64(m.scale.0).f64(m.scale.1).f64(m.scale.2);
        for c in m.rgba {
            w.f32(c);
        }
        w.i32(0).u32(0);
        w.bool(false);
        w.len(m.points.len());
        for &(x, y) in &m.points {
            w.f64(x).f64(y).f64(0.0);
        }
        w.len(0);
        w.string(&m.text).string("").bool(false);
    };
    let clear = Marker {
        ns: "",
        id: 0,
        shape: Shape::Cube,
        at: (0.0, 0.0, 0.0),
        scale: (1.0, 1.0, 1.0),
        rgba: [0.0; 4],
        points: Vec::new(),
        text: String::new(),
    };
    one(&mut w, &clear, 3);
    for m in markers {
        one(&mut w, m, 0);
    }
    w.finish()
}
