//! Schedules for the learning rate α and the exploration rate ε.
//!
//! Paper 000 §VI-A: "both start at 1 and decrease by 0.01 every 100 primitive steps". A
//! [`Schedule`] is that rule with its numbers as parameters: `start`, minus `decrement` after
//! every `every_steps` primitive steps, never below `min`.

use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Schedule {
    pub start: f64,
    pub decrement: f64,
    pub every_steps: u64,
    pub min: f64,
}

impl Schedule {
    /// A value that never changes.
    pub const fn constant(v: f64) -> Self {
        Self {
            start: v,
            decrement: 0.0,
            every_steps: 1,
            min: v,
        }
    }

    /// Paper 000's schedule: 1, minus 0.01 every 100 primitive steps, down to `min`.
    pub const fn paper_000(min: f64) -> Self {
        Self {
            start: 1.0,
            decrement: 0.01,
            every_steps: 100,
            min,
        }
    }

    /// The value after `steps` primitive steps: max(min, start − decrement · ⌊steps / every⌋).
    pub fn at(&self, steps: u64) -> f64 {
        let k = steps / self.every_steps.max(1);
        (self.start - self.decrement * k as f64).max(self.min)
    }
}
