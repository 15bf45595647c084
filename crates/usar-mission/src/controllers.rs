//! The mission's controllers as they sit on the host: the team, which listens at its base
//! station for the crawler's Behavioral Trace Map and keeps its wheeled robots off what the
//! crawler recorded they cannot take; and the crawler, which builds the map and sends it.

use usar_btm::build::{BuildError, Explorer, StopReason};
use usar_btm::plan::{Limit, RobotLimits, link_violations, node_violations};
use usar_btm::wire;
use usar_sim::host::{Controller, Endpoint, FleetIo};
use usar_team::TeamController;
use usar_world::Point2;

/// The radio topic of BTMs.
pub const BTM_TOPIC: &str = "btm";

/// The team, with the BTMs that reach its base station turned into keep-out zones.
pub struct TeamWithBtm {
    pub team: TeamController,
    /// What the team's robots can take.
    limits: RobotLimits,
    /// How far from a closed link or node the planners stay, metres: the robot's circumscribed
    /// radius.
    clearance_m: f64,
    /// Whether links and nodes too narrow for the team's robots are closed too.
    narrow_too: bool,
    /// BTMs received and ones that could not be read.
    pub maps_received: u32,
    pub maps_unreadable: u32,
}

impl TeamWithBtm {
    /// `narrow_too`: also close links and nodes narrower than the team's robots (paper 004's
    /// width limit), not only the slopes and stairs.
    pub fn new(
        team: TeamController,
        limits: RobotLimits,
        clearance_m: f64,
        narrow_too: bool,
    ) -> Self {
        Self {
            team,
            limits,
            clearance_m,
            narrow_too,
            maps_received: 0,
            maps_unreadable: 0,
        }
    }

    /// Closes every link and node of `btm` too steep or with too high a step for the team's
    /// robots, as the crawler measured them: the slopes and stairs the team's own 2-D lasers
    /// cannot see (and, with `narrow_too`, those too narrow). By default width is not taken
    /// from the BTM: the team's maps show it, and the crawler's width samples are unreliable at
    /// a link's ends (a start link measured 0.01 m wide, issue 23).
    fn keep_off(&mut self, btm: &usar_btm::model::Btm) {
        let narrow_too = self.narrow_too;
        let unclimbable = |violations: Vec<(Limit, String)>| {
            violations.iter().any(|(limit, _)| match limit {
                Limit::Inclination | Limit::Step => true,
                Limit::Width => narrow_too,
            })
        };
        for link in &btm.links {
            let (Some(a), Some(b)) = (btm.node(link.start), link.end.and_then(|e| btm.node(e)))
            else {
                continue;
            };
            if unclimbable(link_violations(link, &self.limits)) {
                let half_width = link.min_width_m.unwrap_or(0.0) / 2.0;
                self.team.keep_out(
                    Point2::new(a.x_m, a.y_m),
                    Point2::new(b.x_m, b.y_m),
                    self.clearance_m + half_width,
                );
            }
        }
        for node in &btm.nodes {
            if unclimbable(node_violations(node, &self.limits)) {
                let p = Point2::new(node.x_m, node.y_m);
                self.team.keep_out(p, p, self.clearance_m);
            }
        }
    }
}

impl Controller for TeamWithBtm {
    fn step(&mut self, io: &mut FleetIo<'_>) {
        for message in io.receive(Endpoint::Base, BTM_TOPIC) {
            self.maps_received += 1;
            match wire::decode(&message.payload) {
                Ok(btm) => self.keep_off(&btm),
                Err(_) => self.maps_unreadable += 1,
            }
        }
        self.team.step(io);
    }
}

/// The crawler: it explores and builds its BTM, and sends the map to the base station every
/// `share_period_s` (and once more when it has finished).
pub struct SharingCrawler<'a> {
    pub explorer: Explorer<'a>,
    share_period_s: f64,
    last_shared_s: Option<f64>,
    /// Why the exploration ended, once it has.
    pub finished: Option<Result<StopReason, BuildError>>,
    shared_final: bool,
    pub maps_sent: u32,
}

impl<'a> SharingCrawler<'a> {
    pub fn new(explorer: Explorer<'a>, share_period_s: f64) -> Self {
        Self {
            explorer,
            share_period_s,
            last_shared_s: None,
            finished: None,
            shared_final: false,
            maps_sent: 0,
        }
    }

    fn share(&mut self, io: &mut FleetIo<'_>) {
        let btm = self.explorer.btm();
        if btm.nodes.is_empty() {
            return;
        }
        let sent = io.send(
            Endpoint::Robot(io.id(0)),
            Endpoint::Base,
            BTM_TOPIC,
            wire::encode(btm),
        );
        self.last_shared_s = Some(io.time_s());
        self.maps_sent += u32::from(sent);
    }
}

impl Controller for SharingCrawler<'_> {
    fn step(&mut self, io: &mut FleetIo<'_>) {
        if self.finished.is_none() {
            self.explorer.step(io);
            self.finished = self.explorer.take_finished();
        }
        let due = self
            .last_shared_s
            .is_none_or(|t| io.time_s() - t >= self.share_period_s);
        if self.finished.is_some() {
            if !std::mem::replace(&mut self.shared_final, true) {
                self.share(io);
            }
        } else if due {
            self.share(io);
        }
    }
}
