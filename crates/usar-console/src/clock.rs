//! The mission clock: simulated time as the mission thread moves it, read by the server and
//! the bench, and the flag that asks the mission to stop.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

/// See the [module documentation](self).
#[derive(Debug, Default)]
pub struct MissionClock {
    time_s: Mutex<f64>,
    stopping: AtomicBool,
}

impl MissionClock {
    pub fn new() -> Self {
        Self::default()
    }

    /// Simulated seconds since the mission started.
    pub fn now_s(&self) -> f64 {
        *self.time_s.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Moves the clock to `time_s` (never backwards).
    pub fn advance_to(&self, time_s: f64) {
        let mut t = self.time_s.lock().unwrap_or_else(|e| e.into_inner());
        if time_s > *t {
            *t = time_s;
        }
    }

    /// Asks the mission to end.
    pub fn stop(&self) {
        self.stopping.store(true, Ordering::SeqCst);
    }

    pub fn is_stopping(&self) -> bool {
        self.stopping.load(Ordering::SeqCst)
    }
}
