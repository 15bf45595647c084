//! Paper 004 Fig. 15 test course.
use crate::scene::Scene;

#[derive(Clone, Debug, Default, PartialEq)]
pub struct CourseParams {}

pub fn generate_course(_seed: u64, _params: &CourseParams) -> Scene {
    todo!("course generator")
}
