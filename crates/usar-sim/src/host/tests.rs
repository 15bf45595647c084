use super::*;
use crate::sensors::LaserScan;
use usar_world::{Cell, GridGeometry, Point2, obstacle};

/// A 10 × 6 m hall with a wall along x = 8 m.
fn hall() -> Arc<Scene> {
    let g = GridGeometry::new(100, 60, 0.1, Point2::new(0.0, 0.0));
    let mut s = Scene::empty("hall", g);
    for row in 0..60 {
        s.obstacle[Cell::new(80, row)] = obstacle::WALL;
    }
    Arc::new(s)
}

/// Drives every robot of its fleet at a fixed velocity and keeps the scans of robot 0.
struct Drive {
    v: Velocity,
    scan: LaserScan,
}

impl Controller for Drive {
    fn step(&mut self, io: &mut FleetIo<'_>) {
        io.laser(0, &mut self.scan);
        for k in 0..io.len() {
            io.command(k, self.v);
        }
    }
}

fn drive(linear_mps: f64) -> Drive {
    Drive {
        v: Velocity {
            linear_mps,
            angular_radps: 0.0,
        },
        scan: LaserScan::default(),
    }
}

fn in_lasers() -> SimConfig {
    SimConfig {
        robots_in_lasers: true,
        ..SimConfig::default()
    }
}

#[test]
fn a_robot_of_one_controller_sees_the_robot_of_another_in_its_laser() {
    let mut host = Host::new(hall(), in_lasers(), 3, Oracles::default());
    let team = host
        .add_fleet(&[(RobotSpec::wheeled(), Pose2::new(2.0, 3.0, 0.0))])
        .unwrap();
    let crawler = host
        .add_fleet(&[(RobotSpec::crawler(), Pose2::new(5.0, 3.0, 0.0))])
        .unwrap();
    let (mut looking, mut still) = (drive(0.0), drive(0.0));
    host.step(&mut [(team, &mut looking), (crawler, &mut still)]);
    // Straight ahead: the crawler's back face at 5.0 − 0.3 = 4.7 m, 2.7 m away (the wall is
    // 6 m away).
    let ahead = looking.scan.ranges_m[looking.scan.ranges_m.len() / 2];
    assert!((f64::from(ahead) - 2.7).abs() < 0.05, "{ahead}");
    // Without bodies in lasers, the same beam reaches the wall.
    let mut host = Host::new(hall(), SimConfig::default(), 3, Oracles::default());
    let team = host
        .add_fleet(&[(RobotSpec::wheeled(), Pose2::new(2.0, 3.0, 0.0))])
        .unwrap();
    host.add_fleet(&[(RobotSpec::crawler(), Pose2::new(5.0, 3.0, 0.0))])
        .unwrap();
    host.step(&mut [(team, &mut looking)]);
    let ahead = looking.scan.ranges_m[looking.scan.ranges_m.len() / 2];
    assert!((f64::from(ahead) - 6.0).abs() < 0.05, "{ahead}");
}

#[test]
fn robots_of_different_controllers_cannot_occupy_one_place() {
    let mut host = Host::new(hall(), in_lasers(), 3, Oracles::default());
    let team = host
        .add_fleet(&[(RobotSpec::wheeled(), Pose2::new(2.0, 3.0, 0.0))])
        .unwrap();
    assert!(
        host.add_fleet(&[(RobotSpec::crawler(), Pose2::new(2.2, 3.0, 0.0))])
            .is_err()
    );
    let crawler = host
        .add_fleet(&[(
            RobotSpec::crawler(),
            Pose2::new(5.0, 3.0, std::f64::consts::PI),
        )])
        .unwrap();
    let (mut a, mut b) = (drive(0.5), drive(0.5));
    for _ in 0..60 {
        host.step(&mut [(team, &mut a), (crawler, &mut b)]);
    }
    let truth = host.evaluator();
    let (p, q) = (
        truth.robot(host.fleet(team)[0]).pose,
        truth.robot(host.fleet(crawler)[0]).pose,
    );
    // Face to face: the wheeled robot's front half (0.25) and the crawler's (0.3) apart.
    assert!(q.x - p.x >= 0.55 - 1e-9, "{p:?} {q:?}");
    assert!(
        truth
            .robots()
            .iter()
            .all(|r| r.collisions == 1 && r.robot_contacts == 1)
    );
}

#[test]
fn without_the_localization_oracle_readings_carry_the_odometry_pose() {
    for oracle in [false, true] {
        let oracles = Oracles {
            localization: oracle,
        };
        let mut host = Host::new(hall(), SimConfig::default(), 5, oracles);
        let fleet = host
            .add_fleet(&[(RobotSpec::wheeled(), Pose2::new(2.0, 3.0, 0.0))])
            .unwrap();
        let mut turning = Drive {
            v: Velocity {
                linear_mps: 0.5,
                angular_radps: 0.5,
            },
            scan: LaserScan::default(),
        };
        for _ in 0..50 {
            host.step(&mut [(fleet, &mut turning)]);
        }
        struct Look(Option<Pose2>, Pose2, Pose2);
        impl Controller for Look {
            fn step(&mut self, io: &mut FleetIo<'_>) {
                let mut scan = LaserScan::default();
                io.laser(0, &mut scan);
                *self = Look(io.true_pose(0), scan.pose, io.odometry(0).estimate);
            }
        }
        let mut look = Look(None, Pose2::default(), Pose2::default());
        host.decide(fleet, &mut look);
        let truth = host.evaluator().robot(host.fleet(fleet)[0]).pose;
        let Look(true_pose, stamped, odometry) = look;
        if oracle {
            assert_eq!((true_pose, stamped), (Some(truth), truth));
        } else {
            assert_eq!((true_pose, stamped), (None, odometry));
            assert_ne!(odometry, truth, "odometry drifts");
        }
    }
}

#[test]
fn a_failed_robot_stops_and_its_controller_sees_it_gone() {
    let mut host = Host::new(hall(), SimConfig::default(), 1, Oracles::default());
    let fleet = host
        .add_fleet(&[
            (RobotSpec::wheeled(), Pose2::new(2.0, 2.0, 0.0)),
            (RobotSpec::wheeled(), Pose2::new(2.0, 4.0, 0.0)),
        ])
        .unwrap();
    host.schedule_failure(host.fleet(fleet)[1], 0.5);
    let mut go = drive(0.5);
    for _ in 0..20 {
        host.step(&mut [(fleet, &mut go)]);
    }
    let truth = host.evaluator();
    let [a, b] = [0, 1].map(|k| truth.robot(host.fleet(fleet)[k]).pose.x);
    assert!((a - 3.0).abs() < 1e-9 && (b - 2.25).abs() < 1e-9, "{a} {b}");
    struct Alive(Vec<bool>);
    impl Controller for Alive {
        fn step(&mut self, io: &mut FleetIo<'_>) {
            self.0 = (0..io.len()).map(|k| io.alive(k)).collect();
        }
    }
    let mut alive = Alive(Vec::new());
    host.decide(fleet, &mut alive);
    assert_eq!(alive.0, [true, false]);
}

/// Sends one message from robot 0 to the base station on the first step, and collects what
/// the base station receives.
struct Talk {
    sent: bool,
    received: Vec<Message>,
}

impl Controller for Talk {
    fn step(&mut self, io: &mut FleetIo<'_>) {
        if !std::mem::replace(&mut self.sent, true) {
            io.send(
                Endpoint::Robot(io.id(0)),
                Endpoint::Base,
                "btm",
                vec![1, 2, 3],
            );
        }
        self.received.extend(io.receive(Endpoint::Base, "btm"));
    }
}

fn talk(spec: RadioSpec, at: Point2) -> (Vec<Message>, RadioStats) {
    let mut host = Host::new(hall(), SimConfig::default(), 1, Oracles::default()).with_radio(spec);
    let fleet = host
        .add_fleet(&[(RobotSpec::wheeled(), Pose2::new(at.x, at.y, 0.0))])
        .unwrap();
    host.set_base_owner(fleet);
    let mut t = Talk {
        sent: false,
        received: Vec::new(),
    };
    for _ in 0..3 {
        host.step(&mut [(fleet, &mut t)]);
    }
    let stats = host.evaluator().radio();
    (t.received, stats)
}

#[test]
fn the_radio_carries_within_range_and_loses_beyond_it() {
    let spec = RadioSpec {
        range_m: Some(3.0),
        drop_probability: 0.0,
        base: Some(Point2::new(1.0, 1.0)),
    };
    let (near, stats) = talk(spec.clone(), Point2::new(2.0, 2.0));
    assert_eq!(near.len(), 1);
    assert_eq!(
        (near[0].payload.as_slice(), near[0].sent_s),
        (&[1u8, 2, 3][..], 0.0)
    );
    assert_eq!(
        (stats.delivered, stats.lost, stats.bytes_delivered),
        (1, 0, 3)
    );
    let (far, stats) = talk(spec.clone(), Point2::new(6.0, 4.0));
    assert!(far.is_empty());
    assert_eq!((stats.sent, stats.lost), (1, 1));
    let lossy = RadioSpec {
        drop_probability: 1.0,
        ..spec
    };
    assert!(talk(lossy, Point2::new(2.0, 2.0)).0.is_empty());
}

#[test]
fn the_evaluator_knows_which_victim_a_thermal_reading_saw() {
    let mut scene = (*hall()).clone();
    scene.victims.push(usar_world::Victim {
        id: 7,
        position: Point2::new(4.0, 3.0),
        heat_c: 34.0,
        visible_size_m2: 0.5,
        buried_fraction: 0.0,
    });
    let mut host = Host::new(Arc::new(scene), SimConfig::default(), 1, Oracles::default());
    let fleet = host
        .add_fleet(&[(RobotSpec::wheeled(), Pose2::new(2.0, 3.0, 0.0))])
        .unwrap();
    struct Look(Vec<crate::sensors::ThermalReading>);
    impl Controller for Look {
        fn step(&mut self, io: &mut FleetIo<'_>) {
            self.0 = io.thermal(0);
        }
    }
    let mut look = Look(Vec::new());
    host.decide(fleet, &mut look);
    assert_eq!(look.0.len(), 1);
    assert!(look.0[0].human_signature);
    assert_eq!(
        host.evaluator().truth_of(look.0[0].id),
        Some(HeatTruth::Victim(7))
    );
}

#[test]
fn a_controller_speaks_and_listens_only_as_its_own_robots_and_the_base_it_runs() {
    let mut host = Host::new(hall(), SimConfig::default(), 1, Oracles::default());
    let a = host
        .add_fleet(&[(RobotSpec::wheeled(), Pose2::new(2.0, 2.0, 0.0))])
        .unwrap();
    let b = host
        .add_fleet(&[(RobotSpec::wheeled(), Pose2::new(2.0, 4.0, 0.0))])
        .unwrap();
    host.set_base_owner(a);
    let theirs = Endpoint::Robot(host.fleet(b)[0]);
    /// Tries to speak as `from`, and collects what reaches `at` on "x".
    struct Try {
        from: Endpoint,
        at: Endpoint,
        sent: Option<bool>,
        got: usize,
    }
    impl Controller for Try {
        fn step(&mut self, io: &mut FleetIo<'_>) {
            if self.sent.is_none() {
                self.sent = Some(io.send(self.from, self.at, "x", vec![7]));
            }
            self.got += io.receive(self.at, "x").len();
        }
    }
    // Fleet b may not speak as the base, nor listen there.
    let mut impostor = Try {
        from: Endpoint::Base,
        at: Endpoint::Base,
        sent: None,
        got: 0,
    };
    // Fleet a runs the base: it speaks as the base to b's robot, but cannot read b's inbox.
    let mut base = Try {
        from: Endpoint::Base,
        at: theirs,
        sent: None,
        got: 0,
    };
    for _ in 0..3 {
        host.step(&mut [(a, &mut base), (b, &mut impostor)]);
    }
    assert_eq!((impostor.sent, impostor.got), (Some(false), 0));
    assert_eq!((base.sent, base.got), (Some(true), 0));
    assert_eq!(host.evaluator().radio().sent, 1);
}
