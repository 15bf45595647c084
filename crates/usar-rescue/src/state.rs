//! The state the MAXQ engine sees: a small copy of what each subtask's abstraction reads,
//! rebuilt by the domain after every primitive (the map and the robot stay in the domain).

/// The status of the possible victim the robot is dealing with (the V of Root's state).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum VictimStatus {
    /// No undecided possible victim the robot can reach.
    None = 0,
    /// One is pending; the robot must move next to it and face it.
    ToReach = 1,
    /// At hand with p > 0.7.
    CertainAtHand = 2,
    /// At hand with 0.3 ≤ p ≤ 0.7: the operator decides.
    UncertainAtHand = 3,
}

const STUCK: u8 = 1;
const TARGETS: u8 = 2;
const DONE: u8 = 4;
const HEADING: u8 = 8;
const VICTIM_MODE: u8 = 16;
const ON_COURSE: u8 = 32;

/// See the [module documentation](self).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct RescueState {
    flags: u8,
    /// [`VictimStatus`] as a number.
    pub victim: u8,
    /// NG's abstract state (see `hierarchy`).
    pub ng: u16,
    pub forward: u8,
    pub backward: u8,
    pub rotate: u8,
    /// Counts exploration progress (cells entered or classified for the first time, victims
    /// reached or decided); NG ends when it changes.
    pub progress: u32,
    /// The robot's cell (row-major index) and heading.
    pub cell: u16,
    pub heading: u8,
    /// The flat learner's key: the whole unabstracted state (see
    /// [`crate::RescueDomain::state`]).
    pub flat: u64,
}

impl RescueState {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        stuck: bool,
        targets_remain: bool,
        done: bool,
        has_heading: bool,
        victim: VictimStatus,
        ng: u16,
        forward: u8,
        backward: u8,
        rotate: u8,
        progress: u32,
        cell: u16,
        heading: u8,
    ) -> Self {
        let flag = |b: bool, f: u8| if b { f } else { 0 };
        let victim_mode = victim != VictimStatus::None;
        Self {
            flags: flag(stuck, STUCK)
                | flag(targets_remain, TARGETS)
                | flag(done, DONE)
                | flag(has_heading, HEADING)
                | flag(victim_mode, VICTIM_MODE),
            victim: victim as u8,
            ng,
            forward,
            backward,
            rotate,
            progress,
            cell,
            heading,
            flat: 0,
        }
    }

    /// Sets the flat learner's key.
    pub fn with_flat_key(mut self, key: u64) -> Self {
        self.flat = key;
        self
    }

    pub fn stuck(&self) -> bool {
        self.flags & STUCK != 0
    }
    /// Whether cells of interest the robot can reach remain.
    pub fn targets_remain(&self) -> bool {
        self.flags & TARGETS != 0
    }
    pub fn done(&self) -> bool {
        self.flags & DONE != 0
    }
    /// Whether NG has somewhere to head (exploration target or victim).
    pub fn has_heading(&self) -> bool {
        self.flags & HEADING != 0
    }
    /// Marks that the last primitive kept the robot on course: it moved one cell along the
    /// desired heading or made exploration progress (NG's pseudo-reward).
    pub fn with_on_course(mut self, on_course: bool) -> Self {
        if on_course {
            self.flags |= ON_COURSE;
        }
        self
    }
    /// Whether the cell behind is one the robot has crossed (visited, see `backward`): the
    /// only cells it reverses into.
    pub fn back_visited(&self) -> bool {
        self.backward >> 1 == 2
    }
    pub fn on_course(&self) -> bool {
        self.flags & ON_COURSE != 0
    }
    pub fn victim_mode(&self) -> bool {
        self.flags & VICTIM_MODE != 0
    }
    pub fn victim_status(&self) -> VictimStatus {
        match self.victim {
            1 => VictimStatus::ToReach,
            2 => VictimStatus::CertainAtHand,
            3 => VictimStatus::UncertainAtHand,
            _ => VictimStatus::None,
        }
    }

    /// The flat learner's key: the whole unabstracted state.
    pub fn flat_key(&self) -> u64 {
        self.flat
    }
}
