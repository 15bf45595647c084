//! The layout styles of paper 000 §VI: the random training scenes and the evaluation scenes A, B
//! and C (Fig. 8), each with the class shares its layouts keep to.

use std::ops::RangeInclusive;

/// Which kind of arena to generate (paper 000 §VI).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RubbleStyle {
    /// The training scenes (§VI-A, §VI-B): "a high density of non-climbable obstacles", "many
    /// isolated regions separated by non-climbable obstacles in which the robot could only enter
    /// through a single open cell or by traversing over climbable obstacles".
    #[default]
    Random,
    /// Scene A: "the largest amount of climbable and non-climbable obstacles".
    SceneA,
    /// Scene B: "more isolated regions connected by single cell openings".
    SceneB,
    /// Scene C: "sizeable rubble boundaries created by large numbers of adjacent non-climbable
    /// cells".
    SceneC,
}

/// The share of the arena's coarse cells (0–1) of each intended terrain class that a style keeps
/// to; the rest is open floor (victims lie on open or climbable terrain and do not change the
/// shares).
#[derive(Clone, Debug, PartialEq)]
pub struct ClassShares {
    pub non_climbable: RangeInclusive<f64>,
    pub climbable: RangeInclusive<f64>,
    pub drop: RangeInclusive<f64>,
}

/// How a style builds its layout (see `layout::build`).
#[derive(Clone, Debug)]
pub(super) struct StyleConfig {
    pub shares: ClassShares,
    /// Number of regions the barriers divide the arena into.
    pub regions: RangeInclusive<u32>,
    /// Thickness of a barrier, coarse cells.
    pub barrier_thickness: RangeInclusive<i32>,
    /// Probability that a barrier's gate is climbable rubble rather than a single open cell.
    pub climbable_gate_probability: f64,
    /// Whether one victim must be reachable only over climbable rubble (and so one gate climbable).
    pub needs_climb_only_victim: bool,
}

impl RubbleStyle {
    pub const ALL: [RubbleStyle; 4] = [
        RubbleStyle::Random,
        RubbleStyle::SceneA,
        RubbleStyle::SceneB,
        RubbleStyle::SceneC,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            RubbleStyle::Random => "random",
            RubbleStyle::SceneA => "scene-a",
            RubbleStyle::SceneB => "scene-b",
            RubbleStyle::SceneC => "scene-c",
        }
    }

    /// The class shares of the style's layouts. The paper shows its scenes only as pictures
    /// (Fig. 8); these ranges order the styles as its text does: A has the most climbable and,
    /// with C, the most non-climbable rubble, B the fewest obstacles but the most regions, C the
    /// thickest barriers.
    pub fn class_shares(self) -> ClassShares {
        self.config().shares
    }

    /// Whether at least one victim is reachable only over climbable rubble.
    pub fn needs_climb_only_victim(self) -> bool {
        self.config().needs_climb_only_victim
    }

    pub(super) fn config(self) -> StyleConfig {
        match self {
            RubbleStyle::Random => StyleConfig {
                shares: ClassShares {
                    non_climbable: 0.30..=0.42,
                    climbable: 0.08..=0.16,
                    drop: 0.01..=0.03,
                },
                regions: 4..=7,
                barrier_thickness: 1..=1,
                climbable_gate_probability: 0.5,
                needs_climb_only_victim: true,
            },
            RubbleStyle::SceneA => StyleConfig {
                shares: ClassShares {
                    non_climbable: 0.36..=0.46,
                    climbable: 0.16..=0.24,
                    drop: 0.01..=0.03,
                },
                regions: 3..=4,
                barrier_thickness: 1..=1,
                climbable_gate_probability: 0.5,
                needs_climb_only_victim: true,
            },
            RubbleStyle::SceneB => StyleConfig {
                shares: ClassShares {
                    non_climbable: 0.26..=0.36,
                    climbable: 0.02..=0.06,
                    drop: 0.0..=0.02,
                },
                regions: 7..=9,
                barrier_thickness: 1..=1,
                climbable_gate_probability: 0.0,
                needs_climb_only_victim: false,
            },
            RubbleStyle::SceneC => StyleConfig {
                shares: ClassShares {
                    non_climbable: 0.42..=0.54,
                    climbable: 0.06..=0.12,
                    drop: 0.01..=0.03,
                },
                regions: 3..=5,
                barrier_thickness: 2..=3,
                climbable_gate_probability: 0.3,
                needs_climb_only_victim: true,
            },
        }
    }
}

impl std::fmt::Display for RubbleStyle {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

impl std::str::FromStr for RubbleStyle {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        RubbleStyle::ALL
            .into_iter()
            .find(|k| k.as_str() == s)
            .ok_or_else(|| {
                format!(
                    "unknown rubble style {s:?}, expected one of: random, scene-a, scene-b, scene-c"
                )
            })
    }
}
