//! CDR, the wire form of ROS 2 messages (OMG XCDR1, little endian, as `rmw` and MCAP's `cdr`
//! message encoding use it): a 4-byte encapsulation header, then every primitive aligned to
//! its own size (up to 8) counted from the end of the header; a string is its length with the
//! terminating NUL, its bytes and the NUL; a sequence its element count and its elements; a
//! fixed array its elements alone.

/// A message being encoded.
pub struct CdrWriter {
    buf: Vec<u8>,
}

/// The encapsulation header of little-endian plain CDR.
const CDR_LE: [u8; 4] = [0x00, 0x01, 0x00, 0x00];

impl Default for CdrWriter {
    fn default() -> Self {
        Self::new()
    }
}

impl CdrWriter {
    pub fn new() -> Self {
        Self {
            buf: CDR_LE.to_vec(),
        }
    }

    /// The encoded message.
    pub fn finish(self) -> Vec<u8> {
        self.buf
    }

    fn align(&mut self, n: usize) {
        let offset = self.buf.len() - CDR_LE.len();
        let pad = (n - offset % n) % n;
        self.buf.extend(std::iter::repeat_n(0u8, pad));
    }

    pub fn bool(&mut self, v: bool) -> &mut Self {
        self.buf.push(u8::from(v));
        self
    }

    pub fn i8(&mut self, v: i8) -> &mut Self {
        self.buf.push(v as u8);
        self
    }

    pub fn i32(&mut self, v: i32) -> &mut Self {
        self.align(4);
        self.buf.extend(v.to_le_bytes());
        self
    }

    pub fn u32(&mut self, v: u32) -> &mut Self {
        self.align(4);
        self.buf.extend(v.to_le_bytes());
        self
    }

    pub fn f32(&mut self, v: f32) -> &mut Self {
        self.align(4);
        self.buf.extend(v.to_le_bytes());
        self
    }

    pub fn f64(&mut self, v: f64) -> &mut Self {
        self.align(8);
        self.buf.extend(v.to_le_bytes());
        self
    }

    pub fn string(&mut self, s: &str) -> &mut Self {
        self.u32(s.len() as u32 + 1);
        self.buf.extend(s.as_bytes());
        self.buf.push(0);
        self
    }

    /// The element count of a sequence; its elements follow.
    pub fn len(&mut self, n: usize) -> &mut Self {
        self.u32(n as u32)
    }

    /// A `float32[]`.
    pub fn f32s(&mut self, v: &[f32]) -> &mut Self {
        self.len(v.len());
        for &x in v {
            self.f32(x);
        }
        self
    }

    /// An `int8[]`.
    pub fn i8s(&mut self, v: &[i8]) -> &mut Self {
        self.len(v.len());
        self.buf.extend(v.iter().map(|&x| x as u8));
        self
    }
}

#[cfg(test)]
mod tests {
    use super::CdrWriter;

    #[test]
    fn primitives_align_to_their_size_after_the_header() {
        let mut w = CdrWriter::new();
        w.bool(true).f64(1.0).string("ab").i8(-1).f32(2.0);
        let b = w.finish();
        assert_eq!(&b[..4], &[0, 1, 0, 0]);
        // bool at 0, f64 padded to 8, string length at 16 ("ab\0": 3), its bytes, i8 at 23,
        // f32 padded to 24.
        assert_eq!(b[4], 1);
        assert_eq!(&b[12..20], &1.0f64.to_le_bytes());
        assert_eq!(&b[20..24], &3u32.to_le_bytes());
        assert_eq!(&b[24..27], b"ab\0");
        assert_eq!(b[27], 0xff);
        assert_eq!(&b[28..32], &2.0f32.to_le_bytes());
        assert_eq!(b.len(), 32);
    }
}
