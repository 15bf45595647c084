//! The base station's victim board: the warm regions with a human signature the team's robots
//! report, one entry per place. Each new one is a question for the operator — is it a person?
//! — and the board keeps the answers (paper 002's robots detect; the operator confirms).

use usar_rescue::controller::Question;
use usar_rescue::perception::victim_probability;
use usar_team::VictimReport;
use usar_world::Point2;

/// Reports this close to an earlier one are the same warm region, metres: about a person's
/// length, so that one person seen from two sides is asked about once.
pub const SAME_PLACE_M: f64 = 1.5;

/// A place on the board.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Entry {
    pub at: Point2,
    /// The first report of it.
    pub report: VictimReport,
    /// The operator's verdict and when (`None`: not answered yet).
    pub confirmed: Option<(bool, f64)>,
}

/// See the [module documentation](self).
#[derive(Clone, Debug, Default)]
pub struct VictimBoard {
    pub entries: Vec<Entry>,
}

impl VictimBoard {
    /// Adds the reports' new places; the questions to ask about them, each with the team robot
    /// (its number in the team) that reported it.
    pub fn post(&mut self, reports: &[VictimReport]) -> Vec<(usize, Question)> {
        let mut questions = Vec::new();
        for r in reports {
            if self
                .entries
                .iter()
                .any(|e| e.at.distance(r.at) < SAME_PLACE_M)
            {
                continue;
            }
            self.entries.push(Entry {
                at: r.at,
                report: *r,
                confirmed: None,
            });
            questions.push((
                r.robot,
                Question::Victim {
                    source: r.reading,
                    probability: victim_probability(true, r.size_m2),
                    size_m2: r.size_m2,
                    at: r.at,
                },
            ));
        }
        questions
    }

    /// The operator's answer about the place first reported with `reading`.
    pub fn answer(&mut self, reading: usar_sim::sensors::DetectionId, tag: bool, time_s: f64) {
        if let Some(e) = self
            .entries
            .iter_mut()
            .find(|e| e.report.reading == reading)
        {
            e.confirmed = Some((tag, time_s));
        }
    }
}
