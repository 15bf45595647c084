//! The radio: messages between robots and the base station. A message reaches its receiver at
//! the next step, when both ends are within range of each other and the draw of the loss
//! probability spares it; otherwise it is lost (and counted).

use crate::simulation::{RobotId, derive_seed};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};
use usar_world::Point2;

/// The random stream of the radio (robots use streams 0, 1, … of the seed): the stream the
/// team's radio drew from before the host had one, so earlier results stand.
const RADIO_STREAM: u64 = (1 << 20) + 2;

/// How far the radio carries and how often it loses a message.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RadioSpec {
    /// Range between two ends, metres (`None`: everywhere).
    #[serde(default)]
    pub range_m: Option<f64>,
    /// Probability that a message within range is lost.
    #[serde(default)]
    pub drop_probability: f64,
    /// Where the base station stands (`None`: it hears every robot, whatever the range).
    #[serde(default)]
    pub base: Option<Point2>,
}

/// One end of a radio link.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Endpoint {
    Robot(RobotId),
    Base,
}

/// A message on the radio.
#[derive(Clone, Debug, PartialEq)]
pub struct Message {
    pub from: Endpoint,
    pub to: Endpoint,
    /// What the payload is (`"btm"`, `"map"`, …), for the receiver to pick its messages.
    pub topic: String,
    pub payload: Vec<u8>,
    pub sent_s: f64,
}

/// Counts of what the radio carried.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct RadioStats {
    pub sent: u64,
    pub delivered: u64,
    pub lost: u64,
    pub bytes_delivered: u64,
    /// Sent at the last step, not yet arrived.
    pub in_flight: u64,
    /// Arrived but dropped unread: an inbox holds at most [`INBOX_CAP`] messages per receiver
    /// and topic, the oldest going first.
    pub dropped_unread: u64,
}

/// The most messages an inbox keeps per receiver and topic.
pub const INBOX_CAP: usize = 256;

/// The radio of a host.
pub struct Radio {
    spec: RadioSpec,
    rng: Pcg64Mcg,
    in_flight: Vec<Message>,
    inbox: Vec<Message>,
    stats: RadioStats,
}

impl Radio {
    pub fn new(spec: RadioSpec, seed: u64) -> Self {
        Self {
            spec,
            rng: Pcg64Mcg::seed_from_u64(derive_seed(seed, RADIO_STREAM)),
            in_flight: Vec::new(),
            inbox: Vec::new(),
            stats: RadioStats::default(),
        }
    }

    pub fn spec(&self) -> &RadioSpec {
        &self.spec
    }

    pub(super) fn set_spec(&mut self, spec: RadioSpec) {
        self.spec = spec;
    }

    pub fn stats(&self) -> RadioStats {
        RadioStats {
            in_flight: self.in_flight.len() as u64,
            ..self.stats
        }
    }

    /// Sends `message` between ends at `from_at` and `to_at` (the base's place is the spec's).
    pub(super) fn send(
        &mut self,
        message: Message,
        from_at: Option<Point2>,
        to_at: Option<Point2>,
    ) {
        self.stats.sent += 1;
        let in_range = match (self.spec.range_m, from_at, to_at) {
            (Some(range), Some(a), Some(b)) => a.distance(b) <= range,
            _ => true,
        };
        let lost = !in_range
            || (self.spec.drop_probability > 0.0
                && self.rng.random::<f64>() < self.spec.drop_probability);
        if lost {
            self.stats.lost += 1;
        } else {
            self.in_flight.push(message);
        }
    }

    /// Whether a robot at `at` reaches the base station now: within range of it, and spared by
    /// one draw of the loss probability (drawn whether in range or not, one draw per call).
    pub(super) fn link_to_base(&mut self, at: Point2) -> bool {
        let in_range = match (self.spec.range_m, self.spec.base) {
            (Some(range), Some(base)) => at.distance(base) <= range,
            _ => true,
        };
        let delivered = self.spec.drop_probability <= 0.0
            || self.rng.random::<f64>() >= self.spec.drop_probability;
        in_range && delivered
    }

    /// The clock moved on: messages in flight arrive.
    pub(super) fn tick(&mut self) {
        for m in std::mem::take(&mut self.in_flight) {
            self.stats.delivered += 1;
            self.stats.bytes_delivered += m.payload.len() as u64;
            let waiting = self
                .inbox
                .iter()
                .filter(|w| w.to == m.to && w.topic == m.topic)
                .count();
            if waiting >= INBOX_CAP
                && let Some(oldest) = self
                    .inbox
                    .iter()
                    .position(|w| w.to == m.to && w.topic == m.topic)
            {
                self.inbox.remove(oldest);
                self.stats.dropped_unread += 1;
            }
            self.inbox.push(m);
        }
    }

    /// Takes the messages that arrived for `to` on `topic`, oldest first.
    pub(super) fn receive(&mut self, to: Endpoint, topic: &str) -> Vec<Message> {
        // Asked at every step, mostly with nothing there: only a hit rebuilds the inbox.
        if !self.inbox.iter().any(|m| m.to == to && m.topic == topic) {
            return Vec::new();
        }
        let (mine, rest) = std::mem::take(&mut self.inbox)
            .into_iter()
            .partition(|m| m.to == to && m.topic == topic);
        self.inbox = rest;
        mine
    }
}
