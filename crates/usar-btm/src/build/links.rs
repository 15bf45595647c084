//! Links while they are driven (Table II): the recorder keeps what the robot measured along
//! the way — distance, the free width L_l + L_r beside it and its body inclination — so that
//! a link gets its length, minimum width and maximum inclination when its end node is made.
//! The map writer owns the BTM being built and writes every new or changed row to the store
//! at once.

use crate::model::{Btm, Link, Node};
use crate::store::{BtmError, BtmStore};
use std::collections::BTreeMap;
use usar_world::Point2;

/// One measurement along a link.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkSample {
    /// Odometric distance driven since the build started, metres.
    pub driven_m: f64,
    pub position: Point2,
    /// L_l + L_r beside the robot, metres.
    pub width_m: f64,
    /// Inclination of the body (attitude sensor), radians.
    pub inclination_rad: f64,
}

/// The measurements along the link being driven.
#[derive(Clone, Debug, Default)]
pub struct LinkRecorder {
    pub samples: Vec<LinkSample>,
}

/// Length, minimum width, maximum inclination and the path of a driven stretch.
#[derive(Clone, Debug, PartialEq)]
pub struct LinkMeasures {
    pub length_m: f64,
    pub min_width_m: Option<f64>,
    pub max_inclination_rad: Option<f64>,
    pub path: Vec<Point2>,
}

/// Path points closer than this to the last one kept are dropped.
const PATH_SPACING_M: f64 = 0.1;

impl LinkRecorder {
    pub fn push(&mut self, sample: LinkSample) {
        self.samples.push(sample);
    }

    /// Splits off the samples driven before `driven_m`, leaving the rest here.
    pub fn split_before(&mut self, driven_m: f64) -> LinkRecorder {
        let at = self.samples.partition_point(|s| s.driven_m < driven_m);
        let rest = self.samples.split_off(at);
        LinkRecorder {
            samples: std::mem::replace(&mut self.samples, rest),
        }
    }

    /// Where the robot was after `driven_m`, interpolated; the nearest end outside the range.
    pub fn position_at(&self, driven_m: f64) -> Option<Point2> {
        let i = self.samples.partition_point(|s| s.driven_m < driven_m);
        match (
            i.checked_sub(1).map(|j| self.samples[j]),
            self.samples.get(i),
        ) {
            (Some(a), Some(b)) if b.driven_m > a.driven_m => {
                let t = (driven_m - a.driven_m) / (b.driven_m - a.driven_m);
                Some(Point2::new(
                    a.position.x + t * (b.position.x - a.position.x),
                    a.position.y + t * (b.position.y - a.position.y),
                ))
            }
            (Some(a), _) => Some(a.position),
            (None, Some(b)) => Some(b.position),
            (None, None) => None,
        }
    }

    /// Largest inclination among the samples driven within [from, to].
    pub fn max_inclination_between(&self, from_m: f64, to_m: f64) -> Option<f64> {
        self.samples
            .iter()
            .filter(|s| s.driven_m >= from_m && s.driven_m <= to_m)
            .map(|s| s.inclination_rad)
            .reduce(f64::max)
    }

    /// The measures of the stretch from node position `from` to `to`.
    pub fn measures(&self, from: Point2, to: Point2) -> LinkMeasures {
        let mut path = vec![from];
        for s in &self.samples {
            if path
                .last()
                .is_some_and(|p| p.distance(s.position) >= PATH_SPACING_M)
            {
                path.push(s.position);
            }
        }
        path.push(to);
        let length_m = path.windows(2).map(|w| w[0].distance(w[1])).sum();
        LinkMeasures {
            length_m,
            min_width_m: self.samples.iter().map(|s| s.width_m).reduce(f64::min),
            max_inclination_rad: self
                .samples
                .iter()
                .map(|s| s.inclination_rad)
                .reduce(f64::max),
            path,
        }
    }
}

/// The BTM under construction, mirrored row by row into the store.
pub struct MapWriter<'s> {
    pub btm: Btm,
    store: Option<&'s BtmStore>,
    /// The driven path of every searched link, from its start node to its end node.
    paths: BTreeMap<u32, Vec<Point2>>,
}

impl<'s> MapWriter<'s> {
    pub fn new(store: Option<&'s BtmStore>) -> Self {
        Self {
            btm: Btm::default(),
            store,
            paths: BTreeMap::new(),
        }
    }

    fn put_node(&self, id: u32) -> Result<(), BtmError> {
        match (self.store, self.btm.node(id)) {
            (Some(store), Some(n)) => store.put_node(n),
            _ => Ok(()),
        }
    }

    fn put_link(&self, id: u32) -> Result<(), BtmError> {
        match (self.store, self.link(id)) {
            (Some(store), Some(l)) => store.put_link(l),
            _ => Ok(()),
        }
    }

    pub fn link(&self, id: u32) -> Option<&Link> {
        self.btm.links.iter().find(|l| l.id == id)
    }

    pub fn node_position(&self, id: u32) -> Option<Point2> {
        self.btm.node(id).map(|n| Point2::new(n.x_m, n.y_m))
    }

    /// Adds a node of `kind`/`subtype` at `at` (its id assigned here), then lets `fill` set
    /// its attributes before it is stored.
    pub fn add_node(
        &mut self,
        at: Point2,
        kind: &str,
        subtype: Option<&str>,
        fill: impl FnOnce(&mut Node),
    ) -> Result<u32, BtmError> {
        let id = self.btm.next_node_id();
        let mut node = Node::new(id, at.x, at.y, kind, subtype);
        fill(&mut node);
        self.btm.nodes.push(node);
        self.put_node(id)?;
        Ok(id)
    }

    /// Changes node `id` with `change` and stores it again.
    pub fn update_node(&mut self, id: u32, change: impl FnOnce(&mut Node)) -> Result<(), BtmError> {
        if let Some(n) = self.btm.nodes.iter_mut().find(|n| n.id == id) {
            change(n);
        }
        self.put_node(id)
    }

    /// Adds an un-searched link leaving `start` in `direction_rad`.
    pub fn add_unsearched(&mut self, start: u32, direction_rad: f64) -> Result<u32, BtmError> {
        let id = self.btm.next_link_id();
        self.btm
            .links
            .push(Link::unsearched(id, start, direction_rad));
        self.put_link(id)?;
        Ok(id)
    }

    /// Marks link `id` searched, ending at node `end`, with the measures driven.
    pub fn close_link(&mut self, id: u32, end: u32, m: LinkMeasures) -> Result<(), BtmError> {
        if let Some(l) = self.btm.links.iter_mut().find(|l| l.id == id) {
            l.end = Some(end);
            l.searched = true;
            l.length_m = Some(m.length_m);
            l.min_width_m = m.min_width_m;
            l.max_inclination_rad = m.max_inclination_rad;
            self.paths.insert(id, m.path);
        }
        self.put_link(id)
    }

    /// Sets an attribute of link `id` that travels in `extra`.
    pub fn set_link_extra(
        &mut self,
        id: u32,
        key: &str,
        value: serde_json::Value,
    ) -> Result<(), BtmError> {
        if let Some(l) = self.btm.links.iter_mut().find(|l| l.id == id) {
            l.extra.insert(key.into(), value);
        }
        self.put_link(id)
    }

    /// Removes an un-searched link that turned out to be the far end of the link just
    /// driven (a loop closed: both were the same passage).
    pub fn remove_unsearched(&mut self, stub: u32) -> Result<(), BtmError> {
        self.btm.links.retain(|l| l.id != stub);
        match self.store {
            Some(store) => store.delete_link(stub),
            None => Ok(()),
        }
    }

    /// The driven path of link `id` as seen leaving node `from` (reversed when `from` is its
    /// end).
    pub fn path_from(&self, id: u32, from: u32) -> Option<Vec<Point2>> {
        let link = self.link(id)?;
        let mut path = self.paths.get(&id)?.clone();
        if link.start != from {
            path.reverse();
        }
        Some(path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(d: f64, w: f64, inc: f64) -> LinkSample {
        LinkSample {
            driven_m: d,
            position: Point2::new(d, 0.0),
            width_m: w,
            inclination_rad: inc,
        }
    }

    #[test]
    fn measures_take_the_narrowest_width_and_the_steepest_inclination() {
        let mut rec = LinkRecorder::default();
        for (i, (w, inc)) in [(1.6, 0.0), (1.2, 0.3), (1.5, 0.1)].into_iter().enumerate() {
            rec.push(sample(i as f64, w, inc));
        }
        let m = rec.measures(Point2::new(-0.5, 0.0), Point2::new(2.5, 0.0));
        assert!((m.length_m - 3.0).abs() < 1e-12);
        assert_eq!(m.min_width_m, Some(1.2));
        assert_eq!(m.max_inclination_rad, Some(0.3));
        let first = rec.split_before(1.5);
        assert_eq!(first.samples.len(), 2);
        assert_eq!(rec.samples.len(), 1);
        assert_eq!(first.position_at(0.5), Some(Point2::new(0.5, 0.0)));
    }
}
