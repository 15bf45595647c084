//! Making any map a paper-002 scene: a room layer from the room segmentation when the scene has
//! none (real maps, imported images, scene files without rooms), and start poses for the whole
//! team when the scene has fewer than robots (an imported map has one).

use usar_map::segmentation::edt::squared_edt;
use usar_map::segmentation::{SegmentationParams, segment_scene};
use usar_world::{Pose2, Scene, obstacle};

/// What [`prepare_scene`] changed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Prepared {
    /// Rooms the segmentation made (0 when the scene had a room layer).
    pub segmented_rooms: usize,
    /// Start poses added.
    pub added_start_poses: usize,
}

/// Gives `scene` a room layer (segmenting its free space with `params` if it has no rooms) and
/// at least `robots` start poses (see [`add_start_poses`]).
pub fn prepare_scene(
    scene: &mut Scene,
    robots: usize,
    clearance_m: f64,
    params: &SegmentationParams,
) -> Prepared {
    let mut prepared = Prepared::default();
    if scene.rooms.is_empty() {
        let seg = segment_scene(scene, params);
        seg.apply_to(scene);
        prepared.segmented_rooms = scene.rooms.len();
    }
    prepared.added_start_poses = add_start_poses(scene, robots, clearance_m);
    prepared
}

/// Adds start poses (heading east) until the scene has `robots`, on cells at least `clearance_m`
/// from every obstacle and at least `2 × clearance_m` (and 1 m) from every other start pose,
/// taken in breadth-first order (4-connected through such cells) from the first start pose — or,
/// if there is none, from the free cell farthest from the obstacles. Returns how many were added
/// (fewer when the space around the first pose is too small).
pub fn add_start_poses(scene: &mut Scene, robots: usize, clearance_m: f64) -> usize {
    if scene.start_poses.len() >= robots {
        return 0;
    }
    let g = *scene.geometry();
    let (w, h) = (g.width as usize, g.height as usize);
    let free: Vec<bool> = scene
        .obstacle
        .as_slice()
        .iter()
        .map(|&o| o == obstacle::NONE)
        .collect();
    let d2 = squared_edt(&free, w, h);
    let res = g.resolution_m;
    let min_d2 = ((clearance_m / res).powi(2)) as f32;
    let open = |i: usize| free[i] && d2[i] >= min_d2;
    let start = match scene.start_poses.first() {
        Some(p) => g.index(g.world_to_cell(p.position())),
        None => match (0..d2.len()).filter(|&i| free[i]).max_by(|&a, &b| {
            d2[a].total_cmp(&d2[b]).then(b.cmp(&a)) // ties: lower index
        }) {
            Some(i) => i,
            None => return 0,
        },
    };
    let spacing = (2.0 * clearance_m).max(1.0);
    let mut seen = vec![false; free.len()];
    let mut queue = std::collections::VecDeque::from([start]);
    seen[start] = true;
    let before = scene.start_poses.len();
    while let Some(i) = queue.pop_front() {
        if scene.start_poses.len() >= robots {
            break;
        }
        let p = g.cell_center(g.cell_of_index(i));
        if open(i)
            && scene
                .start_poses
                .iter()
                .all(|q| q.position().distance(p) >= spacing)
        {
            scene.start_poses.push(Pose2::new(p.x, p.y, 0.0));
        }
        let (c, r) = (i % w, i / w);
        let next = [
            (c > 0).then(|| i - 1),
            (c + 1 < w).then(|| i + 1),
            (r > 0).then(|| i - w),
            (r + 1 < h).then(|| i + w),
        ];
        for j in next.into_iter().flatten() {
            // The start cell may be tight; spread only through open cells.
            if !seen[j] && open(j) {
                seen[j] = true;
                queue.push_back(j);
            }
        }
    }
    scene.start_poses.len() - before
}
