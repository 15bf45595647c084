//! Free space (§III-A-1, §IV-B): the entrance node, following the nearer wall round the open
//! area, and the exit node.

use super::*;

/// A free space must be driven this far before its exit may be declared, metres.
const FREE_SPACE_MIN_M: f64 = 2.0;
/// Around the entrance of a free space the walls are not followed out of it, metres.
const ENTRANCE_ZONE_M: f64 = 1.5;

/// The state of a walk through a free space.
pub(super) struct FreeSpaceWalk {
    pub(super) entrance: u32,
    pub(super) right_wall: bool,
    pub(super) seeking: bool,
    pub(super) passes: u32,
    pub(super) away: bool,
    pub(super) entered_driven_m: f64,
}

impl Explorer<'_> {
    pub(super) fn enter_free_space(&mut self, mut ex: Exploration) -> Result<Velocity, BuildError> {
        let at_driven = self.driven_m - self.cfg.free_space_strip_half_m;
        let at = ex
            .rec
            .position_at(at_driven)
            .unwrap_or(self.pose().position());
        let node = self
            .map
            .add_node(at, kind::FREE_SPACE, Some(subtype::ENTRANCE), |_| {})?;
        let before = ex.rec.split_before(at_driven);
        let from = self.node_position(ex.from);
        self.map
            .close_link(ex.link, node, before.measures(from, at))?;
        ex.link = self.map.add_unsearched(node, self.pose().theta)?;
        ex.from = node;
        ex.phase = Phase::FreeSpace {
            entrance: node,
            right_wall: true,
            seeking: true,
            passes: 0,
            away: false,
            exit: ExitTracker::default(),
            entered_driven_m: self.driven_m,
        };
        self.state = State::Explore(ex);
        Ok(Velocity::default())
    }

    pub(super) fn free_space(
        &mut self,
        mut ex: Exploration,
        mut walk: FreeSpaceWalk,
        mut exit: ExitTracker,
    ) -> Result<Velocity, BuildError> {
        self.mode = RunMode::WallFollowing;
        let cfg = self.cfg;
        let here = self.pose().position();
        let inside_m = self.driven_m - walk.entered_driven_m;
        let entrance_at = self.node_position(walk.entrance);
        let from_entrance = here.distance(entrance_at);
        let near_entrance = inside_m > FREE_SPACE_MIN_M && from_entrance < ENTRANCE_ZONE_M;
        if from_entrance > 2.0 * ENTRANCE_ZONE_M {
            walk.away = true;
        } else if near_entrance && walk.away {
            walk.away = false;
            walk.passes += 1;
        }
        if walk.passes >= 2 {
            // Round every wall back to the entrance twice: no other way out.
            self.map.close_link(
                ex.link,
                walk.entrance,
                ex.rec.measures(entrance_at, entrance_at),
            )?;
            self.plan_return(walk.entrance)?;
            return Ok(Velocity::default());
        }
        if inside_m > FREE_SPACE_MIN_M
            && !near_entrance
            && let Some(at) = exit.update(
                self.beside(),
                cfg.free_space_clearance_m,
                self.step_m,
                here,
                cfg.free_space_exit_confirm_m,
            )
        {
            let node = self
                .map
                .add_node(at, kind::FREE_SPACE, Some(subtype::EXIT), |_| {})?;
            self.map
                .close_link(ex.link, node, ex.rec.measures(entrance_at, at))?;
            ex.link = self.map.add_unsearched(node, self.pose().theta)?;
            ex.from = node;
            ex.rec = LinkRecorder::default();
            ex.phase = Phase::Running;
            self.state = State::Explore(ex);
            return Ok(Velocity::default());
        }
        // Straight into the open area until a wall is met: turning at once towards the side
        // wall would lead round the door jamb and back out of the entrance. Straight on past
        // the entrance too when the walls lead back to it, to follow them further.
        let blocked_ahead =
            self.view.front_clearance(self.spec.width_m / 2.0 + 0.1) < cfg.wall_distance_m + 0.1;
        if walk.seeking {
            // The wall met decides the side (§IV-B: the nearer wall is followed); met head-on,
            // the nearer side wall, ties going right.
            let right = side_distance(&self.view, true);
            let left = side_distance(&self.view, false);
            if right < cfg.wall_distance_m || left < cfg.wall_distance_m || blocked_ahead {
                walk.seeking = false;
                walk.right_wall =
                    if right < cfg.wall_distance_m || left < cfg.wall_distance_m {
                        right <= left
                    } else {
                        follow_right_wall(self.view.side_clearance(
                            -cfg.free_space_strip_half_m,
                            cfg.free_space_strip_half_m,
                        ))
                    };
            }
        }
        let seeking = walk.seeking || (near_entrance && !blocked_ahead);
        let right_wall = walk.right_wall;
        let v = if seeking {
            target_approach(Point2::new(cfg.look_ahead_m, 0.0), self.gains())
        } else {
            wall_following(
                &self.view,
                right_wall,
                cfg.wall_distance_m,
                cfg.look_ahead_m,
                self.spec.width_m / 2.0,
                self.gains(),
            )
        };
        ex.phase = Phase::FreeSpace {
            entrance: walk.entrance,
            right_wall: walk.right_wall,
            seeking: walk.seeking,
            passes: walk.passes,
            away: walk.away,
            exit,
            entered_driven_m: walk.entered_driven_m,
        };
        self.state = State::Explore(ex);
        Ok(v)
    }
}
