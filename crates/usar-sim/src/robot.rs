//! Robot models: footprint, climbing ability, speeds and sensor mounts. A crawler and a wheeled
//! robot differ in what they can climb, so heterogeneous teams exist (SPEC §0).

use crate::sensors::{DepthSpec, InfraredSpec, LaserSpec, NoiseSpec, ThermalSpec, TiltedLaserSpec};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// How a robot moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Locomotion {
    /// Tracks: climbs rubble, slopes and stairs.
    Crawler,
    /// Wheels: flat floors and gentle ramps only.
    Wheeled,
}

/// A robot model. Loadable from a TOML file (see `docs/robot-format.md`); every field has the
/// default of its preset, so a file may set only what differs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotSpec {
    pub name: String,
    pub locomotion: Locomotion,
    /// Footprint length along the heading, metres.
    pub length_m: f64,
    /// Footprint width, metres.
    pub width_m: f64,
    /// Steepest inclination the robot can drive on, radians.
    pub max_inclination_rad: f64,
    /// Highest step (height difference between neighbouring floor cells) it can climb, metres.
    pub max_step_m: f64,
    pub max_linear_mps: f64,
    pub max_angular_radps: f64,
    pub laser: LaserSpec,
    pub tilted_laser: TiltedLaserSpec,
    pub depth: DepthSpec,
    pub thermal: ThermalSpec,
    pub infrared: InfraredSpec,
    pub noise: NoiseSpec,
}

impl RobotSpec {
    /// A tracked rescue robot (the size of a small crawler such as those of papers 000 and 004):
    /// 0.6 × 0.45 m, climbs 35° slopes and 0.2 m steps, 0.5 m/s.
    pub fn crawler() -> Self {
        Self {
            name: "crawler".into(),
            locomotion: Locomotion::Crawler,
            length_m: 0.6,
            width_m: 0.45,
            max_inclination_rad: 35f64.to_radians(),
            max_step_m: 0.20,
            max_linear_mps: 0.5,
            max_angular_radps: 1.0,
            laser: LaserSpec::default(),
            tilted_laser: TiltedLaserSpec::default(),
            depth: DepthSpec::default(),
            thermal: ThermalSpec::default(),
            infrared: InfraredSpec::default(),
            noise: NoiseSpec::default(),
        }
    }

    /// Paper 000's robot moving cell by cell: the crawler made small enough to turn in place
    /// inside one of the paper's 0.914 m cells with 0.15 m to spare on every side (circumscribed
    /// radius 0.28 m): 0.45 × 0.34 m. The larger [`RobotSpec::crawler`] wedges against rubble
    /// reaching into its cell when it turns.
    pub fn cell_crawler() -> Self {
        Self {
            name: "cell-crawler".into(),
            length_m: 0.45,
            width_m: 0.34,
            ..Self::crawler()
        }
    }

    /// A wheeled indoor robot (a Pioneer-class base as in paper 002's USARSim teams):
    /// 0.5 × 0.4 m, 15° ramps, 0.05 m steps, 0.5 m/s.
    pub fn wheeled() -> Self {
        Self {
            name: "wheeled".into(),
            locomotion: Locomotion::Wheeled,
            length_m: 0.5,
            width_m: 0.4,
            max_inclination_rad: 15f64.to_radians(),
            max_step_m: 0.05,
            max_linear_mps: 0.5,
            max_angular_radps: 1.2,
            ..Self::crawler()
        }
    }

    /// The wheeled robot at 0.3 × its speeds (0.15 m/s, 0.36 rad/s): paper 002's pace, the
    /// default of its team runs. The paper gives no speeds; at this pace D-MCDM + SR with 6
    /// robots explores 3 424 m² of the generated office in 20 minutes (Table 5: 3 060 m²), where
    /// at 0.5 m/s it explores 6 963 m², nearly the whole floor (`docs/paper-002-reproduction.md`).
    pub fn wheeled_paper_pace() -> Self {
        Self {
            name: "wheeled-paper-pace".into(),
            max_linear_mps: 0.15,
            max_angular_radps: 0.36,
            ..Self::wheeled()
        }
    }

    /// A preset by name (`crawler`, `wheeled`, `wheeled-paper-pace`), or `None`.
    pub fn preset(name: &str) -> Option<Self> {
        match name {
            "crawler" => Some(Self::crawler()),
            "cell-crawler" => Some(Self::cell_crawler()),
            "wheeled" => Some(Self::wheeled()),
            "wheeled-paper-pace" => Some(Self::wheeled_paper_pace()),
            _ => None,
        }
    }

    /// Radius of the circle around the footprint: planners inflate obstacles by it so that the
    /// robot can turn anywhere on its path.
    pub fn circumscribed_radius_m(&self) -> f64 {
        0.5 * self.length_m.hypot(self.width_m)
    }

    /// A robot named the way a user names one: a preset (`crawler`, `cell-crawler`,
    /// `wheeled`, `wheeled-paper-pace`) or the path of a robot file.
    pub fn load(spec: &str) -> Result<Self, crate::SimError> {
        if let Some(preset) = Self::preset(spec) {
            return Ok(preset);
        }
        let path = Path::new(spec);
        if !path.exists() {
            return Err(crate::SimError::RobotFile {
                path: spec.to_string(),
                message: "not a robot preset (crawler, cell-crawler, wheeled, wheeled-paper-pace) and no such \
                          robot file"
                    .into(),
            });
        }
        Self::from_toml_file(path)
    }

    /// Reads a robot file (TOML). It names a `preset` to start from and overrides fields of it.
    pub fn from_toml_file(path: &Path) -> Result<Self, crate::SimError> {
        let text = usar_world::limits::read_text(path)?;
        Self::from_toml(&text, path)
    }

    /// Parses a robot file; `path` is used in error messages only.
    pub fn from_toml(text: &str, path: &Path) -> Result<Self, crate::SimError> {
        let bad = |message: String| crate::SimError::RobotFile {
            path: path.display().to_string(),
            message,
        };
        let mut table: toml::Table = toml::from_str(text)
            .map_err(|e: toml::de::Error| bad(usar_world::toml_error_line(text, &e)))?;
        let preset = match table.remove("preset") {
            None => Self::crawler(),
            Some(toml::Value::String(name)) => Self::preset(&name).ok_or_else(|| {
                bad(format!(
                    "field `preset`: found {name:?}, expected \"crawler\", \"wheeled\" or \"wheeled-paper-pace\""
                ))
            })?,
            Some(other) => {
                return Err(bad(format!(
                    "field `preset`: found {other}, expected a string"
                )));
            }
        };
        let mut base = toml::Table::try_from(&preset).map_err(|e| bad(e.to_string()))?;
        merge_tables(&mut base, table);
        let spec: RobotSpec = base
            .try_into()
            .map_err(|e: toml::de::Error| bad(e.message().trim().replace('\n', "; ")))?;
        spec.validate().map_err(|e| bad(e.to_string()))?;
        Ok(spec)
    }

    /// Checks physical plausibility; the error names the field.
    pub fn validate(&self) -> Result<(), FieldError> {
        let positive = [
            ("length_m", self.length_m),
            ("width_m", self.width_m),
            ("max_linear_mps", self.max_linear_mps),
            ("max_angular_radps", self.max_angular_radps),
            ("laser.max_range_m", self.laser.max_range_m),
            ("laser.mount_height_m", self.laser.mount_height_m),
        ];
        for (field, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(FieldError::new(field, v.to_string(), "a positive number"));
            }
        }
        if !(0.0..std::f64::consts::FRAC_PI_2).contains(&self.max_inclination_rad) {
            return Err(FieldError::new(
                "max_inclination_rad",
                self.max_inclination_rad.to_string(),
                "an angle in [0, π/2)",
            ));
        }
        if !(self.max_step_m.is_finite() && self.max_step_m >= 0.0) {
            return Err(FieldError::new(
                "max_step_m",
                self.max_step_m.to_string(),
                "≥ 0 metres",
            ));
        }
        let nonnegative = [
            ("laser.range_noise_sd_m", self.laser.range_noise_sd_m),
            (
                "tilted_laser.range_noise_sd_m",
                self.tilted_laser.range_noise_sd_m,
            ),
            (
                "tilted_laser.mount_height_m",
                self.tilted_laser.mount_height_m,
            ),
            ("depth.mount_height_m", self.depth.mount_height_m),
            (
                "thermal.temperature_noise_sd_c",
                self.thermal.temperature_noise_sd_c,
            ),
            ("thermal.mount_height_m", self.thermal.mount_height_m),
            ("infrared.range_noise_sd_m", self.infrared.range_noise_sd_m),
            ("infrared.mount_height_m", self.infrared.mount_height_m),
            (
                "noise.odometry_translation_sd_per_m",
                self.noise.odometry_translation_sd_per_m,
            ),
            (
                "noise.odometry_rotation_sd_per_rad",
                self.noise.odometry_rotation_sd_per_rad,
            ),
            ("noise.attitude_sd_rad", self.noise.attitude_sd_rad),
        ];
        for (field, v) in nonnegative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(FieldError::new(field, v.to_string(), "a number ≥ 0"));
            }
        }
        let ranges = [
            ("tilted_laser.max_range_m", self.tilted_laser.max_range_m),
            ("depth.max_range_m", self.depth.max_range_m),
            ("thermal.max_range_m", self.thermal.max_range_m),
            ("infrared.max_range_m", self.infrared.max_range_m),
        ];
        for (field, v) in ranges {
            if !(v.is_finite() && v > 0.0) {
                return Err(FieldError::new(field, v.to_string(), "a positive number"));
            }
        }
        let full_turn = std::f64::consts::TAU;
        let fields_of_view = [
            ("laser.fov_rad", self.laser.fov_rad),
            ("tilted_laser.fov_rad", self.tilted_laser.fov_rad),
            ("depth.hfov_rad", self.depth.hfov_rad),
            ("depth.vfov_rad", self.depth.vfov_rad),
            ("thermal.hfov_rad", self.thermal.hfov_rad),
        ];
        for (field, v) in fields_of_view {
            if !(v > 0.0 && v <= full_turn + 1e-9) {
                return Err(FieldError::new(field, v.to_string(), "an angle in (0, 2π]"));
            }
        }
        if !(0.0..=1.0).contains(&self.thermal.size_noise_fraction) {
            return Err(FieldError::new(
                "thermal.size_noise_fraction",
                self.thermal.size_noise_fraction.to_string(),
                "a fraction in [0, 1]",
            ));
        }
        let [low, high] = self.thermal.human_band_c;
        if !(low.is_finite() && high.is_finite() && low <= high) {
            return Err(FieldError::new(
                "thermal.human_band_c",
                format!("[{low}, {high}]"),
                "[low, high] °C with low ≤ high",
            ));
        }
        if let Some(d) = self.infrared.directions_rad.iter().find(|d| !d.is_finite()) {
            return Err(FieldError::new(
                "infrared.directions_rad",
                d.to_string(),
                "finite angles in radians",
            ));
        }
        // Beams are checked against the limit before any scan buffer is sized from them.
        let max_beams = usar_world::limits::limits().max_beams;
        let beams = [
            ("laser.beams", u64::from(self.laser.beams)),
            ("tilted_laser.beams", u64::from(self.tilted_laser.beams)),
            (
                "depth.rows × depth.cols",
                u64::from(self.depth.rows) * u64::from(self.depth.cols),
            ),
            (
                "infrared.directions_rad",
                self.infrared.directions_rad.len() as u64,
            ),
        ];
        for (field, n) in beams {
            if n > max_beams {
                return Err(FieldError::new(
                    field,
                    n.to_string(),
                    format!("at most {max_beams} beams (raise the limit with --max-beams)"),
                ));
            }
        }
        for (field, n) in [
            ("laser.beams", self.laser.beams),
            ("tilted_laser.beams", self.tilted_laser.beams),
            ("depth.rows", self.depth.rows),
            ("depth.cols", self.depth.cols),
        ] {
            if n == 0 {
                return Err(FieldError::new(field, "0", "at least 1"));
            }
        }
        Ok(())
    }
}

/// A field of a robot's model out of its range: which, what was found, what was expected.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("field `{field}`: found {found}, expected {expected}")]
pub struct FieldError {
    pub field: String,
    pub found: String,
    pub expected: String,
}

impl FieldError {
    pub fn new(
        field: impl Into<String>,
        found: impl Into<String>,
        expected: impl Into<String>,
    ) -> Self {
        Self {
            field: field.into(),
            found: found.into(),
            expected: expected.into(),
        }
    }
}

/// Recursively overrides `base` with `over` (tables merge, other values replace).
fn merge_tables(base: &mut toml::Table, over: toml::Table) {
    for (k, v) in over {
        match (base.get_mut(&k), v) {
            (Some(toml::Value::Table(b)), toml::Value::Table(o)) => merge_tables(b, o),
            (_, v) => {
                base.insert(k, v);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn robot_file_overrides_a_preset() {
        let spec = RobotSpec::from_toml(
            "preset = \"wheeled\"\nwidth_m = 0.7\n[laser]\nbeams = 180\n",
            Path::new("r.toml"),
        )
        .unwrap();
        assert_eq!(spec.width_m, 0.7);
        assert_eq!(spec.laser.beams, 180);
        assert_eq!(spec.locomotion, Locomotion::Wheeled);
        assert_eq!(spec.max_step_m, RobotSpec::wheeled().max_step_m);
    }

    #[test]
    fn robot_file_with_a_typo_names_the_field() {
        let err = RobotSpec::from_toml("widht_m = 0.7\n", Path::new("r.toml"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("r.toml") && err.contains("widht_m"), "{err}");
        let err = RobotSpec::from_toml("width_m = -1.0\n", Path::new("r.toml"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("width_m") && err.contains("-1"), "{err}");
    }

    #[test]
    fn every_preset_is_valid() {
        for name in ["crawler", "wheeled", "wheeled-paper-pace"] {
            let spec = RobotSpec::preset(name).unwrap();
            assert_eq!(spec.validate(), Ok(()), "{name}");
        }
    }

    #[test]
    fn a_bad_value_is_a_typed_field_error() {
        let mut spec = RobotSpec::crawler();
        spec.width_m = -0.4;
        assert_eq!(
            spec.validate(),
            Err(FieldError::new("width_m", "-0.4", "a positive number"))
        );
        assert_eq!(
            spec.validate().unwrap_err().to_string(),
            "field `width_m`: found -0.4, expected a positive number"
        );
    }

    #[test]
    fn negative_noise_and_runaway_beams_name_the_field() {
        let err = |text: &str| {
            RobotSpec::from_toml(text, Path::new("r.toml"))
                .unwrap_err()
                .to_string()
        };
        for (text, field) in [
            (
                "[laser]\nrange_noise_sd_m = -0.1\n",
                "laser.range_noise_sd_m",
            ),
            ("[noise]\nattitude_sd_rad = -1.0\n", "noise.attitude_sd_rad"),
            (
                "[thermal]\nsize_noise_fraction = 2.0\n",
                "thermal.size_noise_fraction",
            ),
            ("[laser]\nfov_rad = 0.0\n", "laser.fov_rad"),
            ("[depth]\nrows = 0\n", "depth.rows"),
        ] {
            let e = err(text);
            assert!(e.contains(&format!("field `{field}`")), "{text}: {e}");
        }
        // A duplicate key is named as one, on one line.
        let e = err("width_m = 0.5\nwidth_m = 0.6\n");
        assert_eq!(e, "r.toml: line 2, column 1: duplicate key `width_m`");
        // A hundred million beams would size every scan buffer at 400 MB.
        let e = err("[laser]\nbeams = 100000000\n");
        assert!(
            e.contains("laser.beams") && e.contains("--max-beams"),
            "{e}"
        );
        let e = err("[depth]\nrows = 100000\ncols = 100000\n");
        assert!(e.contains("depth.rows × depth.cols"), "{e}");
    }
}
