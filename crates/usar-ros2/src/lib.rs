//! A live ROS 2 bridge in pure Rust: ros2-client on RustDDS, built from crates.io alone, no
//! ROS installation. ROS 2 peers (RViz2, Nav2, `ros2 topic`, any DDS participant using ROS 2's
//! names and types) see usar as ROS 2 nodes:
//!
//! - [`sim`]: a simulated robot publishing `/scan`, `/odom`, `/tf` (`odom` → `base_link`),
//!   `/tf_static` (`base_link` → `laser`), `/map` (the scene, as a `map_server` would) and
//!   `/clock`, driven by `/cmd_vel`;
//! - [`explore`]: usar's frontier explorer on a robot's `/scan` and `/odom`, publishing its
//!   goal (`geometry_msgs/PoseStamped` on `/goal_pose`, Nav2's), its `/map` and the frontier
//!   candidates as markers;
//! - [`btm`]: the passive BTM builder on `/scan` and `/odom`, publishing the BTM as markers.
//!
//! QoS as ROS 2 users expect ([`qos`]): sensor data best effort, maps reliable and transient
//! local, commands and goals reliable. Topic names are remappable ([`Topics`]).
//! [`Bridge::new`] joins a DDS domain; [`BridgeOptions::loopback`] keeps discovery and data on
//! 127.0.0.1 (unicast discovery; a Cyclone DDS peer then needs its loopback peer set).

pub mod btm;
pub mod explore;
pub mod msgs;
pub mod sim;

use ros2_client::{
    Context, MessageTypeName, Name, Node, NodeName, NodeOptions, Publisher, QosProfile,
    Subscription,
};
use serde::{Serialize, de::DeserializeOwned};

/// Why the bridge failed.
#[derive(Debug, thiserror::Error)]
pub enum BridgeError {
    #[error("DDS: {0}")]
    Dds(String),
    #[error("ROS 2 name {0:?}: expected a name such as scan or /robot1/scan")]
    Name(String),
    #[error(transparent)]
    Btm(#[from] usar_btm::store::BtmError),
    #[error("{0}")]
    Setup(String),
}

fn dds(e: impl std::fmt::Debug) -> BridgeError {
    BridgeError::Dds(format!("{e:?}"))
}

/// QoS profiles as ROS 2 users expect them.
pub mod qos {
    use ros2_client::QosProfile;
    use ros2_client::qos::{Durability, History, WhenFull};

    /// Sensor data (rclcpp's `SensorDataQoS`): best effort, volatile, keep last 5.
    pub fn sensor() -> QosProfile {
        QosProfile::subscription_default()
            .reliability_best_effort()
            .durability(Durability::Volatile)
            .history(History::KeepLast { depth: 5 })
    }

    /// Maps (`map_server`'s): reliable, transient local (late joiners get the last one), keep
    /// last 1.
    pub fn map() -> QosProfile {
        QosProfile::publisher_default()
            .reliability_reliable(WhenFull::DEFAULT)
            .durability(Durability::TransientLocal)
            .history(History::KeepLast { depth: 1 })
    }

    /// Commands, goals, odometry, transforms (`ros2 topic pub`'s default): reliable,
    /// volatile, keep last 10.
    pub fn reliable() -> QosProfile {
        QosProfile::publisher_default()
            .reliability_reliable(WhenFull::DEFAULT)
            .durability(Durability::Volatile)
            .history(History::KeepLast { depth: 10 })
    }
}

/// Where the bridge joins.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BridgeOptions {
    /// DDS domain (`ROS_DOMAIN_ID`).
    pub domain: u16,
    /// Only 127.0.0.1: discovery by unicast on loopback, nothing on other interfaces.
    pub loopback: bool,
}

impl BridgeOptions {
    /// From the environment ROS 2 users set: `ROS_DOMAIN_ID`, and `ROS_LOCALHOST_ONLY=1` or
    /// `ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST` for loopback.
    pub fn from_env() -> Self {
        let var = |k: &str| std::env::var(k).ok();
        Self {
            domain: var("ROS_DOMAIN_ID")
                .and_then(|d| d.parse().ok())
                .unwrap_or(0),
            loopback: var("ROS_LOCALHOST_ONLY").is_some_and(|v| v == "1")
                || var("ROS_AUTOMATIC_DISCOVERY_RANGE").is_some_and(|v| v == "LOCALHOST"),
        }
    }
}

/// Topic names, remappable: each field is the ROS 2 name of a topic (`scan`, `/robot1/scan`).
#[derive(Clone, Debug, PartialEq)]
pub struct Topics {
    pub scan: String,
    pub odom: String,
    pub tf: String,
    pub tf_static: String,
    pub map: String,
    pub clock: String,
    pub cmd_vel: String,
    pub goal: String,
    pub markers: String,
}

impl Default for Topics {
    fn default() -> Self {
        Self {
            scan: "/scan".into(),
            odom: "/odom".into(),
            tf: "/tf".into(),
            tf_static: "/tf_static".into(),
            map: "/map".into(),
            clock: "/clock".into(),
            cmd_vel: "/cmd_vel".into(),
            goal: "/goal_pose".into(),
            markers: "/markers".into(),
        }
    }
}

impl Topics {
    /// Applies `from:=to` remappings (ROS 2's `--remap` form; the leading slash optional on
    /// either side).
    pub fn remap(&mut self, rules: &[String]) -> Result<(), BridgeError> {
        for rule in rules {
            let (from, to) = rule
                .split_once(":=")
                .ok_or_else(|| BridgeError::Name(rule.clone()))?;
            let from = from.trim_start_matches('/');
            let slot = match from {
                "scan" => &mut self.scan,
                "odom" => &mut self.odom,
                "tf" => &mut self.tf,
                "tf_static" => &mut self.tf_static,
                "map" => &mut self.map,
                "clock" => &mut self.clock,
                "cmd_vel" => &mut self.cmd_vel,
                "goal_pose" => &mut self.goal,
                "markers" => &mut self.markers,
                _ => return Err(BridgeError::Name(from.into())),
            };
            *slot = to.to_string();
        }
        Ok(())
    }
}

/// A ROS 2 node on a DDS domain.
pub struct Bridge {
    node: Node,
}

impl Bridge {
    /// Joins the domain as node `name`.
    pub fn new(name: &str, options: &BridgeOptions) -> Result<Self, BridgeError> {
        let context = if options.loopback {
            let participant =
                ros2_client::dds::rustdds::DomainParticipantBuilder::new(options.domain)
                    .with_only_networks([std::net::Ipv4Addr::LOCALHOST])
                    .build()
                    .map_err(dds)?;
            Context::from_domain_participant(participant).map_err(dds)?
        } else {
            Context::with_options(ros2_client::ContextOptions::new().domain_id(options.domain))
                .map_err(dds)?
        };
        let node = context
            .new_node(
                NodeName::new("/", name).map_err(|_| BridgeError::Name(name.into()))?,
                NodeOptions::new(),
            )
            .map_err(dds)?;
        Ok(Self { node })
    }

    fn topic(
        &mut self,
        name: &str,
        (package, ty): (&str, &str),
        qos: &QosProfile,
    ) -> Result<ros2_client::dds::rustdds::Topic, BridgeError> {
        let (namespace, base) = match name.rsplit_once('/') {
            Some(("", base)) => ("/".to_string(), base),
            Some((ns, base)) => (
                if ns.starts_with('/') {
                    ns.to_string()
                } else {
                    format!("/{ns}")
                },
                base,
            ),
            None => ("/".to_string(), name),
        };
        let name = Name::new(&namespace, base).map_err(|_| BridgeError::Name(name.into()))?;
        self.node
            .create_topic(&name, MessageTypeName::new(package, ty), qos)
            .map_err(dds)
    }

    /// A publisher of `(package, type)` messages on topic `name`.
    pub fn publisher<M: Serialize>(
        &mut self,
        name: &str,
        ty: (&str, &str),
        qos: QosProfile,
    ) -> Result<Publisher<M>, BridgeError> {
        let topic = self.topic(name, ty, &qos)?;
        self.node.create_publisher(&topic, Some(qos)).map_err(dds)
    }

    /// A subscription to `(package, type)` messages on topic `name`.
    pub fn subscription<M: 'static + DeserializeOwned>(
        &mut self,
        name: &str,
        ty: (&str, &str),
        qos: QosProfile,
    ) -> Result<Subscription<M>, BridgeError> {
        let topic = self.topic(name, ty, &qos)?;
        self.node
            .create_subscription(&topic, Some(qos))
            .map_err(dds)
    }
}

/// The ROS 2 type of each message.
pub mod types {
    pub const LASER_SCAN: (&str, &str) = ("sensor_msgs", "LaserScan");
    pub const ODOMETRY: (&str, &str) = ("nav_msgs", "Odometry");
    pub const OCCUPANCY_GRID: (&str, &str) = ("nav_msgs", "OccupancyGrid");
    pub const TF: (&str, &str) = ("tf2_msgs", "TFMessage");
    pub const CLOCK: (&str, &str) = ("rosgraph_msgs", "Clock");
    pub const TWIST: (&str, &str) = ("geometry_msgs", "Twist");
    pub const POSE_STAMPED: (&str, &str) = ("geometry_msgs", "PoseStamped");
    pub const MARKER_ARRAY: (&str, &str) = ("visualization_msgs", "MarkerArray");
}

/// A laser scan message as usar's reading (ranges beyond `range_max` or not finite: no
/// return; below `range_min` or NaN: no reading), stamped with `pose`.
pub fn scan_reading(m: &msgs::LaserScan, pose: usar_world::Pose2) -> usar_sim::sensors::LaserScan {
    usar_sim::sensors::LaserScan {
        pose,
        angle_min_rad: f64::from(m.angle_min),
        angle_increment_rad: f64::from(m.angle_increment),
        max_range_m: f64::from(m.range_max),
        ranges_m: m
            .ranges
            .iter()
            .map(|&r| {
                if r.is_nan() || r < m.range_min {
                    f32::NAN
                } else if r >= m.range_max || r.is_infinite() {
                    f32::INFINITY
                } else {
                    r
                }
            })
            .collect(),
    }
}

/// A robot's `/scan` and `/odom` as a node hears them: each scan paired with the latest
/// odometry received before it (scans before any odometry are dropped).
pub struct SensorFeed {
    scans: Subscription<msgs::LaserScan>,
    odom: Subscription<msgs::Odometry>,
    odometry: Option<usar_world::Pose2>,
}

impl SensorFeed {
    /// Subscribes to `topics.scan` (sensor data QoS) and `topics.odom` (reliable).
    pub fn new(node: &mut Bridge, topics: &Topics) -> Result<Self, BridgeError> {
        Ok(Self {
            scans: node.subscription(&topics.scan, types::LASER_SCAN, qos::sensor())?,
            odom: node.subscription(&topics.odom, types::ODOMETRY, qos::reliable())?,
            odometry: None,
        })
    }

    /// Hands every scan waiting, with its odometry, to `on_scan`; whether anything came.
    pub fn poll(&mut self, mut on_scan: impl FnMut(usar_world::Pose2, &msgs::LaserScan)) -> bool {
        let mut busy = false;
        while let Ok(Some((o, _))) = self.odom.take() {
            self.odometry = Some(o.pose.pose.to_pose2());
            busy = true;
        }
        while let Ok(Some((scan, _))) = self.scans.take() {
            if let Some(at) = self.odometry {
                on_scan(at, &scan);
            }
            busy = true;
        }
        busy
    }
}

/// Stops a node's loop from another thread (or a Ctrl-C handler).
pub type StopFlag = std::sync::Arc<std::sync::atomic::AtomicBool>;

fn stopped(flag: &StopFlag) -> bool {
    flag.load(std::sync::atomic::Ordering::Relaxed)
}

/// The README's examples, compiled as doctests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
