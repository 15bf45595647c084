//! Which reading means "no return within range". A laser that sees nothing reports its
//! maximum (SICK: 81.83 m, or 8.183–8.191 m in its 8 m mode; the CMU log: 8183 cm), some
//! drivers +∞ or NaN. ROBOTLASER1, RAWLASER and ROS's `LaserScan` state their maximum; FLASER,
//! DP-SLAM and Thrun's logs do not, and no value is assumed: the maximum is found in the
//! readings as a **saturation spike** — the largest readings piling up at the top of the
//! range. With `v` the largest reading, the readings in the top band `[0.99 v, v]` are no
//! return when there are at least [`MIN_SPIKE`] of them and more than in the whole band below
//! it, `[0.90 v, 0.99 v)` (nine times wider): real returns thin out towards the far end of a
//! laser's range, a saturated one piles up. Without a spike every reading is a return.
//!
//! Readings at or below 0 and NaN are no reading at all (neither a return nor free space).

use crate::{LogEvent, RobotLog};
use serde::Serialize;

/// Fewest readings in the top band that make a spike.
pub const MIN_SPIKE: usize = 10;

/// Where the no-return threshold comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Source {
    /// The log states the laser's maximum range.
    Stated,
    /// A saturation spike in the readings.
    Spike,
    /// Given by the user.
    Given,
    /// No spike: every finite positive reading is a return.
    None,
}

/// The no-return threshold of a log and what it makes of its readings.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct NoReturn {
    /// Readings at or above are no return.
    pub threshold_m: Option<f64>,
    pub source: Source,
    /// Share of the valid readings that are no return.
    pub share: f64,
    /// The longest reading that is a return.
    pub longest_return_m: f64,
}

/// The threshold of `log`: the stated maximum of its first scan that states one, else a
/// saturation spike.
pub fn estimate(log: &RobotLog) -> NoReturn {
    let readings = || {
        log.events
            .iter()
            .filter_map(|e| match e {
                LogEvent::Scan(s) => Some(s),
                LogEvent::Odometry { .. } => None,
            })
            .flat_map(|s| s.ranges_m.iter().map(|&r| f64::from(r)))
    };
    let stated = log.events.iter().find_map(|e| match e {
        LogEvent::Scan(s) => s.range_max_m,
        LogEvent::Odometry { .. } => None,
    });
    let (threshold_m, source) = match stated {
        Some(m) => (Some(m), Source::Stated),
        None => match spike(readings()) {
            Some(t) => (Some(t), Source::Spike),
            None => (None, Source::None),
        },
    };
    with_threshold(readings(), threshold_m, source)
}

/// The figures of `readings` under a threshold.
pub fn with_threshold(
    readings: impl Iterator<Item = f64>,
    threshold_m: Option<f64>,
    source: Source,
) -> NoReturn {
    let (mut valid, mut none, mut longest) = (0usize, 0usize, 0.0f64);
    for r in readings {
        match classify(r, threshold_m) {
            Reading::Return(r) => {
                valid += 1;
                longest = longest.max(r);
            }
            Reading::NoReturn => {
                valid += 1;
                none += 1;
            }
            Reading::Invalid => {}
        }
    }
    NoReturn {
        threshold_m,
        source,
        share: if valid == 0 {
            0.0
        } else {
            none as f64 / valid as f64
        },
        longest_return_m: longest,
    }
}

/// What one reading is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reading {
    Return(f64),
    NoReturn,
    Invalid,
}

/// Classifies reading `r` (metres) under a threshold.
#[inline]
pub fn classify(r: f64, threshold_m: Option<f64>) -> Reading {
    if r.is_nan() || r <= 0.0 {
        Reading::Invalid
    } else if r == f64::INFINITY || threshold_m.is_some_and(|t| r >= t) {
        Reading::NoReturn
    } else {
        Reading::Return(r)
    }
}

/// The lower edge of a saturation spike at the top of `readings`, if there is one.
fn spike(readings: impl Iterator<Item = f64> + Clone) -> Option<f64> {
    let top = readings
        .clone()
        .filter(|r| r.is_finite() && *r > 0.0)
        .fold(0.0f64, f64::max);
    if top <= 0.0 {
        return None;
    }
    let (band_low, below_low) = (0.99 * top, 0.90 * top);
    let (mut in_band, mut below, mut lowest) = (0usize, 0usize, top);
    for r in readings.filter(|r| r.is_finite()) {
        if r >= band_low {
            in_band += 1;
            lowest = lowest.min(r);
        } else if r >= below_low {
            below += 1;
        }
    }
    (in_band >= MIN_SPIKE && in_band > below).then_some(lowest)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pile_of_readings_at_the_top_is_no_return_and_a_thin_tail_is_not() {
        // 100 readings spread over 1–20 m, 50 at 81.83 m: a spike.
        let spread = (0..100).map(|k| 1.0 + 0.19 * f64::from(k));
        let saturated = spread.clone().chain(std::iter::repeat_n(81.83, 50));
        assert_eq!(spike(saturated), Some(81.83));
        // A clean log with a thin far tail: none.
        assert_eq!(spike(spread.clone()), None);
        // A few at the top are not enough.
        assert_eq!(spike(spread.chain(std::iter::repeat_n(30.0, 5))), None);
    }

    #[test]
    fn readings_are_returns_no_returns_or_nothing() {
        assert_eq!(classify(2.0, Some(8.0)), Reading::Return(2.0));
        assert_eq!(classify(8.0, Some(8.0)), Reading::NoReturn);
        assert_eq!(classify(f64::INFINITY, None), Reading::NoReturn);
        assert_eq!(classify(0.0, None), Reading::Invalid);
        assert_eq!(classify(f64::NAN, None), Reading::Invalid);
        let figures = with_threshold([1.0, 9.0, 0.0, 3.0].into_iter(), Some(8.0), Source::Given);
        assert_eq!(figures.share, 1.0 / 3.0);
        assert_eq!(figures.longest_return_m, 3.0);
    }
}
