//! The incremental travel distances (eq. 10) equal a breadth-first search from scratch, and
//! their first step is the one such a search (neighbours E, N, W, S) gives.

use proptest::prelude::*;
use usar_rescue::travel::{TravelDistances, UNREACHED};

const W: usize = 9;
const H: usize = 7;

fn neighbours() -> Vec<[u32; 4]> {
    (0..W * H)
        .map(|i| {
            let (c, r) = ((i % W) as i32, (i / W) as i32);
            [(1, 0), (0, 1), (-1, 0), (0, -1)].map(|(dc, dr)| {
                let (x, y) = (c + dc, r + dr);
                if x < 0 || y < 0 || x >= W as i32 || y >= H as i32 {
                    u32::MAX
                } else {
                    (y as usize * W + x as usize) as u32
                }
            })
        })
        .collect()
}

/// The search the exploration used to run at every step: FIFO, neighbours in order, each
/// cell inheriting the first step of the cell that reached it first.
fn reference(passable: &[bool], start: usize) -> (Vec<u16>, Vec<Option<u8>>) {
    let nb = neighbours();
    let mut dist = vec![UNREACHED; W * H];
    let mut first = vec![None; W * H];
    dist[start] = 0;
    let mut queue = std::collections::VecDeque::from([start]);
    while let Some(i) = queue.pop_front() {
        for (dir, &k) in nb[i].iter().enumerate() {
            if k == u32::MAX {
                continue;
            }
            let k = k as usize;
            if dist[k] != UNREACHED || !passable[k] {
                continue;
            }
            dist[k] = dist[i] + 1;
            first[k] = if i == start {
                Some(dir as u8)
            } else {
                first[i]
            };
            queue.push_back(k);
        }
    }
    (dist, first)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Cells open and close in random order while the robot moves among random sources.
    #[test]
    fn incremental_distances_and_first_steps_match_a_fresh_search(
        events in prop::collection::vec((0..W * H, prop::bool::weighted(0.85), 0..W * H), 1..160)
    ) {
        let mut t = TravelDistances::new(&neighbours());
        let mut passable = vec![false; W * H];
        for (cell, open, source) in events {
            passable[cell] = open;
            t.set_passable(cell, open);
            t.update(source);
            let (dist, first) = reference(&passable, source);
            let row: Vec<u16> = t.row(source).iter().map(|&d| d.min(UNREACHED)).collect();
            prop_assert_eq!(row, dist);
            for (x, &step) in first.iter().enumerate() {
                prop_assert_eq!(t.first_step(source, x), step, "from {} to {}", source, x);
            }
        }
    }
}
