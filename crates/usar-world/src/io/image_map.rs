//! Occupancy images (PGM and PNG) read as ground-truth scenes, with the pixel rules of ROS
//! `map_server` (ROS 1 `image_loader.cpp`, Nav2 `map_io.cpp`).
//!
//! A pixel's *shade* is the mean of its colour channels scaled to [0, 1] (0 black, 1 white); its
//! occupancy is p = 1 − shade (`negate` false) or p = shade (`negate` true), i.e.
//! p = (255 − v)/255 for an 8-bit grey value v. p above `occupied_thresh` is occupied, p below
//! `free_thresh` is free, anything else is unknown (see [`ThresholdMode`] and
//! [`ThresholdConvention`] for the details). A pixel whose alpha is not fully opaque is unknown.
//!
//! In the scene, occupied and unknown pixels both become [`obstacle::WALL`]: unmapped space is not
//! part of the world a robot can enter, so it is closed off exactly like a wall. Free pixels become
//! [`obstacle::NONE`] on flat floor (height 0). Image row 0 is the top of the picture and becomes
//! the scene's northernmost row (`height − 1`); the origin is the lower-left corner of the
//! lower-left pixel, as in ROS.
//!
//! The scene gets one start pose, chosen deterministically: the free cell farthest from any
//! obstacle (or the grid border) in the largest 4-connected free region, heading 0. See
//! [`deepest_free_cell`].

use crate::error::{Result, WorldError};
use crate::geometry::{Point2, Pose2};
use crate::grid::{Cell, Grid, GridGeometry, NEIGHBORS8};
use crate::scene::{Provenance, Scene, obstacle};
use std::path::Path;

/// How an occupancy between the two thresholds is read (the ROS `mode` field).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ThresholdMode {
    /// Three classes: occupied, free, and unknown between the thresholds (ROS default).
    #[default]
    Trinary,
    /// Between the thresholds ROS keeps a graded occupancy
    /// r = (p − free_thresh)/(occupied_thresh − free_thresh). The scene is binary: the cell is an
    /// obstacle when r ≥ 0.5 (ROS value ≥ 50 of 100), free otherwise.
    Scale,
    /// The grey value itself is the ROS occupancy value: v ∈ 0..=100 is an occupancy of v %, any
    /// larger value (map_saver writes 255 for −1) is unknown. The percentage is then thresholded
    /// like [`ThresholdMode::Scale`]. With [`ThresholdConvention::Ros1`] `negate` flips v first
    /// (as ROS 1 does); Nav2 ignores `negate` in raw mode.
    Raw,
}

impl ThresholdMode {
    /// The spelling of the ROS `mode` field.
    pub fn as_str(self) -> &'static str {
        match self {
            ThresholdMode::Trinary => "trinary",
            ThresholdMode::Scale => "scale",
            ThresholdMode::Raw => "raw",
        }
    }

    /// Parses the ROS `mode` field (`trinary`, `scale` or `raw`).
    pub fn from_name(name: &str) -> Option<Self> {
        [
            ThresholdMode::Trinary,
            ThresholdMode::Scale,
            ThresholdMode::Raw,
        ]
        .into_iter()
        .find(|m| m.as_str() == name)
    }
}

/// Whether an occupancy exactly equal to a threshold already counts as occupied / free.
///
/// The default is [`ThresholdConvention::Ros1`] (strict): it is what the loader *code* of both
/// ROS 1 `map_server` (`image_loader.cpp`: `occ > occ_th`, `occ < free_th`) and Nav2
/// (`map_io.cpp`: `occupied_thresh < occ`, `occ < free_thresh`) does, and what the ROS wiki states
/// ("greater than this threshold", "less than this threshold"). The inclusive form is what the
/// ROS 1 header comment documents and what Nav2's map *saver* uses. For 8-bit images the two only
/// differ when (255 − v)/255 equals a threshold exactly, which happens for none of the usual
/// thresholds (0.65, 0.196, 0.25, 0.1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ThresholdConvention {
    /// Occupied if p > occupied_thresh, free if p < free_thresh.
    #[default]
    Ros1,
    /// Occupied if p ≥ occupied_thresh, free if p ≤ free_thresh.
    Nav2,
}

/// How to read an occupancy image that comes without (or with) a ROS YAML file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageMapOptions {
    /// Side of one pixel, metres (ROS `resolution`). Default 0.1 m, the project's cell size.
    pub resolution_m: f64,
    /// World position of the lower-left corner of the lower-left pixel (ROS `origin` x, y).
    pub origin: Point2,
    /// Rotation of the image about `origin`, counter-clockwise, radians (ROS `origin` yaw).
    /// A rotated image is turned on import into an axis-aligned grid (see
    /// [`super::rotation::rotate_obstacles`]).
    pub yaw_rad: f64,
    /// True: dark pixels are free and light ones occupied (ROS `negate: 1`).
    pub negate: bool,
    /// Occupancy above which a pixel is occupied (ROS default 0.65).
    pub occupied_thresh: f64,
    /// Occupancy below which a pixel is free (ROS default 0.196).
    pub free_thresh: f64,
    pub mode: ThresholdMode,
    pub convention: ThresholdConvention,
}

impl Default for ImageMapOptions {
    /// The ROS `map_server` defaults (`negate 0`, `occupied_thresh 0.65`, `free_thresh 0.196`,
    /// trinary) at the origin, with 0.1 m pixels.
    fn default() -> Self {
        Self {
            resolution_m: 0.1,
            origin: Point2::new(0.0, 0.0),
            yaw_rad: 0.0,
            negate: false,
            occupied_thresh: 0.65,
            free_thresh: 0.196,
            mode: ThresholdMode::Trinary,
            convention: ThresholdConvention::Ros1,
        }
    }
}

impl ImageMapOptions {
    /// Checks the options; errors name `path` and the ROS field (`resolution`, `origin`,
    /// `occupied_thresh`, `free_thresh`).
    pub fn validate(&self, path: &Path) -> Result<()> {
        crate::scene::check_resolution(self.resolution_m, "resolution", path)?;
        crate::scene::check_extent(self.origin, (0.0, 0.0), "origin", path)?;
        if !(self.yaw_rad.is_finite() && self.yaw_rad.abs() <= 100.0) {
            return Err(WorldError::invalid(
                path,
                "origin[2]",
                self.yaw_rad,
                "a yaw in radians (|yaw| ≤ 100)",
            ));
        }
        for (field, v) in [
            ("occupied_thresh", self.occupied_thresh),
            ("free_thresh", self.free_thresh),
        ] {
            if !(0.0..=1.0).contains(&v) {
                return Err(WorldError::invalid(
                    path,
                    field,
                    v,
                    "an occupancy in [0, 1]",
                ));
            }
        }
        if self.free_thresh >= self.occupied_thresh {
            return Err(WorldError::invalid(
                path,
                "free_thresh",
                self.free_thresh,
                format!("less than occupied_thresh ({})", self.occupied_thresh),
            ));
        }
        Ok(())
    }
}

/// What one pixel says about its cell after thresholding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixelClass {
    Free,
    Occupied,
    Unknown,
}

/// Classifies an occupancy p ∈ [0, 1] (already negated if needed) for trinary and scale modes.
fn classify_occupancy(p: f64, graded: bool, opts: &ImageMapOptions) -> PixelClass {
    let (occupied, free) = match opts.convention {
        ThresholdConvention::Ros1 => (p > opts.occupied_thresh, p < opts.free_thresh),
        ThresholdConvention::Nav2 => (p >= opts.occupied_thresh, p <= opts.free_thresh),
    };
    if occupied {
        PixelClass::Occupied
    } else if free {
        PixelClass::Free
    } else if !graded {
        PixelClass::Unknown
    } else {
        // Scale mode: r = (p − free)/(occupied − free) ∈ [0, 1]; obstacle from r ≥ 0.5 on.
        let r = (p - opts.free_thresh) / (opts.occupied_thresh - opts.free_thresh);
        if r >= 0.5 {
            PixelClass::Occupied
        } else {
            PixelClass::Free
        }
    }
}

/// Classifies one pixel from the sum of its colour channels.
///
/// `colour_sum` is the sum of `channels` samples of at most `maxval` each; `opaque` is false when
/// the pixel's alpha is below `maxval`.
pub fn classify_pixel(
    colour_sum: u32,
    channels: u32,
    maxval: u32,
    opaque: bool,
    opts: &ImageMapOptions,
) -> PixelClass {
    if !opaque {
        return PixelClass::Unknown;
    }
    let full = f64::from(channels) * f64::from(maxval);
    let sum = f64::from(colour_sum);
    match opts.mode {
        ThresholdMode::Trinary | ThresholdMode::Scale => {
            // p = (255 − v)/255 for one 8-bit channel; one division keeps threshold ties exact.
            let p = if opts.negate {
                sum / full
            } else {
                (full - sum) / full
            };
            classify_occupancy(p, opts.mode == ThresholdMode::Scale, opts)
        }
        ThresholdMode::Raw => {
            let shade = sum / full;
            let shade = if opts.negate && opts.convention == ThresholdConvention::Ros1 {
                1.0 - shade
            } else {
                shade
            };
            let value = (shade * 255.0).round();
            if value > 100.0 {
                PixelClass::Unknown
            } else {
                classify_occupancy(value / 100.0, true, opts)
            }
        }
    }
}

/// A decoded image: samples row-major from the top row, channels interleaved.
#[derive(Clone, Debug, PartialEq)]
pub struct DecodedImage {
    pub width: u32,
    pub height: u32,
    /// Largest sample value: 255 for 8-bit data, 65 535 for 16-bit, the PGM `maxval` otherwise.
    pub maxval: u32,
    /// Colour channels per pixel, not counting alpha: 1 (grey) or 3 (RGB).
    pub colour_channels: u32,
    /// True when each pixel carries a final alpha sample.
    pub has_alpha: bool,
    pub samples: Vec<u16>,
}

impl DecodedImage {
    fn samples_per_pixel(&self) -> usize {
        self.colour_channels as usize + usize::from(self.has_alpha)
    }
}

/// The 8-byte PNG signature.
const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

/// Decodes a PGM (P2, P5), PPM (P3, P6) or PNG image from memory; `path` names it in errors.
///
/// The format is recognised by its first bytes, not by the file name. Netpbm files may carry `#`
/// comments anywhere in the header and any `maxval` from 1 to 65 535 (two bytes per sample above
/// 255, as the Netpbm specification says). Bytes after the first image are ignored.
pub fn decode_image(bytes: &[u8], path: &Path) -> Result<DecodedImage> {
    if bytes.is_empty() {
        return Err(WorldError::syntax(
            path,
            "byte 0",
            "file is empty, expected a PGM (P5 or P2) or PNG image",
        ));
    }
    if bytes.starts_with(&PNG_SIGNATURE) {
        return decode_png(bytes, path);
    }
    match bytes {
        [b'P', kind @ (b'2' | b'3' | b'5' | b'6'), ..] => decode_netpbm(bytes, *kind, path),
        [b'P', kind @ (b'1' | b'4' | b'7'), ..] => Err(WorldError::syntax(
            path,
            "byte 0",
            format!(
                "Netpbm type P{} is not supported, expected a greyscale PGM (P5 or P2), a PPM \
                 (P6 or P3) or a PNG image",
                char::from(*kind)
            ),
        )),
        _ => {
            let head = &bytes[..bytes.len().min(8)];
            Err(WorldError::syntax(
                path,
                "byte 0",
                format!(
                    "unknown image format: the file starts with \"{}\", expected the PGM magic \
                     number P5 or P2 or the PNG signature",
                    head.escape_ascii()
                ),
            ))
        }
    }
}

fn decode_png(bytes: &[u8], path: &Path) -> Result<DecodedImage> {
    use image::DynamicImage as D;
    use image::ImageDecoder as _;
    let image_error = |e: image::ImageError| WorldError::Image {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    // The header's size is checked before a pixel is decoded: a 76 KB 1-bit PNG can declare
    // 20 000 × 20 000 pixels.
    let decoder =
        image::codecs::png::PngDecoder::new(std::io::Cursor::new(bytes)).map_err(image_error)?;
    let (width, height) = decoder.dimensions();
    crate::limits::check_cells(path, "image size", width.into(), height.into())?;
    let image = D::from_decoder(decoder).map_err(image_error)?;
    let (width, height) = (image.width(), image.height());
    let widen = |v: Vec<u8>| v.into_iter().map(u16::from).collect::<Vec<u16>>();
    let (maxval, colour_channels, has_alpha, samples) = match image {
        D::ImageLuma8(b) => (255, 1, false, widen(b.into_raw())),
        D::ImageLumaA8(b) => (255, 1, true, widen(b.into_raw())),
        D::ImageRgb8(b) => (255, 3, false, widen(b.into_raw())),
        D::ImageRgba8(b) => (255, 3, true, widen(b.into_raw())),
        D::ImageLuma16(b) => (65535, 1, false, b.into_raw()),
        D::ImageLumaA16(b) => (65535, 1, true, b.into_raw()),
        D::ImageRgb16(b) => (65535, 3, false, b.into_raw()),
        D::ImageRgba16(b) => (65535, 3, true, b.into_raw()),
        other => (65535, 3, true, other.to_rgba16().into_raw()),
    };
    if width == 0 || height == 0 {
        return Err(zero_size(path, width, height));
    }
    Ok(DecodedImage {
        width,
        height,
        maxval,
        colour_channels,
        has_alpha,
        samples,
    })
}

fn zero_size(path: &Path, width: u32, height: u32) -> WorldError {
    WorldError::syntax(
        path,
        "header",
        format!("zero-size image: {width}×{height} pixels, expected at least 1×1"),
    )
}

/// Writes `n` with a space between groups of three digits ("307 184").
pub(crate) fn group_thousands(n: u64) -> String {
    let digits = n.to_string();
    let head = match digits.len() % 3 {
        0 => 3.min(digits.len()),
        r => r,
    };
    let mut out = digits[..head].to_string();
    for group in digits.as_bytes()[head..].chunks(3) {
        out.push(' ');
        out.extend(group.iter().map(|&b| char::from(b)));
    }
    out
}

/// A cursor over a Netpbm file.
struct NetpbmCursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    path: &'a Path,
}

impl NetpbmCursor<'_> {
    /// Skips whitespace and `#` comments (which run to the end of the line).
    fn skip_blanks(&mut self) {
        while let Some(&b) = self.bytes.get(self.pos) {
            if b.is_ascii_whitespace() {
                self.pos += 1;
            } else if b == b'#' {
                while self
                    .bytes
                    .get(self.pos)
                    .is_some_and(|&c| c != b'\n' && c != b'\r')
                {
                    self.pos += 1;
                }
            } else {
                break;
            }
        }
    }

    fn describe_here(&self) -> String {
        match self.bytes.get(self.pos) {
            None => "the end of the file".to_string(),
            Some(b) => format!("'{}'", [*b].escape_ascii()),
        }
    }

    /// Reads a decimal number after blanks; `what` names it in errors.
    fn read_number(&mut self, what: &str) -> Result<u32> {
        self.skip_blanks();
        let start = self.pos;
        let mut value: u64 = 0;
        while let Some(&b) = self.bytes.get(self.pos).filter(|b| b.is_ascii_digit()) {
            value = value.saturating_mul(10).saturating_add(u64::from(b - b'0'));
            self.pos += 1;
        }
        if start == self.pos {
            return Err(WorldError::syntax(
                self.path,
                format!("byte {start}"),
                format!(
                    "expected the {what} (a decimal number), found {}",
                    self.describe_here()
                ),
            ));
        }
        if let Some(b) = self
            .bytes
            .get(self.pos)
            .filter(|b| !b.is_ascii_whitespace() && **b != b'#')
        {
            return Err(WorldError::syntax(
                self.path,
                format!("byte {}", self.pos),
                format!("unexpected '{}' after the {what}", [*b].escape_ascii()),
            ));
        }
        u32::try_from(value).map_err(|_| {
            WorldError::syntax(
                self.path,
                format!("byte {start}"),
                format!(
                    "the {what} {} is too large",
                    String::from_utf8_lossy(&self.bytes[start..self.pos])
                ),
            )
        })
    }
}

fn decode_netpbm(bytes: &[u8], kind: u8, path: &Path) -> Result<DecodedImage> {
    let mut cur = NetpbmCursor {
        bytes,
        pos: 2,
        path,
    };
    if let Some(b) = bytes
        .get(2)
        .filter(|b| !b.is_ascii_whitespace() && **b != b'#')
    {
        return Err(WorldError::syntax(
            path,
            "byte 2",
            format!(
                "unexpected '{}' after the magic number P{}, expected whitespace",
                [*b].escape_ascii(),
                char::from(kind)
            ),
        ));
    }
    let width = cur.read_number("image width")?;
    let height = cur.read_number("image height")?;
    let maxval_at = cur.pos;
    let maxval = cur.read_number("maxval")?;
    if width == 0 || height == 0 {
        return Err(zero_size(path, width, height));
    }
    crate::limits::check_cells(path, "image size", width.into(), height.into())?;
    if maxval == 0 || maxval > 65535 {
        return Err(WorldError::syntax(
            path,
            format!("byte {maxval_at}"),
            format!("maxval {maxval} is out of range, expected 1 to 65535"),
        ));
    }
    let colour_channels: u32 = if matches!(kind, b'3' | b'6') { 3 } else { 1 };
    let pixels = u64::from(width) * u64::from(height);
    let samples_wanted = pixels * u64::from(colour_channels);
    let samples = if matches!(kind, b'5' | b'6') {
        // Exactly one whitespace byte separates maxval from the binary raster.
        let raster_start = cur.pos + 1;
        let raster = bytes.get(raster_start..).unwrap_or(&[]);
        let bytes_per_sample: u64 = if maxval > 255 { 2 } else { 1 };
        let wanted = samples_wanted * bytes_per_sample;
        if (raster.len() as u64) < wanted {
            let unit = if colour_channels == 1 && bytes_per_sample == 1 {
                String::new()
            } else {
                format!(" × {} bytes", u64::from(colour_channels) * bytes_per_sample)
            };
            return Err(WorldError::syntax(
                path,
                format!("byte {}", raster_start.min(bytes.len())),
                format!(
                    "truncated: header says {width}×{height} = {} pixels{unit}, file has {} bytes \
                     of pixel data",
                    group_thousands(pixels),
                    group_thousands(raster.len() as u64)
                ),
            ));
        }
        let raster = &raster[..wanted as usize];
        if bytes_per_sample == 1 {
            raster.iter().map(|&b| u16::from(b)).collect::<Vec<u16>>()
        } else {
            raster
                .chunks_exact(2)
                .map(|c| u16::from_be_bytes([c[0], c[1]]))
                .collect()
        }
    } else {
        read_ascii_samples(
            &mut cur,
            samples_wanted,
            (width, height, colour_channels, maxval),
        )?
    };
    if let Some(i) = samples.iter().position(|&s| u32::from(s) > maxval) {
        let pixel = i as u64 / u64::from(colour_channels);
        return Err(WorldError::syntax(
            path,
            format!(
                "pixel {} of row {}",
                pixel % u64::from(width),
                pixel / u64::from(width)
            ),
            format!(
                "sample value {} exceeds the header's maxval {maxval}",
                samples[i]
            ),
        ));
    }
    Ok(DecodedImage {
        width,
        height,
        maxval,
        colour_channels,
        has_alpha: false,
        samples,
    })
}

/// Reads the ASCII raster of a P2/P3 file (comments are tolerated between samples).
fn read_ascii_samples(
    cur: &mut NetpbmCursor<'_>,
    samples_wanted: u64,
    (width, height, channels, maxval): (u32, u32, u32, u32),
) -> Result<Vec<u16>> {
    // Every ASCII sample takes at least two bytes, so the file length bounds the allocation.
    let capacity = samples_wanted.min(cur.bytes.len() as u64 / 2 + 1) as usize;
    let mut samples = Vec::with_capacity(capacity);
    while (samples.len() as u64) < samples_wanted {
        cur.skip_blanks();
        if cur.pos >= cur.bytes.len() {
            return Err(WorldError::syntax(
                cur.path,
                format!("byte {}", cur.pos),
                format!(
                    "truncated: header says {width}×{height} = {} samples, file has {}",
                    group_thousands(samples_wanted),
                    group_thousands(samples.len() as u64)
                ),
            ));
        }
        let at = cur.pos;
        let v = cur.read_number("sample value")?;
        if v > maxval {
            let pixel = samples.len() as u64 / u64::from(channels);
            return Err(WorldError::syntax(
                cur.path,
                format!("byte {at}"),
                format!(
                    "sample value {v} of pixel {} of row {} exceeds the header's maxval {maxval}",
                    pixel % u64::from(width),
                    pixel / u64::from(width)
                ),
            ));
        }
        samples.push(v as u16);
    }
    Ok(samples)
}

/// Reads an occupancy image (PGM P5/P2, PPM P6/P3, PNG) as a ground-truth scene.
///
/// Occupied and unknown pixels become walls, free ones open flat floor (see the module docs);
/// the scene is named after the file stem, its provenance is `import` with the file name, and it
/// has one start pose from [`deepest_free_cell`]. Errors name `path`: unreadable or empty file,
/// bad magic number, truncated pixel data, zero-size image, invalid options (the ROS field
/// names), or an image without a single free pixel.
pub fn read_image_map(path: &Path, opts: &ImageMapOptions) -> Result<Scene> {
    opts.validate(path)?;
    let bytes = crate::limits::read_file(path)?;
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let detail = path
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    scene_from_image_bytes(&bytes, path, opts, name, detail)
}

/// Decodes `bytes` (read from `image_path`) and builds the scene; options must be valid.
pub(crate) fn scene_from_image_bytes(
    bytes: &[u8],
    image_path: &Path,
    opts: &ImageMapOptions,
    name: String,
    detail: String,
) -> Result<Scene> {
    let image = decode_image(bytes, image_path)?;
    let geometry = GridGeometry::new(image.width, image.height, opts.resolution_m, opts.origin);
    crate::scene::check_extent(opts.origin, geometry.extent_m(), "origin", image_path)?;
    let (obstacles, counts) = obstacle_layer(&image, opts);
    let (geometry, obstacles, counts) = if opts.yaw_rad == 0.0 {
        (geometry, obstacles, counts)
    } else {
        super::rotation::rotate_obstacles(&geometry, &obstacles, opts.yaw_rad, image_path)?
    };
    if counts.free == 0 {
        return Err(WorldError::invalid(
            image_path,
            "pixels",
            format!(
                "no free pixel ({} occupied, {} unknown)",
                group_thousands(counts.occupied),
                group_thousands(counts.unknown)
            ),
            format!(
                "at least one free pixel (occupancy below free_thresh {}{})",
                opts.free_thresh,
                if opts.negate { ", negate on" } else { "" }
            ),
        ));
    }
    let obstacle = Grid::from_vec(geometry, obstacles).expect("one value per pixel");
    let start = deepest_free_cell(&obstacle).expect("at least one free cell");
    let mut scene = Scene::empty(name, geometry);
    scene.obstacle = obstacle;
    scene.provenance = Provenance {
        source: "import".to_string(),
        seed: None,
        detail,
    };
    let p = geometry.cell_center(start);
    scene.start_poses.push(Pose2::new(p.x, p.y, 0.0));
    Ok(scene)
}

/// How many pixels fell in each class.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PixelCounts {
    pub free: u64,
    pub occupied: u64,
    pub unknown: u64,
}

/// The obstacle layer of an image, rows flipped (image row 0 becomes scene row `height − 1`).
pub fn obstacle_layer(image: &DecodedImage, opts: &ImageMapOptions) -> (Vec<u8>, PixelCounts) {
    let (w, h) = (image.width as usize, image.height as usize);
    let spp = image.samples_per_pixel();
    let n = image.colour_channels as usize;
    let mut out = vec![obstacle::WALL; w * h];
    let mut counts = PixelCounts::default();
    for (img_row, row_samples) in image.samples.chunks_exact(w * spp).enumerate().take(h) {
        let scene_row = h - 1 - img_row;
        let out_row = &mut out[scene_row * w..(scene_row + 1) * w];
        for (cell, px) in out_row.iter_mut().zip(row_samples.chunks_exact(spp)) {
            let colour_sum: u32 = px[..n].iter().map(|&s| u32::from(s)).sum();
            let opaque = !image.has_alpha || u32::from(px[n]) >= image.maxval;
            let class = classify_pixel(colour_sum, n as u32, image.maxval, opaque, opts);
            *cell = match class {
                PixelClass::Free => {
                    counts.free += 1;
                    obstacle::NONE
                }
                PixelClass::Occupied => {
                    counts.occupied += 1;
                    obstacle::WALL
                }
                PixelClass::Unknown => {
                    counts.unknown += 1;
                    obstacle::WALL
                }
            };
        }
    }
    (out, counts)
}

/// The deterministic start cell of an imported map: among the cells of the largest 4-connected
/// obstacle-free region (ties: the region containing the lowest row-major index), the cell with
/// the largest clearance, i.e. Euclidean distance from its centre to the nearest obstacle cell's
/// centre, the grid border counting as an obstacle ring just outside the grid (ties: lowest
/// index). `None` when there is no free cell.
pub fn deepest_free_cell(obstacles: &Grid<u8>) -> Option<Cell> {
    let g = *obstacles.geometry();
    let free: Vec<bool> = obstacles
        .as_slice()
        .iter()
        .map(|&o| o == obstacle::NONE)
        .collect();
    let region = largest_region(&g, &free)?;
    let clearance = squared_clearance(&g, &free);
    let mut best: Option<(usize, f64)> = None;
    for (i, &d) in clearance.iter().enumerate() {
        if region[i] && best.is_none_or(|(_, b)| d > b) {
            best = Some((i, d));
        }
    }
    best.map(|(i, _)| g.cell_of_index(i))
}

/// Mask of the largest 4-connected region of `free` cells (first found wins ties).
fn largest_region(g: &GridGeometry, free: &[bool]) -> Option<Vec<bool>> {
    let mut label = vec![0u32; free.len()];
    let mut best: Option<(u32, usize)> = None;
    let mut next = 0u32;
    let mut stack = Vec::new();
    for seed in 0..free.len() {
        if !free[seed] || label[seed] != 0 {
            continue;
        }
        next += 1;
        label[seed] = next;
        stack.push(seed);
        let mut size = 0usize;
        while let Some(i) = stack.pop() {
            size += 1;
            let c = g.cell_of_index(i);
            for &(dc, dr) in &NEIGHBORS8[..4] {
                let n = Cell::new(c.col + dc, c.row + dr);
                if let Some(j) = g.checked_index(n).filter(|&j| free[j] && label[j] == 0) {
                    label[j] = next;
                    stack.push(j);
                }
            }
        }
        if best.is_none_or(|(_, s)| size > s) {
            best = Some((next, size));
        }
    }
    let (winner, _) = best?;
    Some(label.iter().map(|&l| l == winner).collect())
}

/// Squared Euclidean distance (in cells) from every cell to the nearest non-free cell, with a
/// ring of obstacles just outside the grid: the exact two-pass transform of Felzenszwalb and
/// Huttenlocher, "Distance Transforms of Sampled Functions" (2012), §2.
fn squared_clearance(g: &GridGeometry, free: &[bool]) -> Vec<f64> {
    /// Stands for "no obstacle in this line" (finite so that the parabola algebra stays exact).
    const FAR: f64 = 1e20;
    let (w, h) = (g.width as usize, g.height as usize);
    let mut dist = vec![0.0f64; w * h];
    let longest = w.max(h) + 2;
    let mut f = vec![0.0f64; longest];
    let mut d = vec![0.0f64; longest];
    let mut v = vec![0usize; longest];
    let mut z = vec![0.0f64; longest + 1];
    // Columns: padded with an obstacle below row 0 and above row h − 1.
    for col in 0..w {
        f[0] = 0.0;
        f[h + 1] = 0.0;
        for row in 0..h {
            f[row + 1] = if free[row * w + col] { FAR } else { 0.0 };
        }
        distance_1d(&f[..h + 2], &mut d[..h + 2], &mut v, &mut z);
        for row in 0..h {
            dist[row * w + col] = d[row + 1];
        }
    }
    // Rows: padded with the (all-obstacle) columns left of 0 and right of w − 1.
    for row in 0..h {
        f[0] = 0.0;
        f[w + 1] = 0.0;
        f[1..=w].copy_from_slice(&dist[row * w..(row + 1) * w]);
        distance_1d(&f[..w + 2], &mut d[..w + 2], &mut v, &mut z);
        dist[row * w..(row + 1) * w].copy_from_slice(&d[1..=w]);
    }
    dist
}

/// One-dimensional squared distance transform: d[q] = min_p (q − p)² + f[p] (lower envelope of
/// parabolas).
fn distance_1d(f: &[f64], d: &mut [f64], v: &mut [usize], z: &mut [f64]) {
    let n = f.len();
    let mut k = 0usize;
    v[0] = 0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    let sq = |x: usize| (x * x) as f64;
    for q in 1..n {
        // z[0] = −∞, so the loop stops at k = 0 at the latest.
        let s = loop {
            let p = v[k];
            let s = ((f[q] + sq(q)) - (f[p] + sq(p))) / (2.0 * (q as f64 - p as f64));
            if s <= z[k] {
                k -= 1;
            } else {
                break s;
            }
        };
        k += 1;
        v[k] = q;
        z[k] = s;
        z[k + 1] = f64::INFINITY;
    }
    k = 0;
    for (q, dq) in d.iter_mut().enumerate().take(n) {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let p = v[k];
        let diff = q as f64 - p as f64;
        *dq = diff * diff + f[p];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn opts() -> ImageMapOptions {
        ImageMapOptions::default()
    }

    #[test]
    fn thresholds_follow_the_chosen_convention_at_exact_ties() {
        // free_thresh 0.2 = (255 − 204)/255 exactly: unknown under ROS 1, free under Nav2.
        let ros1 = ImageMapOptions {
            free_thresh: 0.2,
            ..opts()
        };
        let nav2 = ImageMapOptions {
            convention: ThresholdConvention::Nav2,
            ..ros1
        };
        assert_eq!(
            classify_pixel(204, 1, 255, true, &ros1),
            PixelClass::Unknown
        );
        assert_eq!(classify_pixel(204, 1, 255, true, &nav2), PixelClass::Free);
        // occupied_thresh 0.6 = (255 − 102)/255.
        let ros1 = ImageMapOptions {
            occupied_thresh: 0.6,
            ..opts()
        };
        let nav2 = ImageMapOptions {
            convention: ThresholdConvention::Nav2,
            ..ros1
        };
        assert_eq!(
            classify_pixel(102, 1, 255, true, &ros1),
            PixelClass::Unknown
        );
        assert_eq!(
            classify_pixel(102, 1, 255, true, &nav2),
            PixelClass::Occupied
        );
    }

    #[test]
    fn map_saver_values_classify_as_ros_does() {
        let o = opts();
        assert_eq!(classify_pixel(254, 1, 255, true, &o), PixelClass::Free);
        assert_eq!(classify_pixel(205, 1, 255, true, &o), PixelClass::Unknown);
        assert_eq!(classify_pixel(0, 1, 255, true, &o), PixelClass::Occupied);
        // depot.yaml's free_thresh 0.25 makes 205 free.
        let depot = ImageMapOptions {
            free_thresh: 0.25,
            ..o
        };
        assert_eq!(classify_pixel(205, 1, 255, true, &depot), PixelClass::Free);
        // negate swaps dark and light.
        let neg = ImageMapOptions { negate: true, ..o };
        assert_eq!(classify_pixel(0, 1, 255, true, &neg), PixelClass::Free);
        assert_eq!(
            classify_pixel(254, 1, 255, true, &neg),
            PixelClass::Occupied
        );
        // Transparent is unknown whatever the colour.
        assert_eq!(classify_pixel(255, 1, 255, false, &o), PixelClass::Unknown);
        // RGB channels are averaged: (255 + 255 + 0)/3 = 170 → p = 0.333, unknown.
        assert_eq!(classify_pixel(510, 3, 255, true, &o), PixelClass::Unknown);
    }

    #[test]
    fn scale_and_raw_modes_binarise_graded_occupancy_at_one_half() {
        let scale = ImageMapOptions {
            mode: ThresholdMode::Scale,
            ..opts()
        };
        // Midpoint of [0.196, 0.65] is 0.423 → v ≈ 147.
        assert_eq!(
            classify_pixel(140, 1, 255, true, &scale),
            PixelClass::Occupied
        );
        assert_eq!(classify_pixel(155, 1, 255, true, &scale), PixelClass::Free);
        let raw = ImageMapOptions {
            mode: ThresholdMode::Raw,
            ..opts()
        };
        assert_eq!(classify_pixel(0, 1, 255, true, &raw), PixelClass::Free);
        assert_eq!(
            classify_pixel(100, 1, 255, true, &raw),
            PixelClass::Occupied
        );
        assert_eq!(classify_pixel(50, 1, 255, true, &raw), PixelClass::Occupied);
        assert_eq!(classify_pixel(30, 1, 255, true, &raw), PixelClass::Free);
        assert_eq!(classify_pixel(255, 1, 255, true, &raw), PixelClass::Unknown);
    }

    #[test]
    fn group_thousands_separates_with_spaces() {
        assert_eq!(group_thousands(0), "0");
        assert_eq!(group_thousands(999), "999");
        assert_eq!(group_thousands(1000), "1 000");
        assert_eq!(group_thousands(307_184), "307 184");
        assert_eq!(group_thousands(1_684_044), "1 684 044");
    }

    fn brute_force_clearance(g: &GridGeometry, free: &[bool]) -> Vec<f64> {
        let (w, h) = (g.width as i64, g.height as i64);
        let mut out = Vec::new();
        for r in 0..h {
            for c in 0..w {
                let mut best = i64::MAX;
                for rr in -1..=h {
                    for cc in -1..=w {
                        let outside = rr < 0 || cc < 0 || rr >= h || cc >= w;
                        if outside || !free[(rr * w + cc) as usize] {
                            best = best.min((rr - r).pow(2) + (cc - c).pow(2));
                        }
                    }
                }
                out.push(best as f64);
            }
        }
        out
    }

    proptest::proptest! {
        #[test]
        fn distance_transform_matches_brute_force(
            w in 1u32..12,
            h in 1u32..12,
            bits in proptest::collection::vec(proptest::bool::weighted(0.8), 144),
        ) {
            let g = GridGeometry::new(w, h, 0.1, Point2::new(0.0, 0.0));
            let free: Vec<bool> = bits[..g.len()].to_vec();
            proptest::prop_assert_eq!(squared_clearance(&g, &free), brute_force_clearance(&g, &free));
        }
    }

    #[test]
    fn deepest_free_cell_prefers_the_largest_region_and_its_centre() {
        // A 3×3 open box on the left (walls around it) and a 5×5 open box on the right.
        let g = GridGeometry::new(13, 7, 1.0, Point2::new(0.0, 0.0));
        let mut grid = Grid::filled(g, obstacle::WALL);
        for r in 2..5 {
            for c in 1..4 {
                grid[Cell::new(c, r)] = obstacle::NONE;
            }
        }
        for r in 1..6 {
            for c in 6..11 {
                grid[Cell::new(c, r)] = obstacle::NONE;
            }
        }
        assert_eq!(deepest_free_cell(&grid), Some(Cell::new(8, 3)));
        let none = Grid::filled(g, obstacle::WALL);
        assert_eq!(deepest_free_cell(&none), None);
    }
}
