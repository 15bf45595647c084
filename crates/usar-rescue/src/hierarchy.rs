//! The MAXQ task graph of paper 000 (§IV-A, Fig. 2, eq. 4–5) and its state abstractions.
//!
//! ```text
//! Root ─┬─ NUR ─────┬─ Exit USAR Scene
//!       │           ├─ NG ──┬─ F, B, rotate left θ, rotate right θ
//!       │           └─ HC₃ ─┘  (the operator drives; NG learns from it)
//!       ├─ VI ──────┬─ Tag
//!       │           ├─ NG
//!       │           └─ HC₃
//!       └─ HC₂ ─────┬─ Tag            (the operator decides an uncertain victim)
//!                   └─ Reject
//! ```
//!
//! HC appears at two levels as in Fig. 2: HC₂ under Root shares the VI task with the operator
//! (tag or reject a victim the robot is unsure of); HC₃, the sibling of NG under NUR and VI,
//! hands local navigation to the operator when the robot is stuck. Every choice inside an HC
//! node is the operator's ([`usar_maxq::Domain::delegated_choice`]); HC₃'s executed actions
//! also update NG's completion function ([`usar_maxq::Hierarchy::apprentice`]).
//!
//! **State abstractions** (§IV-A). Each subtask keys its table on features of the state
//! variables the paper gives it, never on the raw robot position or map (a table over 20 × 20
//! positions × maps could not be learned; the paper stores 4 288 values in all):
//!
//! | node | paper | features kept | states |
//! |---|---|---|---|
//! | Root | S(V, L_R, M) | victim status V (none, to reach, certain at hand, uncertain at hand); cells of interest left in M; stuck at L_R | 16 |
//! | NUR | S(L_R, M) | cells of interest left; stuck | 4 |
//! | VI | S(L_V/R, M) | victim certain at hand (L_V/R = adjacent, facing); stuck | 4 |
//! | HC₂ | — | one state | 1 |
//! | NG, HC₃ | S(C₁…C₈, D_E, D_xy, L_V/R) | the four cells it can move into or face next (ahead from D_xy, left, right, behind from infrared and the map: unknown, free unvisited, free visited, blocked); the heading toward D_E's target or toward the victim relative to the robot; whether it is heading for a victim | 2 048 |
//! | F / B | — | the cell ahead / behind and whether it is the desired direction | 8 |
//! | rotate | — | whether the cell ahead is an obstacle not yet avoided | 2 |
//! | Tag | — | victim status | 4 |
//! | Exit | — | cells of interest left; victim pending | 4 |
//!
//! The diagonal cells of C₁…C₈ are in the robot's map and in the exploration utility (λ);
//! the navigation table keys only the four cells a 90° cell robot can enter.
//!
//! **Termination.** Root: the robot exits. NUR: a victim becomes pending. VI: no victim is
//! pending, or the one at hand is uncertain (HC₂'s turn). HC₂: the uncertain victim is decided.
//! NG: stuck, nothing to head for, a victim at hand — or, since it started, the robot moved to
//! another cell, classified one (exploration progress) or switched between exploring and
//! approaching a victim; it ends with the pseudo-reward [`NG_ON_COURSE`] when that last step
//! kept to the desired heading (moved along it, or classified a cell while facing it). HC₃:
//! the robot is no longer stuck (an operator command took effect).
//!
//! **Preconditions.** Exit USAR Scene is available only when no cell of interest the robot
//! can reach or face remains (§IV-A-2: Exit "triggers the end of exploration"); NUR then has
//! nothing else to do. B is available only into a cell the robot has already crossed (visited):
//! the depth sensor looks ahead and the rear infrared cannot tell open floor from a drop, so the
//! robot reverses only over ground it has driven on; it enters new cells facing them, and the
//! depth sensor then classifies the cell beyond.

use crate::state::{RescueState, VictimStatus};
use usar_maxq::{Hierarchy, Node, NodeId, NodeKind};

pub const ROOT: NodeId = 0;
pub const NUR: NodeId = 1;
pub const VI: NodeId = 2;
pub const HC_SHARE: NodeId = 3;
pub const NG: NodeId = 4;
pub const HC_NAV: NodeId = 5;
pub const FORWARD: NodeId = 6;
pub const BACKWARD: NodeId = 7;
pub const ROTATE_LEFT: NodeId = 8;
pub const ROTATE_RIGHT: NodeId = 9;
pub const TAG: NodeId = 10;
pub const REJECT: NodeId = 11;
pub const EXIT: NodeId = 12;

/// The primitives' preconditions, for the hierarchy and the flat learner alike: Exit only
/// when nothing is left to explore, B only into a cell the robot has visited.
pub fn action_available(a: usize, s: &RescueState) -> bool {
    match a {
        action::EXIT => !s.targets_remain(),
        action::BACKWARD => s.back_visited(),
        _ => true,
    }
}

/// Primitive actions of the domain (indices of `Domain::step`).
pub mod action {
    pub const FORWARD: usize = 0;
    pub const BACKWARD: usize = 1;
    pub const ROTATE_LEFT: usize = 2;
    pub const ROTATE_RIGHT: usize = 3;
    pub const TAG: usize = 4;
    pub const REJECT: usize = 5;
    pub const EXIT: usize = 6;
    pub const COUNT: usize = 7;
}

/// Size of the NG abstraction: 4⁴ neighbour categories × 4 relative headings × 2 modes.
pub const NG_STATES: usize = 256 * 4 * 2;

/// NG's pseudo-reward R̃ when it ends on course (the robot moved one cell along the desired
/// heading, or made exploration progress facing it): Table I's "moving in the desired
/// exploration direction" (+15), given for every step along D_E's path, also through visited
/// cells. It only shapes NG's own choices (C̃); the parents see the real rewards.
pub const NG_ON_COURSE: f64 = 15.0;

/// Paper 000's hierarchy.
#[derive(Clone, Debug)]
pub struct RescueHierarchy {
    nodes: Vec<Node>,
}

impl Default for RescueHierarchy {
    fn default() -> Self {
        Self::new()
    }
}

impl RescueHierarchy {
    pub fn new() -> Self {
        let composite = |name: &str, children: Vec<NodeId>, states: usize| Node {
            name: name.into(),
            kind: NodeKind::Composite { children },
            states,
        };
        let primitive = |name: &str, action: usize, states: usize| Node {
            name: name.into(),
            kind: NodeKind::Primitive { action },
            states,
        };
        let nav = vec![FORWARD, BACKWARD, ROTATE_LEFT, ROTATE_RIGHT];
        let nodes = vec![
            composite("Root", vec![NUR, VI, HC_SHARE], 16),
            composite("NUR", vec![EXIT, NG, HC_NAV], 4),
            composite("VI", vec![TAG, NG, HC_NAV], 4),
            composite("HC2", vec![TAG, REJECT], 1),
            composite("NG", nav.clone(), NG_STATES),
            composite("HC3", nav, NG_STATES),
            primitive("F", action::FORWARD, 8),
            primitive("B", action::BACKWARD, 8),
            primitive("rotate_left", action::ROTATE_LEFT, 2),
            primitive("rotate_right", action::ROTATE_RIGHT, 2),
            primitive("Tag", action::TAG, 4),
            primitive("Reject", action::REJECT, 1),
            primitive("Exit", action::EXIT, 4),
        ];
        Self { nodes }
    }
}

impl Hierarchy<RescueState> for RescueHierarchy {
    fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    fn root(&self) -> NodeId {
        ROOT
    }

    fn abstraction(&self, node: NodeId, s: &RescueState) -> usize {
        let stuck = usize::from(s.stuck());
        let targets = usize::from(s.targets_remain());
        let victim = s.victim as usize;
        match node {
            ROOT => (victim * 2 + targets) * 2 + stuck,
            NUR => targets * 2 + stuck,
            VI => usize::from(s.victim == VictimStatus::CertainAtHand as u8) * 2 + stuck,
            HC_SHARE | REJECT => 0,
            NG | HC_NAV => usize::from(s.ng),
            FORWARD => usize::from(s.forward),
            BACKWARD => usize::from(s.backward),
            ROTATE_LEFT | ROTATE_RIGHT => usize::from(s.rotate),
            TAG => victim,
            EXIT => targets * 2 + usize::from(victim != 0),
            _ => 0,
        }
    }

    fn terminated(&self, node: NodeId, s: &RescueState) -> bool {
        let victim = s.victim_status();
        match node {
            ROOT => s.done(),
            NUR => victim != VictimStatus::None,
            VI => matches!(victim, VictimStatus::None | VictimStatus::UncertainAtHand),
            HC_SHARE => victim != VictimStatus::UncertainAtHand,
            NG => {
                s.stuck()
                    || !s.has_heading()
                    || matches!(
                        victim,
                        VictimStatus::CertainAtHand | VictimStatus::UncertainAtHand
                    )
            }
            HC_NAV => !s.stuck(),
            _ => false,
        }
    }

    fn available(&self, node: NodeId, s: &RescueState) -> bool {
        match node {
            EXIT => action_available(action::EXIT, s),
            BACKWARD => action_available(action::BACKWARD, s),
            _ => true,
        }
    }

    fn ended_since(&self, node: NodeId, start: &RescueState, now: &RescueState) -> bool {
        node == NG
            && (now.progress != start.progress
                || now.cell != start.cell
                || now.victim_mode() != start.victim_mode())
    }

    fn pseudo_reward(&self, node: NodeId, s: &RescueState) -> f64 {
        if node == NG && s.on_course() {
            NG_ON_COURSE
        } else {
            0.0
        }
    }

    fn apprentice(&self, node: NodeId) -> Option<NodeId> {
        (node == HC_NAV).then_some(NG)
    }
}
