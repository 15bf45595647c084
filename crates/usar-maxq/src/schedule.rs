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

    /// Checks that the schedule stays in [0, 1] (a rate or a probability): `start` and `min`
    /// in [0, 1] with `min ≤ start`, a finite `decrement ≥ 0`, `every_steps ≥ 1`. The error
    /// names the sub-field and says what was expected.
    pub fn validate(&self) -> Result<(), ParamError> {
        for (field, v) in [("start", self.start), ("min", self.min)] {
            if !(0.0..=1.0).contains(&v) {
                return Err(ParamError::new(field, v, "a value in [0, 1]"));
            }
        }
        if self.min > self.start {
            return Err(ParamError::new(
                "min",
                self.min,
                format!("at most start ({})", self.start),
            ));
        }
        if !(self.decrement.is_finite() && self.decrement >= 0.0) {
            return Err(ParamError::new(
                "decrement",
                self.decrement,
                "a finite number ≥ 0",
            ));
        }
        if self.every_steps == 0 {
            return Err(ParamError::new("every_steps", 0, "at least 1"));
        }
        Ok(())
    }

    /// The value after `steps` primitive steps: max(min, start − decrement · ⌊steps / every⌋).
    pub fn at(&self, steps: u64) -> f64 {
        let k = steps / self.every_steps.max(1);
        (self.start - self.decrement * k as f64).max(self.min)
    }
}

/// A learning parameter outside what learning can use.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{field}: found {found}, expected {expected}")]
pub struct ParamError {
    /// The field's path (`gamma`, `alpha.min`, …).
    pub field: String,
    pub found: String,
    pub expected: String,
}

impl ParamError {
    pub fn new(
        field: impl Into<String>,
        found: impl std::fmt::Display,
        expected: impl Into<String>,
    ) -> Self {
        Self {
            field: field.into(),
            found: found.to_string(),
            expected: expected.into(),
        }
    }

    /// The same error under `parent` (`min` → `alpha.min`).
    pub fn within(mut self, parent: &str) -> Self {
        self.field = format!("{parent}.{}", self.field);
        self
    }
}
