//! The checks a team configuration passes before a team is built.

use super::*;

impl TeamConfig {
    /// Checks every field a team reads (timing, map resolution against the scene's
    /// `scene_resolution_m`, measures, label errors, radio, failures, stop rule) and returns the
    /// fuzzy measures of the MCDM strategies.
    pub fn check(&self, scene_resolution_m: f64) -> Result<Measures, MissionError> {
        if self.robots == 0 {
            return Err(MissionError::Config("robots must be at least 1".into()));
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
                return Err(MissionError::Config(format!(
                    "{name} must be a positive number of seconds, found {v}"
                )));
            }
        }
        if let Some(r) = self.map_resolution_m
            && !(r.is_finite() && r >= scene_resolution_m)
        {
            return Err(MissionError::Config(format!(
                "map_resolution_m: found {r}, expected at least the scene's {scene_resolution_m} m"
            )));
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
        if x.bid_grid_factor == 0 || x.max_robots_per_candidate == 0 {
            return Err(MissionError::Config(
                "bid_grid_factor and max_robots_per_candidate must be at least 1".into(),
            ));
        }
        if !(0.0..=1.0).contains(&self.radio.drop_probability) {
            return Err(MissionError::Config(format!(
                "radio drop probability: found {}, expected a probability in [0, 1]",
                self.radio.drop_probability
            )));
        }
        if let Some(r) = self.radio.range_m
            && !(r.is_finite() && r > 0.0)
        {
            return Err(MissionError::Config(format!(
                "radio range: found {r} m, expected a positive distance"
            )));
        }
        if let Some(f) = self.failures.iter().find(|f| f.robot >= self.robots) {
            return Err(MissionError::Config(format!(
                "failure of robot {}: the team has robots 0 to {}",
                f.robot,
                self.robots - 1
            )));
        }
        if let Some(f) = self.stop_at_relevant
            && !(0.0..=1.0).contains(&f)
        {
            return Err(MissionError::Config(format!(
                "stop_at_relevant: found {f}, expected a fraction in [0, 1]"
            )));
        }
        Ok(measures)
    }
}
