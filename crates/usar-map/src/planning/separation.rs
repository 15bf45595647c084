//! A quick, exact "no path" answer for [`super::GridAStar`]: a search for an unreachable goal
//! examines the start's whole connected part of the grid before it fails, and on a robot's map
//! most such queries have a goal in a small pocket (a frontier behind a gap the robot's radius
//! closes) or a start in one.
//!
//! Both movement models of the planners allow a diagonal move only when both orthogonal cells
//! beside it are passable, so two cells are connected exactly when they are 4-connected. Two
//! breadth-first floods, one from the start and one from the goal, grow one cell at a time in
//! turn: when one of them has reached every cell of its part without meeting the other, the
//! two parts differ and no path exists. When they meet, or both grow past a bound, the answer is
//! "maybe", and the search runs as before: the paths found are unchanged, only failures end
//! sooner.

use super::nav_grid::{NavGrid, PASSABLE};

/// Cells each flood may expand before it stops (some microseconds). On the office floor's
/// team runs the smaller part of an unreachable query had fewer than 64 cells three times in
/// four and more than 1024 one time in forty; a connected query, whose floods must grow until
/// they meet, pays up to twice this.
const MAX_CELLS_PER_SIDE: usize = 1024;

/// Scratch memory of the two floods, kept between queries.
#[derive(Clone, Debug, Default)]
pub(crate) struct Separation {
    /// Per padded cell: `2·query` once the start's flood reached it, `2·query + 1` once the
    /// goal's did, anything else: not reached in this query.
    mark: Vec<u32>,
    query: u32,
    queues: [Vec<u32>; 2],
}

impl Separation {
    /// Whether the passable padded cells `start` and `goal` certainly lie in different
    /// connected parts of `grid` (`false`: connected, or not known within the bound).
    pub(crate) fn separated(&mut self, grid: &NavGrid, start: usize, goal: usize) -> bool {
        if start == goal {
            return false;
        }
        let cells = grid.cells();
        if self.mark.len() < cells.len() {
            self.mark.resize(cells.len(), 0);
        }
        if self.query >= u32::MAX / 2 - 1 {
            self.mark.fill(0);
            self.query = 0;
        }
        self.query += 1;
        let own = [2 * self.query, 2 * self.query + 1];
        let s = grid.stride() as isize;
        let offsets = [1, s, -1, -s];
        let mark = &mut self.mark[..];
        let mut heads = [0usize; 2];
        for (side, &cell) in [start, goal].iter().enumerate() {
            mark[cell] = own[side];
            self.queues[side].clear();
            self.queues[side].push(cell as u32);
        }
        loop {
            let mut grew = false;
            for side in 0..2 {
                if heads[side] >= MAX_CELLS_PER_SIDE {
                    // Past the bound: this flood stops, the other may still finish.
                    continue;
                }
                let queue = &mut self.queues[side];
                let Some(&cur) = queue.get(heads[side]) else {
                    // This flood has its whole part, and never met the other one.
                    return true;
                };
                grew = true;
                heads[side] += 1;
                for &o in &offsets {
                    let next = (cur as usize).wrapping_add_signed(o);
                    if cells[next] != PASSABLE || mark[next] == own[side] {
                        continue;
                    }
                    if mark[next] == own[1 - side] {
                        return false;
                    }
                    mark[next] = own[side];
                    queue.push(next as u32);
                }
            }
            if !grew {
                return false;
            }
        }
    }
}
