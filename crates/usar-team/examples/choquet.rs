//! Paper 002's multi-criteria decision on its own: rank your candidate locations with the
//! Choquet integral (eq. 1) and the S-MCDM fuzzy measure of Table 1, no mission needed.
//!
//! ```sh
//! cargo run -p usar-team --example choquet
//! ```
//!
//! Each candidate has raw values of the five criteria of §3.2 — A: frontier length (cells),
//! d: distance (m), b: time to get there (s), S: relevance of its room's label, ND: doors of its
//! room — normalised over the candidates compared (more A, S, ND is better; more d, b is worse),
//! then aggregated with the measure.

use usar_team::mcdm::{FuzzyMeasure, Sense, normalize, s_mcdm_table_1};

fn main() {
    let measure = FuzzyMeasure::new(&s_mcdm_table_1()).expect("Table 1 is a valid measure");
    println!("criteria: {}", measure.criteria.join(", "));
    // Your candidates: a name and one raw value per criterion, in the measure's order.
    //                                     A     d      b     S    ND
    let candidates: [(&str, [f64; 5]); 3] = [
        ("doorway of a big room", [40.0, 12.0, 30.0, 1.0, 2.0]),
        ("corridor end", [25.0, 5.0, 14.0, 0.2, 1.0]),
        ("small office", [30.0, 20.0, 55.0, 0.6, 1.0]),
    ];
    assert_eq!(
        measure.criteria.len(),
        5,
        "this example gives five criteria values"
    );
    // The sense of each criterion: is more better (a longer frontier) or worse (a longer path)?
    let senses: Vec<Sense> = measure
        .criteria
        .iter()
        .map(|c| match c.as_str() {
            "d" | "b" => Sense::Cost,
            _ => Sense::Benefit,
        })
        .collect();
    let columns: Vec<Vec<Option<f64>>> = (0..5)
        .map(|j| {
            let raw: Vec<Option<f64>> = candidates.iter().map(|(_, v)| Some(v[j])).collect();
            normalize(&raw, senses[j])
        })
        .collect();
    let mut ranked: Vec<(f64, &str)> = candidates
        .iter()
        .enumerate()
        .map(|(k, (name, _))| {
            let u: Vec<f64> = columns.iter().map(|c| c[k].unwrap_or(0.0)).collect();
            (measure.choquet(&u), *name)
        })
        .collect();
    ranked.sort_by(|a, b| b.0.total_cmp(&a.0));
    for (utility, name) in &ranked {
        println!("{utility:.3}  {name}");
    }
    assert!(ranked.iter().all(|(u, _)| (0.0..=1.0).contains(u)));
}
