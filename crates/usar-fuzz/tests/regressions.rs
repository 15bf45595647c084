//! Inputs the fuzz harness found, each a named test: the loader now refuses them with an
//! error and without a panic.

use usar_fuzz::{check, loaders::loader};

/// `name` refuses `input` with an error, within the memory and time bounds.
fn refused(name: &str, input: &[u8]) {
    let (accepted, problem) = check(loader(name).unwrap(), input);
    assert_eq!(problem, None, "{name}");
    assert_eq!(accepted, Some(false), "{name}: accepted");
}

#[test]
fn the_harness_reports_a_panic_as_a_finding() {
    // The harness itself: a loader that panics is caught and reported, not fatal.
    static PANICS: usar_fuzz::loaders::Loader = usar_fuzz::loaders::Loader {
        name: "panics",
        seeds: Vec::new,
        load: |_| panic!("boom"),
    };
    let (accepted, problem) = check(&PANICS, b"x");
    assert_eq!(accepted, None);
    assert_eq!(problem, Some(usar_fuzz::Problem::Panic("boom".into())));
}

#[test]
fn the_harness_reports_runaway_memory_as_a_finding() {
    static HOGS: usar_fuzz::loaders::Loader = usar_fuzz::loaders::Loader {
        name: "hogs",
        seeds: Vec::new,
        load: |_| {
            let v = vec![1u8; 600_000_000];
            std::hint::black_box(&v);
            Ok(())
        },
    };
    let (_, problem) = check(&HOGS, b"x");
    assert!(
        matches!(problem, Some(usar_fuzz::Problem::Memory { .. })),
        "{problem:?}"
    );
}

#[test]
fn issue_19_inputs_are_refused() {
    refused("image", b"P5\n20000 20000\n255\n\x00");
    refused(
        "ros-yaml",
        format!("image: {}\n", "[".repeat(100_000)).as_bytes(),
    );
    refused(
        "ros-yaml",
        b"image: m.pgm\nresolution: 1e300\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
    );
    refused("robot-toml", b"[laser]\nbeams = 100000000\n");
    refused("mission-toml", b"[rescuer]\ntrain_trials = 4000000000\n");
    refused(
        "campaign-toml",
        b"name = \"../../../x\"\nrunner = \"noop\"\n",
    );
}
