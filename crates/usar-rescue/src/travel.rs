//! Travel distances d_x of the exploration (paper 000 §V, eq. 10): path lengths in cells
//! through the cells the robot's map shows passable, kept for every cell the robot has stood
//! on and brought up to date incrementally as the map grows.
//!
//! The exploration asks, at every replanning, for the distances from the robot's cell to the
//! cells of interest and for the first step of a shortest path to a target. Rebuilding a
//! breadth-first search from the robot at every step was most of the cost of a training step;
//! instead each source cell keeps its distance field (a row of `n` distances), and:
//!
//! - a cell that becomes passable (a newly classified open or climbable cell) is appended to a
//!   log; a field that is used again applies the cells logged since its last use by relaxing
//!   distances outward from them (distances only shrink when cells are added), which gives
//!   exactly the breadth-first distances of the grown map;
//! - a passable cell that becomes impassable (a bump corrects the map) starts a new epoch:
//!   every field is rebuilt on its next use.
//!
//! **First step.** A breadth-first search that expands the four neighbours in the order
//! E, N, W, S and gives each cell the first step of the cell that reached it first, gives every
//! cell x the first step of the lexicographically smallest shortest path to it, i.e. the
//! smallest direction index k such that the robot's neighbour in direction k lies on a shortest
//! path to x. [`TravelDistances::first_step`] computes that same step from the distance field
//! (walking back from x over cells one step nearer), so results do not depend on how the field
//! was obtained.

use crate::marks::Marks;

/// A distance meaning "not reached" (any value ≥ [`UNREACHED`] is unreached; a row also
/// holds `BLOCKED` for impassable cells).
pub const UNREACHED: u16 = u16::MAX - 1;
/// Impassable cell, in a row.
const BLOCKED: u16 = u16::MAX;
const NONE: u32 = u32::MAX;

/// Distance fields of every source cell over the known passable cells (see the
/// [module documentation](self)).
#[derive(Clone, Debug)]
pub struct TravelDistances {
    n: usize,
    /// The four neighbours of each cell by direction index (E, N, W, S); a neighbour outside
    /// the map is the extra cell `n`, always [`BLOCKED`].
    neighbours: Vec<[u32; 4]>,
    /// A row before the search: [`UNREACHED`] for passable cells, [`BLOCKED`] elsewhere
    /// (`n + 1` entries).
    template: Vec<u16>,
    /// `n × (n + 1)`: row `s` holds the distances from source `s` (valid when
    /// `epoch_of[s] == epoch`), or [`BLOCKED`] / [`UNREACHED`].
    dist: Vec<u16>,
    epoch_of: Vec<u32>,
    /// Per source: how many entries of `log` its row includes.
    applied: Vec<u32>,
    epoch: u32,
    /// Cells that became passable during this epoch, in order.
    log: Vec<u32>,
    queue: Vec<u32>,
    /// Marks of the walk back in [`TravelDistances::first_step`].
    mark: Marks,
}

/// Logged additions above which a field is rebuilt rather than updated.
const REBUILD_AFTER: usize = 48;

impl TravelDistances {
    /// Fields over a map with the given neighbour table ([`u32::MAX`] outside the map); every
    /// cell impassable.
    pub fn new(neighbours: &[[u32; 4]]) -> Self {
        let n = neighbours.len();
        let w = n + 1;
        Self {
            n,
            neighbours: neighbours
                .iter()
                .map(|nb| nb.map(|k| if k == NONE { n as u32 } else { k }))
                .collect(),
            template: vec![BLOCKED; w],
            // Never read before the row's first rebuild (`epoch_of` is 0): zeroed memory,
            // which the allocator gives without writing it.
            dist: vec![0; n * w],
            epoch_of: vec![0; n],
            applied: vec![0; n],
            epoch: 1,
            log: Vec::new(),
            queue: Vec::with_capacity(n),
            mark: Marks::new(w),
        }
    }

    /// Whether cell `i` is passable.
    #[inline]
    pub fn is_passable(&self, i: usize) -> bool {
        self.template[i] == UNREACHED
    }

    /// Records whether cell `i` is passable now.
    #[inline]
    pub fn set_passable(&mut self, i: usize, passable: bool) {
        if (self.template[i] == UNREACHED) == passable {
            return;
        }
        if passable {
            self.template[i] = UNREACHED;
            self.log.push(i as u32);
        } else {
            self.template[i] = BLOCKED;
            self.epoch += 1;
            self.log.clear();
        }
    }

    /// Brings the distances from `source` to every cell (through passable cells; the source
    /// itself need not be passable) up to date with the map; read them with
    /// [`TravelDistances::row`].
    pub fn update(&mut self, source: usize) {
        let s = source;
        let fresh = self.epoch_of[s] == self.epoch && self.template[s] == UNREACHED;
        if !fresh || self.log.len() - self.applied[s] as usize > REBUILD_AFTER {
            self.rebuild(s);
        } else if self.log.len() > self.applied[s] as usize {
            self.apply_log(s);
        }
        self.epoch_of[s] = self.epoch;
        self.applied[s] = self.log.len() as u32;
    }

    /// The distances from `source` as of its last [`TravelDistances::update`]: values
    /// ≥ [`UNREACHED`] are unreached cells.
    #[inline]
    pub fn row(&self, source: usize) -> &[u16] {
        let w = self.n + 1;
        &self.dist[source * w..source * w + self.n]
    }

    /// Breadth-first search from `s`.
    fn rebuild(&mut self, s: usize) {
        let w = self.n + 1;
        let row = &mut self.dist[s * w..(s + 1) * w];
        row.copy_from_slice(&self.template);
        row[s] = 0;
        self.queue.clear();
        self.queue.push(s as u32);
        spread(row, &mut self.queue, &self.neighbours);
    }

    /// Brings row `s` up to date with the cells logged since its last use: each new cell
    /// takes one more than its nearest passable neighbour, and shorter distances spread from
    /// it. Every value stays the length of a walk through passable cells, and when the queue
    /// is empty no edge between passable cells can shorten a distance: the row is the
    /// breadth-first one.
    fn apply_log(&mut self, s: usize) {
        let w = self.n + 1;
        let row = &mut self.dist[s * w..(s + 1) * w];
        self.queue.clear();
        let pending = &self.log[self.applied[s] as usize..];
        for &v in pending {
            if row[v as usize] == BLOCKED {
                row[v as usize] = UNREACHED;
            }
        }
        for &v in pending {
            let v = v as usize;
            // BLOCKED cells hold u16::MAX: the minimum ignores them.
            let best = self.neighbours[v]
                .iter()
                .map(|&k| row[k as usize])
                .min()
                .unwrap_or(BLOCKED);
            if best < UNREACHED && best + 1 < row[v] {
                row[v] = best + 1;
                self.queue.push(v as u32);
            }
        }
        spread(row, &mut self.queue, &self.neighbours);
    }

    /// The first step (direction index, E N W S) from `source` toward reached cell `target`
    /// on the lexicographically smallest shortest path, from the updated row of `source` (see
    /// the [module documentation](self)); `None` when `target` is the source or unreached.
    pub fn first_step(&mut self, source: usize, target: usize) -> Option<u8> {
        let w = self.n + 1;
        let dist = &self.dist[source * w..(source + 1) * w];
        let d = dist[target];
        if target == source || d >= UNREACHED {
            return None;
        }
        if d == 1 {
            return self.neighbours[source]
                .iter()
                .position(|&k| k as usize == target)
                .map(|k| k as u8);
        }
        self.mark.clear();
        // Walk back from the target over cells one step nearer, down to the cells at 1.
        self.queue.clear();
        self.queue.push(target as u32);
        self.mark.mark(target);
        let mut head = 0;
        while head < self.queue.len() {
            let i = self.queue[head] as usize;
            head += 1;
            let want = dist[i] - 1;
            if want == 1 {
                // Predecessors at distance 1 are neighbours of the source: mark them only.
                for &k in &self.neighbours[i] {
                    if dist[k as usize] == 1 {
                        self.mark.mark(k as usize);
                    }
                }
                continue;
            }
            for &k in &self.neighbours[i] {
                let k = k as usize;
                if dist[k] == want && !self.mark.is_marked(k) {
                    self.mark.mark(k);
                    self.queue.push(k as u32);
                }
            }
        }
        self.neighbours[source]
            .iter()
            .position(|&k| self.mark.is_marked(k as usize) && dist[k as usize] == 1)
            .map(|k| k as u8)
    }
}

/// Spreads shorter distances through passable cells from the cells in `queue` (first in, first
/// out): a cell takes one more than the cell it is reached from when that is shorter. From a
/// single source on a fresh row this is the breadth-first search.
fn spread(row: &mut [u16], queue: &mut Vec<u32>, neighbours: &[[u32; 4]]) {
    let mut head = 0;
    while head < queue.len() {
        let i = queue[head] as usize;
        head += 1;
        let d = row[i] + 1;
        for &k in &neighbours[i] {
            let k = k as usize;
            if d < row[k] && row[k] != BLOCKED {
                row[k] = d;
                queue.push(k as u32);
            }
        }
    }
}
