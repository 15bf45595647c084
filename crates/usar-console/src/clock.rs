//! The mission clock: simulated time, advanced by the team's simulation thread at a chosen
//! speed, and waited on by the other robots' threads (the MAXQ robot, the BTM builder), so that
//! pause, resume and speed-up act on the whole mission at once.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

/// See the [module documentation](self).
#[derive(Debug, Default)]
pub struct MissionClock {
    time_s: Mutex<f64>,
    ticked: Condvar,
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

    /// Moves the clock to `time_s` (never backwards) and wakes the waiting threads.
    pub fn advance_to(&self, time_s: f64) {
        let mut t = self.time_s.lock().unwrap_or_else(|e| e.into_inner());
        if time_s > *t {
            *t = time_s;
            self.ticked.notify_all();
        }
    }

    /// Blocks until the clock reaches `time_s`; `false` when the mission is stopping.
    pub fn wait_until(&self, time_s: f64) -> bool {
        let mut t = self.time_s.lock().unwrap_or_else(|e| e.into_inner());
        while *t < time_s {
            if self.is_stopping() {
                return false;
            }
            t = self
                .ticked
                .wait_timeout(t, Duration::from_millis(100))
                .unwrap_or_else(|e| e.into_inner())
                .0;
        }
        !self.is_stopping()
    }

    /// Asks every thread waiting on the clock to end.
    pub fn stop(&self) {
        self.stopping.store(true, Ordering::SeqCst);
        self.ticked.notify_all();
    }

    pub fn is_stopping(&self) -> bool {
        self.stopping.load(Ordering::SeqCst)
    }
}
