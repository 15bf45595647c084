//! The checks a team configuration passes before a team is built.

use super::*;

/// A setting of a team configuration holding a value it does not accept.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{field}: found {found}, expected {expected}")]
pub struct ConfigError {
    pub field: String,
    pub found: String,
    pub expected: String,
}

pub(super) fn invalid(
    field: &str,
    found: impl std::fmt::Display,
    expected: impl std::fmt::Display,
) -> MissionError {
    MissionError::Config(ConfigError {
        field: field.into(),
        found: found.to_string(),
        expected: expected.to_string(),
    })
}

impl TeamConfig {
    /// Checks the fields a team reads before it starts (the team size, timing, map resolution
    /// against the scene's `scene_resolution_m`, measures, label errors, bid grid, i(p)'s
    /// bound, radio, failures' robots, the relevant-area stop) and returns the fuzzy measures of
    /// the MCDM strategies.
    pub fn check(&self, scene_resolution_m: f64) -> Result<Measures, MissionError> {
        if self.robots == 0 {
            return Err(invalid("robots", 0, "at least 1"));
        }
        let t = &self.timing;
        for (name, v) in [
            ("scan_period_s", t.scan_period_s),
            ("merge_period_s", t.merge_period_s),
            ("assignment_period_s", t.assignment_period_s),
            ("thermal_period_s", t.thermal_period_s),
            ("sample_period_s", t.sample_period_s),
            ("sim.dt_s", self.sim.dt_s),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(invalid(name, v, "a positive number of seconds"));
            }
        }
        if let Some(r) = self.map_resolution_m
            && !(r.is_finite() && r >= scene_resolution_m)
        {
            return Err(invalid(
                "map_resolution_m",
                r,
                format!("at least the scene's {scene_resolution_m} m"),
            ));
        }
        let x = &self.exploration;
        let measures = Measures {
            s_mcdm: FuzzyMeasure::new(&x.s_mcdm).map_err(|source| MissionError::Measure {
                which: "S-MCDM",
                source,
            })?,
            d_mcdm: FuzzyMeasure::new(&x.d_mcdm).map_err(|source| MissionError::Measure {
                which: "D-MCDM",
                source,
            })?,
        };
        x.label_errors.check()?;
        for (name, v) in [
            ("bid_grid_factor", x.bid_grid_factor),
            ("max_robots_per_candidate", x.max_robots_per_candidate),
        ] {
            if v == 0 {
                return Err(invalid(name, 0, "at least 1"));
            }
        }
        if !(0.0..=1.0).contains(&self.radio.drop_probability) {
            return Err(invalid(
                "radio drop probability",
                self.radio.drop_probability,
                "a probability in [0, 1]",
            ));
        }
        if let Some(r) = self.radio.range_m
            && !(r.is_finite() && r > 0.0)
        {
            return Err(invalid(
                "radio range",
                format!("{r} m"),
                "a positive distance",
            ));
        }
        if let Some(f) = self.failures.iter().find(|f| f.robot >= self.robots) {
            return Err(invalid(
                "failures.robot",
                f.robot,
                format!("a robot of the team, 0 to {}", self.robots - 1),
            ));
        }
        if let Some(f) = self.stop_at_relevant
            && !(0.0..=1.0).contains(&f)
        {
            return Err(invalid("stop_at_relevant", f, "a fraction in [0, 1]"));
        }
        Ok(measures)
    }
}
