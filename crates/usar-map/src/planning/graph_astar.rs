//! A* on any graph (the Behavioral Trace Map's nodes and links, a room graph): a thin layer over
//! the `pathfinding` crate's [`astar`], which takes `successors`, `heuristic` and `success`
//! closures and breaks ties toward the larger cost so far.
//!
//! `pathfinding` needs a totally ordered cost; [`graph_astar`] takes `f64` costs (metres,
//! seconds) and orders them with [`f64::total_cmp`].
//!
//! ```
//! use usar_map::planning::graph_astar;
//!
//! // A square a-b-c-d with a long diagonal a-c.
//! let links = |n: &char| -> Vec<(char, f64)> {
//!     match n {
//!         'a' => vec![('b', 1.0), ('d', 1.0), ('c', 5.0)],
//!         'b' => vec![('a', 1.0), ('c', 1.0)],
//!         'c' => vec![('b', 1.0), ('d', 1.0), ('a', 5.0)],
//!         _ => vec![('a', 1.0), ('c', 1.0)],
//!     }
//! };
//! let (path, cost) = graph_astar(&'a', links, |_| 0.0, |n| *n == 'c').unwrap();
//! assert_eq!(cost, 2.0);
//! assert_eq!(path.len(), 3);
//! ```

use pathfinding::num_traits::Zero;
use std::cmp::Ordering;
use std::hash::Hash;
use std::ops::Add;

pub use pathfinding::directed::astar::{astar, astar_bag};

/// An `f64` cost with a total order, for `pathfinding`'s integer-like cost bound.
#[derive(Clone, Copy, Debug, Default)]
pub struct TotalCost(pub f64);

impl PartialEq for TotalCost {
    fn eq(&self, other: &Self) -> bool {
        self.0.total_cmp(&other.0) == Ordering::Equal
    }
}
impl Eq for TotalCost {}
impl PartialOrd for TotalCost {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for TotalCost {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0)
    }
}
impl Add for TotalCost {
    type Output = TotalCost;
    fn add(self, rhs: Self) -> Self {
        TotalCost(self.0 + rhs.0)
    }
}
impl Zero for TotalCost {
    fn zero() -> Self {
        TotalCost(0.0)
    }
    fn is_zero(&self) -> bool {
        self.0 == 0.0
    }
}

/// A least-cost path from `start` to the first node where `success` holds, with its cost.
///
/// - `successors(n)` lists `(neighbour, cost)` pairs; costs must be finite and non-negative.
/// - `heuristic(n)` must not overestimate the remaining cost (admissible), or a longer path may
///   be returned; `|_| 0.0` turns the search into Dijkstra's.
///
/// Returns `None` when no node satisfying `success` is reachable.
pub fn graph_astar<N, FN, IN, FH, FS>(
    start: &N,
    mut successors: FN,
    mut heuristic: FH,
    success: FS,
) -> Option<(Vec<N>, f64)>
where
    N: Eq + Hash + Clone,
    FN: FnMut(&N) -> IN,
    IN: IntoIterator<Item = (N, f64)>,
    FH: FnMut(&N) -> f64,
    FS: FnMut(&N) -> bool,
{
    astar(
        start,
        |n| successors(n).into_iter().map(|(m, c)| (m, TotalCost(c))),
        |n| TotalCost(heuristic(n)),
        success,
    )
    .map(|(path, cost)| (path, cost.0))
}
