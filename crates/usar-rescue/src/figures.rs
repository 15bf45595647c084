//! Paper 000's figures from the experiments' results, as PNG or SVG (by the extension): Fig. 7
//! from training, Fig. 9 from an evaluation, Fig. 16–18 and Table III from the teleoperation
//! study. A function that draws several figures writes the first at `path` and the others beside
//! it ([`sibling`]).

use crate::analysis::EvalAnalysis;
use crate::teleoperation::{ParticipantResult, TrialResult};
use crate::training::{TrainReport, TrialPoint};
use std::path::{Path, PathBuf};
use usar_plot::{Bar, BarChart, GroupedBarChart, LineChart, PlotError, Series};

/// `dir/name.ext` → `dir/name{suffix}.ext`.
pub fn sibling(path: &Path, suffix: &str) -> PathBuf {
    let stem = path
        .file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let ext = path
        .extension()
        .map_or_else(String::new, |e| format!(".{}", e.to_string_lossy()));
    path.with_file_name(format!("{stem}{suffix}{ext}"))
}

/// Fig. 7a (cumulative reward per trial, MAXQ and flat Q) at `path` and Fig. 7b (steps per
/// trial, first 200 trials) at its `-steps` sibling.
pub fn plot_training(report: &TrainReport, path: &Path) -> Result<(), PlotError> {
    let cumulative = |pick: &dyn Fn(&TrialPoint) -> Option<f64>| {
        let mut sum = 0.0;
        report
            .curve
            .iter()
            .filter_map(|p| {
                sum += pick(p)?;
                Some((f64::from(p.trial + 1), sum))
            })
            .collect::<Vec<_>>()
    };
    let mut series = vec![Series::line("MAXQ", cumulative(&|p| Some(p.maxq_reward)))];
    let flat = cumulative(&|p| p.flat_reward);
    if !flat.is_empty() {
        series.push(Series::line("flat Q", flat));
    }
    LineChart {
        title: "Cumulative reward per trial (paper 000 Fig. 7a)".into(),
        x_label: "trial".into(),
        y_label: "cumulative reward".into(),
        series,
        y_range: None,
    }
    .save(path)?;
    let steps: Vec<(f64, f64)> = report
        .curve
        .iter()
        .take(200)
        .map(|p| (f64::from(p.trial + 1), p.maxq_steps as f64))
        .collect();
    LineChart {
        title: "Exploration steps, first 200 trials (paper 000 Fig. 7b)".into(),
        x_label: "trial".into(),
        y_label: "steps".into(),
        series: vec![Series::line("MAXQ", steps)],
        y_range: None,
    }
    .save(&sibling(path, "-steps"))
}

/// Fig. 9: exploration steps (mean, sd as error bar) by scene and weight case.
pub fn plot_evaluation(analysis: &EvalAnalysis, path: &Path) -> Result<(), PlotError> {
    let mut bars = Vec::new();
    for (name, s) in &analysis.scenes {
        for (w, m) in &s.steps_by_weights {
            bars.push(Bar {
                label: format!("{name} {w}"),
                value: m.mean,
                error: m.sd.unwrap_or(0.0),
            });
        }
    }
    BarChart {
        title: "Exploration steps by scene and weight case (paper 000 Fig. 9)".into(),
        y_label: "steps".into(),
        bars,
    }
    .save(path)
}

/// Fig. 16 (% explored) at `path`, Fig. 17 (victims), Fig. 18 (collisions) and Table III
/// (trial time) at its `-victims`, `-collisions` and `-time` siblings: per participant,
/// teleoperated beside semi-autonomous.
pub fn plot_study(results: &[ParticipantResult], path: &Path) -> Result<(), PlotError> {
    type Pick = fn(&TrialResult) -> f64;
    let figures: [(&str, &str, &str, Pick); 4] = [
        (
            "",
            "Scene explored (paper 000 Fig. 16)",
            "explored (%)",
            |t| t.explored_percent,
        ),
        ("-victims", "Victims identified (Fig. 17)", "victims", |t| {
            f64::from(t.victims_found)
        }),
        ("-collisions", "Collisions (Fig. 18)", "collisions", |t| {
            f64::from(t.collisions)
        }),
        ("-time", "Trial time (Table III)", "time (s)", |t| t.time_s),
    ];
    for (suffix, title, y_label, pick) in figures {
        GroupedBarChart {
            title: title.into(),
            x_label: "participant".into(),
            y_label: y_label.into(),
            groups: (1..=results.len()).map(|k| k.to_string()).collect(),
            series: vec![
                (
                    "teleoperated".into(),
                    results.iter().map(|p| pick(&p.teleoperated)).collect(),
                ),
                (
                    "semi-autonomous".into(),
                    results.iter().map(|p| pick(&p.semi_autonomous)).collect(),
                ),
            ],
        }
        .save(&sibling(path, suffix))?;
    }
    Ok(())
}

/// Dietterich's Taxi: the greedy policies' mean return over the evaluation starts as training
/// goes on, MAXQ-Q beside flat Q, against the optimum (the y axis from 20 below it to 2 above).
pub fn plot_taxi(report: &usar_maxq::taxi::TaxiReport, path: &Path) -> Result<(), PlotError> {
    let curve = |pick: fn(&(u64, f64, f64)) -> f64| {
        report.curve.iter().map(|p| (p.0 as f64, pick(p))).collect()
    };
    LineChart {
        title: format!("Taxi: greedy return (optimal {:.2})", report.optimal_return),
        x_label: "episodes".into(),
        y_label: format!("mean return over {} starts", report.config.eval_starts),
        series: vec![
            Series::line("MAXQ-Q", curve(|p| p.1)),
            Series::line("flat Q", curve(|p| p.2)),
        ],
        y_range: Some((report.optimal_return - 20.0, report.optimal_return + 2.0)),
    }
    .save(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn siblings_keep_the_extension() {
        assert_eq!(
            sibling(Path::new("out/fig.png"), "-steps"),
            Path::new("out/fig-steps.png")
        );
        assert_eq!(sibling(Path::new("fig"), "-time"), Path::new("fig-time"));
    }
}
