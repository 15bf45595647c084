//! The compact binary form of a BTM (`.btmb`), for sending a map over a rescue site's radio
//! link — the small size that paper 004 §I gives as the reason for a topological map.
//!
//! Layout (little endian; `uv` = unsigned LEB128 varint; `f32` = IEEE single):
//!
//! ```text
//! "BTMB" version:u8
//! strings: uv count, then per string: uv byte length, UTF-8 bytes
//! nodes:   uv count, then per node:
//!          uv id, f32 x_m, f32 y_m, uv kind (string index), uv subtype (index + 1, 0 = none),
//!          u8 mask: 1 slope_inclination_rad, 2 step_height_m, 4 max_robot_inclination_rad,
//!                   8 operator_note, 16 extra
//!          the present f32 values in mask order, uv note (string index), extra
//! links:   uv count, then per link:
//!          uv id, uv start, uv end (id + 1, 0 = open), f32 direction_rad,
//!          u8 mask: 1 searched, 2 length_m, 4 min_width_m, 8 max_inclination_rad,
//!                   16 max_step_m, 32 extra
//!          the present f32 values in mask order, extra
//! extra:   uv count, then per attribute: uv key (string index), uv value (string index of
//!          its JSON text)
//! ```
//!
//! Numbers are stored as `f32`: coordinates keep better than 1 mm up to 8 km from the origin,
//! angles better than 1 µrad. Kinds, subtypes and attribute names are open strings, so new
//! kinds and attributes travel without a format change.
//!
//! Decoding never trusts a count: each is checked against the bytes left (every item takes at
//! least its smallest encoding) and the limits of [`crate::validate`] before anything is
//! stored, so a short file declaring billions of nodes is refused at once. The decoded map is
//! checked like any map read from outside ([`crate::validate::check`]).

use crate::model::{Btm, Extra, Link, Node};
use crate::validate::{MAX_LINKS, MAX_NODES};

/// The smallest encodings, bytes: a string (its length), a node (id, x, y, kind, subtype,
/// mask), a link (id, start, end, direction, mask), an attribute (key, value).
const MIN_STRING: u64 = 1;
const MIN_NODE: u64 = 1 + 4 + 4 + 1 + 1 + 1;
const MIN_LINK: u64 = 1 + 1 + 1 + 4 + 1;
const MIN_ATTRIBUTE: u64 = 2;

const MAGIC: &[u8; 4] = b"BTMB";
pub const WIRE_VERSION: u8 = 1;

struct Writer {
    out: Vec<u8>,
}

impl Writer {
    fn uv(&mut self, mut v: u64) {
        loop {
            let byte = (v & 0x7f) as u8;
            v >>= 7;
            if v == 0 {
                self.out.push(byte);
                return;
            }
            self.out.push(byte | 0x80);
        }
    }

    fn f32(&mut self, v: f64) {
        self.out.extend_from_slice(&(v as f32).to_le_bytes());
    }

    /// The present values, in order (their mask bits are written by the caller).
    fn present(&mut self, values: &[Option<f64>]) {
        for v in values.iter().flatten() {
            self.f32(*v);
        }
    }

    fn extra(&mut self, extra: &Extra, strings: &mut Strings) {
        self.uv(extra.len() as u64);
        for (k, v) in extra {
            self.uv(strings.index(k));
            self.uv(strings.index(&v.to_string()));
        }
    }
}

/// Mask bits `first_bit << i` for the values present.
fn presence(values: &[Option<f64>], first_bit: u8) -> u8 {
    values
        .iter()
        .enumerate()
        .filter(|(_, v)| v.is_some())
        .fold(0, |mask, (i, _)| mask | (first_bit << i))
}

/// Interns strings in first-use order.
#[derive(Default)]
struct Strings {
    list: Vec<String>,
}

impl Strings {
    fn index(&mut self, s: &str) -> u64 {
        match self.list.iter().position(|t| t == s) {
            Some(i) => i as u64,
            None => {
                self.list.push(s.to_string());
                (self.list.len() - 1) as u64
            }
        }
    }
}

/// Encodes a map in the binary wire form.
pub fn encode(btm: &Btm) -> Vec<u8> {
    let mut strings = Strings::default();
    let mut body = Writer { out: Vec::new() };
    let w = &mut body;
    w.uv(btm.nodes.len() as u64);
    for n in &btm.nodes {
        w.uv(u64::from(n.id));
        w.f32(n.x_m);
        w.f32(n.y_m);
        w.uv(strings.index(&n.kind));
        w.uv(n.subtype.as_deref().map_or(0, |s| strings.index(s) + 1));
        let values = [
            n.slope_inclination_rad,
            n.step_height_m,
            n.max_robot_inclination_rad,
        ];
        let mut mask = presence(&values, 1);
        if n.operator_note.is_some() {
            mask |= 8;
        }
        if !n.extra.is_empty() {
            mask |= 16;
        }
        w.out.push(mask);
        w.present(&values);
        if let Some(note) = &n.operator_note {
            w.uv(strings.index(note));
        }
        if !n.extra.is_empty() {
            w.extra(&n.extra, &mut strings);
        }
    }
    w.uv(btm.links.len() as u64);
    for l in &btm.links {
        w.uv(u64::from(l.id));
        w.uv(u64::from(l.start));
        w.uv(l.end.map_or(0, |e| u64::from(e) + 1));
        w.f32(l.direction_rad);
        let values = [
            l.length_m,
            l.min_width_m,
            l.max_inclination_rad,
            l.max_step_m,
        ];
        let mut mask = u8::from(l.searched) | presence(&values, 2);
        if !l.extra.is_empty() {
            mask |= 32;
        }
        w.out.push(mask);
        w.present(&values);
        if !l.extra.is_empty() {
            w.extra(&l.extra, &mut strings);
        }
    }
    let mut head = Writer {
        out: MAGIC.to_vec(),
    };
    head.out.push(WIRE_VERSION);
    head.uv(strings.list.len() as u64);
    for s in &strings.list {
        head.uv(s.len() as u64);
        head.out.extend_from_slice(s.as_bytes());
    }
    head.out.extend_from_slice(&body.out);
    head.out
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn fail<T>(&self, what: &str) -> Result<T, String> {
        Err(format!("byte {}: {what}", self.at))
    }

    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        if self.bytes.len() - self.at < n {
            return self.fail("the data ends early");
        }
        let s = &self.bytes[self.at..self.at + n];
        self.at += n;
        Ok(s)
    }

    fn u8(&mut self) -> Result<u8, String> {
        Ok(self.take(1)?[0])
    }

    fn uv(&mut self) -> Result<u64, String> {
        let mut v = 0u64;
        for shift in (0..64).step_by(7) {
            let b = self.u8()?;
            v |= u64::from(b & 0x7f) << shift;
            if b & 0x80 == 0 {
                return Ok(v);
            }
        }
        self.fail("a number longer than 64 bits")
    }

    fn id(&mut self) -> Result<u32, String> {
        let v = self.uv()?;
        u32::try_from(v).or_else(|_| self.fail(&format!("id {v} does not fit 32 bits")))
    }

    fn f32(&mut self) -> Result<f64, String> {
        let b = self.take(4)?;
        Ok(f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])))
    }

    /// A value that is there when `bit` of `mask` is set.
    fn optional(&mut self, mask: u8, bit: u8) -> Result<Option<f64>, String> {
        if mask & bit != 0 {
            self.f32().map(Some)
        } else {
            Ok(None)
        }
    }

    /// A count of `what`, checked against `limit` and against the bytes left (each item
    /// takes at least `min_bytes`), before anything is allocated for the items.
    fn count(&mut self, what: &str, min_bytes: u64, limit: u64) -> Result<usize, String> {
        let at = self.at;
        let n = self.uv()?;
        let left = (self.bytes.len() - self.at) as u64;
        if n > limit {
            return Err(format!("byte {at}: {n} {what}, expected at most {limit}"));
        }
        if n.saturating_mul(min_bytes) > left {
            return Err(format!(
                "byte {at}: {n} {what} declared, but only {left} bytes are left (at least {min_bytes} a piece)"
            ));
        }
        Ok(n as usize)
    }

    fn string<'s>(&self, strings: &'s [String], i: u64) -> Result<&'s str, String> {
        match strings.get(i as usize) {
            Some(s) => Ok(s),
            None => self.fail(&format!(
                "string index {i}, expected below {}",
                strings.len()
            )),
        }
    }

    fn extra(&mut self, strings: &[String]) -> Result<Extra, String> {
        let mut extra = Extra::new();
        for _ in 0..self.count("attributes", MIN_ATTRIBUTE, u64::MAX)? {
            let (k, v) = (self.uv()?, self.uv()?);
            let key = self.string(strings, k)?.to_string();
            let text = self.string(strings, v)?;
            let value = serde_json::from_str(text)
                .or_else(|e| self.fail(&format!("attribute {key:?}: {e}")))?;
            extra.insert(key, value);
        }
        Ok(extra)
    }
}

/// Why bytes are not a binary BTM.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DecodeError {
    /// The bytes break the wire format: `at` is "byte N: what was wrong".
    #[error("{0}")]
    Bytes(String),
    /// The bytes decode to a map that fails its checks.
    #[error(transparent)]
    Check(#[from] crate::validate::Invalid),
}

/// Decodes the binary wire form and checks the map ([`crate::validate::check`]); errors name
/// the byte offset and what was wrong, or the node or link and its field.
pub fn decode(bytes: &[u8]) -> Result<Btm, DecodeError> {
    let btm = decode_unchecked(bytes).map_err(DecodeError::Bytes)?;
    crate::validate::check(&btm)?;
    Ok(btm)
}

fn decode_unchecked(bytes: &[u8]) -> Result<Btm, String> {
    let mut r = Reader { bytes, at: 0 };
    if r.take(4).ok() != Some(MAGIC.as_slice()) {
        return Err("byte 0: expected the magic \"BTMB\" of a binary BTM".into());
    }
    let version = r.u8()?;
    if version > WIRE_VERSION {
        return r.fail(&format!(
            "version {version}, expected {WIRE_VERSION} or older"
        ));
    }
    let mut strings = Vec::new();
    for _ in 0..r.count("strings", MIN_STRING, u64::MAX)? {
        let len = r.count("string bytes", 1, u64::MAX)?;
        let at = r.at;
        let s = std::str::from_utf8(r.take(len)?)
            .map_err(|e| format!("byte {at}: a string that is not UTF-8: {e}"))?;
        strings.push(s.to_string());
    }
    let mut btm = Btm::default();
    for _ in 0..r.count("nodes", MIN_NODE, MAX_NODES as u64)? {
        let id = r.id()?;
        let (x, y) = (r.f32()?, r.f32()?);
        let kind = r.uv()?;
        let kind = r.string(&strings, kind)?.to_string();
        let subtype = match r.uv()? {
            0 => None,
            i => Some(r.string(&strings, i - 1)?.to_string()),
        };
        let mask = r.u8()?;
        let mut n = Node::new(id, x, y, &kind, subtype.as_deref());
        n.slope_inclination_rad = r.optional(mask, 1)?;
        n.step_height_m = r.optional(mask, 2)?;
        n.max_robot_inclination_rad = r.optional(mask, 4)?;
        if mask & 8 != 0 {
            let i = r.uv()?;
            n.operator_note = Some(r.string(&strings, i)?.to_string());
        }
        if mask & 16 != 0 {
            n.extra = r.extra(&strings)?;
        }
        btm.nodes.push(n);
    }
    for _ in 0..r.count("links", MIN_LINK, MAX_LINKS as u64)? {
        let id = r.id()?;
        let start = r.id()?;
        let end = match r.uv()? {
            0 => None,
            e => Some(u32::try_from(e - 1).or_else(|_| r.fail("link end does not fit 32 bits"))?),
        };
        let mut l = Link::unsearched(id, start, r.f32()?);
        l.end = end;
        let mask = r.u8()?;
        l.searched = mask & 1 != 0;
        l.length_m = r.optional(mask, 2)?;
        l.min_width_m = r.optional(mask, 4)?;
        l.max_inclination_rad = r.optional(mask, 8)?;
        l.max_step_m = r.optional(mask, 16)?;
        if mask & 32 != 0 {
            l.extra = r.extra(&strings)?;
        }
        btm.links.push(l);
    }
    if r.at != bytes.len() {
        return r.fail(&format!("{} bytes after the map", bytes.len() - r.at));
    }
    Ok(btm)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{kind, subtype};

    fn sample() -> Btm {
        let mut a = Node::new(1, 1.25, -3.5, kind::DIVERGENCE, Some(subtype::T_JUNCTION));
        a.operator_note = Some("operator drove here".into());
        let mut b = Node::new(300, 12.0, 4.0, kind::OBSTACLE, Some(subtype::STAIRS));
        b.step_height_m = Some(0.17);
        b.max_robot_inclination_rad = Some(0.6);
        b.extra.insert("impassable_for".into(), "wheeled".into());
        b.extra
            .insert("rises".into(), serde_json::json!([0.17, 0.16]));
        let c = Node::new(7, 0.0, 0.0, "hazard", None);
        let mut l1 = Link::unsearched(1, 1, 0.5);
        l1.end = Some(300);
        l1.searched = true;
        l1.length_m = Some(11.2);
        l1.min_width_m = Some(0.9);
        l1.max_inclination_rad = Some(0.0);
        let mut l2 = Link::unsearched(200, 300, -2.0);
        l2.extra.insert("blocked_for".into(), "crawler".into());
        Btm {
            nodes: vec![a, b, c],
            links: vec![l1, l2],
        }
    }

    fn close(a: Option<f64>, b: Option<f64>) -> bool {
        match (a, b) {
            (None, None) => true,
            (Some(a), Some(b)) => (a - b).abs() < 1e-5 * a.abs().max(1.0),
            _ => false,
        }
    }

    #[test]
    fn a_map_survives_the_round_trip_to_f32_precision() {
        let btm = sample();
        let back = decode(&encode(&btm)).expect("decodes");
        assert_eq!(back.nodes.len(), 3);
        assert_eq!(back.links.len(), 2);
        for (n, m) in btm.nodes.iter().zip(&back.nodes) {
            assert_eq!((n.id, &n.kind, &n.subtype), (m.id, &m.kind, &m.subtype));
            assert!(close(Some(n.x_m), Some(m.x_m)) && close(Some(n.y_m), Some(m.y_m)));
            assert!(close(n.step_height_m, m.step_height_m));
            assert!(close(n.slope_inclination_rad, m.slope_inclination_rad));
            assert!(close(
                n.max_robot_inclination_rad,
                m.max_robot_inclination_rad
            ));
            assert_eq!(n.operator_note, m.operator_note);
            assert_eq!(n.extra, m.extra);
        }
        for (l, k) in btm.links.iter().zip(&back.links) {
            assert_eq!(
                (l.id, l.start, l.end, l.searched),
                (k.id, k.start, k.end, k.searched)
            );
            assert!(close(Some(l.direction_rad), Some(k.direction_rad)));
            assert!(close(l.length_m, k.length_m) && close(l.min_width_m, k.min_width_m));
            assert!(close(l.max_inclination_rad, k.max_inclination_rad));
            assert_eq!(l.max_step_m, k.max_step_m);
            assert_eq!(l.extra, k.extra);
        }
    }

    #[test]
    fn every_truncation_and_a_foreign_file_are_errors_not_panics() {
        let bytes = encode(&sample());
        for cut in 0..bytes.len() {
            assert!(decode(&bytes[..cut]).is_err(), "cut at {cut}");
        }
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(
            decode(&longer)
                .unwrap_err()
                .to_string()
                .contains("after the map")
        );
        assert!(
            decode(b"PK\x03\x04rest")
                .unwrap_err()
                .to_string()
                .contains("magic")
        );
        let mut newer = bytes;
        newer[4] = WIRE_VERSION + 1;
        assert!(decode(&newer).unwrap_err().to_string().contains("version"));
    }
}
