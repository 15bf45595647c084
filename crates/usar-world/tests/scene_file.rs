//! The scene file: a generated scene reads back equal; every field a hand-edited file gets
//! wrong is refused with an error naming it, before anything large is allocated.

use std::path::Path;
use usar_world::generate::{RubbleParams, generate_rubble};
use usar_world::scene::{read_scene, scene_from_json, scene_to_json};
use usar_world::{Point2, Scene, Victim};

fn small_scene() -> Scene {
    generate_rubble(3, &RubbleParams::default())
}

/// The JSON of `scene` as a value, to be broken by hand.
fn json_of(scene: &Scene) -> serde_json::Value {
    serde_json::from_str(&scene_to_json(scene)).unwrap()
}

fn error_of(value: &serde_json::Value) -> String {
    scene_from_json(&value.to_string(), Path::new("hand.json"))
        .unwrap_err()
        .to_string()
}

#[test]
fn a_generated_scene_reads_back_equal_and_writes_the_same_bytes() {
    let scene = small_scene();
    let text = scene_to_json(&scene);
    let back = scene_from_json(&text, Path::new("office.json")).unwrap();
    assert_eq!(back, scene);
    assert_eq!(scene_to_json(&back), text);
}

#[test]
fn a_misspelt_field_is_refused_not_ignored() {
    // `"victim"` for `"victims"` used to give a scene without victims and exit 0.
    let mut v = json_of(&small_scene());
    let victims = v["victims"].take();
    let obj = v.as_object_mut().unwrap();
    obj.remove("victims");
    obj.insert("victim".into(), victims);
    let err = error_of(&v);
    assert!(
        err.contains("hand.json") && err.contains("unknown field `victim`"),
        "{err}"
    );

    let mut v = json_of(&small_scene());
    let poses = v["start_poses"].take();
    let obj = v.as_object_mut().unwrap();
    obj.remove("start_poses");
    obj.insert("start_pose".into(), poses);
    assert!(error_of(&v).contains("unknown field `start_pose`"));

    // Nested records too: a victim's misspelt `heat`.
    let mut v = json_of(&small_scene());
    v["victims"][0]["heat"] = 36.0.into();
    assert!(error_of(&v).contains("unknown field `heat`"));
}

#[test]
fn two_victims_with_one_id_are_refused() {
    let mut scene = small_scene();
    let first: Victim = scene.victims[0].clone();
    scene.victims.push(Victim {
        position: Point2::new(first.position.x, first.position.y),
        ..first
    });
    let err = scene_from_json(&scene_to_json(&scene), Path::new("dup.json"))
        .unwrap_err()
        .to_string();
    let last = scene.victims.len() - 1;
    assert!(
        err.contains(&format!("victims[{last}].id")) && err.contains("unique"),
        "{err}"
    );
}

#[test]
fn a_grid_declared_past_the_cell_limit_is_refused_before_its_layers_are_inflated() {
    // 16 384² cells with tiny layers: the old reader allocated the layers (3.4 GB) first.
    let mut v = json_of(&small_scene());
    v["grid"]["width"] = 16_384.into();
    v["grid"]["height"] = 16_384.into();
    let err = error_of(&v);
    assert!(
        err.contains("field `grid`") && err.contains("--max-cells"),
        "{err}"
    );
}

#[test]
fn absurd_resolutions_and_origins_name_the_grid_field() {
    for (field, value, expect) in [
        ("resolution_m", 1e300, "grid.resolution_m"),
        ("resolution_m", 1e-300, "grid.resolution_m"),
        ("resolution_m", -0.1, "grid.resolution_m"),
    ] {
        let mut v = json_of(&small_scene());
        v["grid"][field] = value.into();
        let err = error_of(&v);
        assert!(err.contains(expect), "{value}: {err}");
    }
    let mut v = json_of(&small_scene());
    v["grid"]["origin"]["x"] = 1e308.into();
    assert!(error_of(&v).contains("grid.origin"));
}

#[test]
fn a_missing_or_endless_file_is_an_error_naming_it() {
    let err = read_scene(Path::new("no/such/scene.json"))
        .unwrap_err()
        .to_string();
    assert!(err.starts_with("no/such/scene.json"), "{err}");
    #[cfg(unix)]
    {
        let err = read_scene(Path::new("/dev/zero")).unwrap_err().to_string();
        assert!(
            err.contains("/dev/zero") && err.contains("file size"),
            "{err}"
        );
    }
}

#[test]
fn a_scene_output_must_be_json() {
    use usar_world::io::check_scene_output;
    assert!(check_scene_output(Path::new("a/b.JSON")).is_ok());
    let err = check_scene_output(Path::new("out.yaml")).unwrap_err();
    assert_eq!(
        err.to_string(),
        "out.yaml: a scene file must end in .json, found .yaml; the extension chooses the format \
         when the file is read back"
    );
    let err = check_scene_output(Path::new("out")).unwrap_err();
    assert_eq!(err.found, "no extension");
}

#[test]
fn summary_names_the_file_and_counts() {
    let scene = small_scene();
    let summary = scene.summary(Path::new("s.json"));
    assert_eq!(summary.file, "s.json");
    assert_eq!(summary.width, scene.geometry().width);
    assert_eq!(summary.victims, scene.victims.len());
    let json = serde_json::to_value(&summary).unwrap();
    let keys: Vec<&String> = json.as_object().unwrap().keys().collect();
    let mut sorted = keys.clone();
    sorted.sort();
    assert_eq!(
        keys, sorted,
        "alphabetical, as the CLI has always printed them"
    );
}

#[test]
fn exports_write_every_format_given() {
    use usar_world::io::Exports;
    let tmp = tempfile::tempdir().unwrap();
    let scene = small_scene();
    let (yaml, png, json) = (
        tmp.path().join("m.yaml"),
        tmp.path().join("m.png"),
        tmp.path().join("m.json"),
    );
    assert!(Exports::default().is_empty());
    let wrong = Exports {
        scene_file: Some(&png),
        ..Exports::default()
    };
    assert!(wrong.check().is_err());
    let exports = Exports {
        ros: Some(&yaml),
        png: Some(&png),
        scene_file: Some(&json),
    };
    exports.check().unwrap();
    assert_eq!(
        exports.write(&scene).unwrap(),
        [yaml.clone(), png.clone(), json.clone()]
    );
    assert_eq!(read_scene(&json).unwrap(), scene);
    assert!(yaml.exists() && png.exists());
}
