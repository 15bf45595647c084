//! ROS 2 messages as Rust structs, serialised by ros2-client's CDR serde: field order is the
//! `.msg` field order, fixed arrays are tuples (no length), sequences are `Vec`s. The layouts
//! are ROS 2 Humble's (also Jazzy's): `visualization_msgs/Marker` has Humble's texture and
//! mesh fields.

use ros2_client::Message;
use serde::de::{self, SeqAccess, Visitor};
use serde::ser::SerializeTuple;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use usar_world::Pose2;

#[derive(Serialize, Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct Time {
    pub sec: i32,
    pub nanosec: u32,
}

impl Time {
    /// A time in seconds (negative times are 0).
    pub fn from_s(t: f64) -> Self {
        let t = t.max(0.0);
        let sec = t.floor();
        Self {
            sec: sec as i32,
            nanosec: (((t - sec) * 1e9).round() as u32).min(999_999_999),
        }
    }

    pub fn as_s(self) -> f64 {
        f64::from(self.sec) + f64::from(self.nanosec) * 1e-9
    }
}

#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct Header {
    pub stamp: Time,
    pub frame_id: String,
}

impl Header {
    pub fn new(t_s: f64, frame: &str) -> Self {
        Self {
            stamp: Time::from_s(t_s),
            frame_id: frame.into(),
        }
    }
}

#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct Clock {
    pub clock: Time,
}
impl Message for Clock {}

#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct LaserScan {
    pub header: Header,
    pub angle_min: f32,
    pub angle_max: f32,
    pub angle_increment: f32,
    pub time_increment: f32,
    pub scan_time: f32,
    pub range_min: f32,
    pub range_max: f32,
    pub ranges: Vec<f32>,
    pub intensities: Vec<f32>,
}
impl Message for LaserScan {}

#[derive(Serialize, Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct Vector3 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

/// `geometry_msgs/Point` has the fields of a `Vector3`.
pub type Point = Vector3;

#[derive(Serialize, Deserialize, Clone, Copy, Debug, PartialEq)]
pub struct Quaternion {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub w: f64,
}

impl Default for Quaternion {
    fn default() -> Self {
        Self::yaw(0.0)
    }
}

impl Quaternion {
    /// A rotation by `yaw` about z.
    pub fn yaw(yaw: f64) -> Self {
        let (s, c) = (yaw / 2.0).sin_cos();
        Self {
            x: 0.0,
            y: 0.0,
            z: s,
            w: c,
        }
    }

    /// The yaw of this rotation.
    pub fn to_yaw(self) -> f64 {
        (2.0 * (self.w * self.z + self.x * self.y))
            .atan2(1.0 - 2.0 * (self.y * self.y + self.z * self.z))
    }
}

#[derive(Serialize, Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct Pose {
    pub position: Point,
    pub orientation: Quaternion,
}

impl Pose {
    pub fn planar(p: Pose2) -> Self {
        Self {
            position: Point {
                x: p.x,
                y: p.y,
                z: 0.0,
            },
            orientation: Quaternion::yaw(p.theta),
        }
    }

    pub fn to_pose2(self) -> Pose2 {
        Pose2::new(self.position.x, self.position.y, self.orientation.to_yaw())
    }
}

/// A 6 × 6 covariance: `float64[36]`, a fixed array (no length on the wire).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Covariance(pub [f64; 36]);

impl Default for Covariance {
    fn default() -> Self {
        Self([0.0; 36])
    }
}

impl Serialize for Covariance {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut t = s.serialize_tuple(36)?;
        for v in &self.0 {
            t.serialize_element(v)?;
        }
        t.end()
    }
}

impl<'de> Deserialize<'de> for Covariance {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Values;
        impl<'de> Visitor<'de> for Values {
            type Value = Covariance;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("36 doubles")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Covariance, A::Error> {
                let mut c = [0.0; 36];
                for (k, v) in c.iter_mut().enumerate() {
                    *v = seq
                        .next_element()?
                        .ok_or_else(|| de::Error::invalid_length(k, &self))?;
                }
                Ok(Covariance(c))
            }
        }
        d.deserialize_tuple(36, Values)
    }
}

#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct PoseWithCovariance {
    pub pose: Pose,
    pub covariance: Covariance,
}

#[derive(Serialize, Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct Twist {
    pub linear: Vector3,
    pub angular: Vector3,
}
impl Message for Twist {}

#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct TwistWithCovariance {
    pub twist: Twist,
    pub covariance: Covariance,
}

#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct Odometry {
    pub header: Header,
    pub child_frame_id: String,
    pub pose: PoseWithCovariance,
    pub twist: TwistWithCovariance,
}
impl Message for Odometry {}

impl Odometry {
    /// A planar pose of `child` in `frame` moving at `linear` m/s and `angular` rad/s.
    pub fn planar(
        t_s: f64,
        frame: &str,
        child: &str,
        at: Pose2,
        linear: f64,
        angular: f64,
    ) -> Self {
        Self {
            header: Header::new(t_s, frame),
            child_frame_id: child.into(),
            pose: PoseWithCovariance {
                pose: Pose::planar(at),
                covariance: Covariance::default(),
            },
            twist: TwistWithCovariance {
                twist: Twist {
                    linear: Vector3 {
                        x: linear,
                        ..Vector3::default()
                    },
                    angular: Vector3 {
                        z: angular,
                        ..Vector3::default()
                    },
                },
                covariance: Covariance::default(),
            },
        }
    }
}

#[derive(Serialize, Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct Transform {
    pub translation: Vector3,
    pub rotation: Quaternion,
}

#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct TransformStamped {
    pub header: Header,
    pub child_frame_id: String,
    pub transform: Transform,
}

impl TransformStamped {
    /// `child` at planar pose `at` in `parent`.
    pub fn planar(t_s: f64, parent: &str, child: &str, at: Pose2) -> Self {
        Self {
            header: Header::new(t_s, parent),
            child_frame_id: child.into(),
            transform: Transform {
                translation: Vector3 {
                    x: at.x,
                    y: at.y,
                    z: 0.0,
                },
                rotation: Quaternion::yaw(at.theta),
            },
        }
    }
}

#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct TFMessage {
    pub transforms: Vec<TransformStamped>,
}
impl Message for TFMessage {}

#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct PoseStamped {
    pub header: Header,
    pub pose: Pose,
}
impl Message for PoseStamped {}

#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct MapMetaData {
    pub map_load_time: Time,
    pub resolution: f32,
    pub width: u32,
    pub height: u32,
    pub origin: Pose,
}

#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct OccupancyGrid {
    pub header: Header,
    pub info: MapMetaData,
    pub data: Vec<i8>,
}
impl Message for OccupancyGrid {}

impl OccupancyGrid {
    /// An occupancy grid: −1 unknown, 0 free, 100 occupied, row-major from `origin` (the
    /// lower-left corner of cell 0).
    pub fn from_cells(t_s: f64, g: &usar_world::GridGeometry, data: Vec<i8>) -> Self {
        Self {
            header: Header::new(t_s, "map"),
            info: MapMetaData {
                map_load_time: Time::from_s(t_s),
                resolution: g.resolution_m as f32,
                width: g.width,
                height: g.height,
                origin: Pose::planar(Pose2::new(g.origin.x, g.origin.y, 0.0)),
            },
            data,
        }
    }

    /// A usar occupancy grid's classes.
    pub fn from_grid(t_s: f64, grid: &usar_map::OccupancyGrid) -> Self {
        let g = grid.geometry();
        let data = (0..g.len())
            .map(|i| match grid.class_at_index(i) {
                usar_map::CellClass::Unknown => -1,
                usar_map::CellClass::Free => 0,
                usar_map::CellClass::Occupied => 100,
            })
            .collect();
        Self::from_cells(t_s, g, data)
    }
}

#[derive(Serialize, Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct ColorRgba {
    pub r: f32,
    pub g: f32,
    pub b: f32,
    pub a: f32,
}

#[derive(Serialize, Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct Duration {
    pub sec: i32,
    pub nanosec: u32,
}

#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct CompressedImage {
    pub header: Header,
    pub format: String,
    pub data: Vec<u8>,
}

#[derive(Serialize, Deserialize, Clone, Copy, Debug, Default, PartialEq)]
pub struct UvCoordinate {
    pub u: f32,
    pub v: f32,
}

#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct MeshFile {
    pub filename: String,
    pub data: Vec<u8>,
}

/// `visualization_msgs/Marker` (Humble).
#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct Marker {
    pub header: Header,
    pub ns: String,
    pub id: i32,
    pub r#type: i32,
    pub action: i32,
    pub pose: Pose,
    pub scale: Vector3,
    pub color: ColorRgba,
    pub lifetime: Duration,
    pub frame_locked: bool,
    pub points: Vec<Point>,
    pub colors: Vec<ColorRgba>,
    pub texture_resource: String,
    pub texture: CompressedImage,
    pub uv_coordinates: Vec<UvCoordinate>,
    pub text: String,
    pub mesh_resource: String,
    pub mesh_file: MeshFile,
    pub mesh_use_embedded_materials: bool,
}

impl Marker {
    pub const SPHERE: i32 = 2;
    pub const LINE_LIST: i32 = 5;
    pub const DELETE_ALL: i32 = 3;

    /// Clears every marker of namespace `ns` (sent before the ones that replace them).
    pub fn delete_all(t_s: f64, ns: &str) -> Self {
        Self {
            header: Header::new(t_s, "map"),
            ns: ns.into(),
            action: Self::DELETE_ALL,
            ..Self::default()
        }
    }

    /// A sphere of diameter `size` at (x, y) in `map`.
    pub fn sphere(
        t_s: f64,
        ns: &str,
        id: i32,
        (x, y): (f64, f64),
        size: f64,
        rgba: [f32; 4],
    ) -> Self {
        Self {
            header: Header::new(t_s, "map"),
            ns: ns.into(),
            id,
            r#type: Self::SPHERE,
            pose: Pose::planar(Pose2::new(x, y, 0.0)),
            scale: Vector3 {
                x: size,
                y: size,
                z: size,
            },
            color: ColorRgba {
                r: rgba[0],
                g: rgba[1],
                b: rgba[2],
                a: rgba[3],
            },
            ..Self::default()
        }
    }
}

#[derive(Serialize, Deserialize, Clone, Debug, Default, PartialEq)]
pub struct MarkerArray {
    pub markers: Vec<Marker>,
}
impl Message for MarkerArray {}
