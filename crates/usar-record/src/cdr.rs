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

/// A message being decoded: the reverse of [`CdrWriter`], little or big endian as its header
/// says. Every read is bounds-checked; a sequence's declared length is checked against the
/// bytes left before anything is allocated.
pub struct CdrReader<'a> {
    body: &'a [u8],
    at: usize,
    little: bool,
}

/// Why a message could not be decoded.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum CdrError {
    #[error("the message ends at byte {0} before its {1}")]
    Truncated(usize, &'static str),
    #[error("encapsulation header {0:02x?} (expected plain CDR, little or big endian)")]
    Encapsulation([u8; 4]),
    #[error("{0} is not UTF-8 text")]
    Text(&'static str),
}

impl<'a> CdrReader<'a> {
    pub fn new(message: &'a [u8]) -> Result<Self, CdrError> {
        let header: [u8; 4] = message
            .get(..4)
            .and_then(|h| h.try_into().ok())
            .ok_or(CdrError::Truncated(0, "encapsulation header"))?;
        let little = match header[..2] {
            [0x00, 0x01] => true,
            [0x00, 0x00] => false,
            _ => return Err(CdrError::Encapsulation(header)),
        };
        Ok(Self {
            body: &message[4..],
            at: 0,
            little,
        })
    }

    fn take<const N: usize>(&mut self, what: &'static str) -> Result<[u8; N], CdrError> {
        let start = self.at.next_multiple_of(N.min(8));
        let bytes = self
            .body
            .get(start..start + N)
            .ok_or(CdrError::Truncated(start + 4, what))?;
        self.at = start + N;
        let mut b: [u8; N] = bytes.try_into().expect("N bytes");
        if !self.little {
            b.reverse();
        }
        Ok(b)
    }

    pub fn u8(&mut self, what: &'static str) -> Result<u8, CdrError> {
        Ok(self.take::<1>(what)?[0])
    }

    pub fn i32(&mut self, what: &'static str) -> Result<i32, CdrError> {
        self.take(what).map(i32::from_le_bytes)
    }

    pub fn u32(&mut self, what: &'static str) -> Result<u32, CdrError> {
        self.take(what).map(u32::from_le_bytes)
    }

    pub fn f32(&mut self, what: &'static str) -> Result<f32, CdrError> {
        self.take(what).map(f32::from_le_bytes)
    }

    pub fn f64(&mut self, what: &'static str) -> Result<f64, CdrError> {
        self.take(what).map(f64::from_le_bytes)
    }

    /// A sequence's element count, refused when its `element_bytes`-byte elements would not
    /// fit in what is left of the message.
    pub fn len(&mut self, element_bytes: usize, what: &'static str) -> Result<usize, CdrError> {
        let n = self.u32(what)? as usize;
        let left = self.body.len().saturating_sub(self.at);
        if n.saturating_mul(element_bytes.max(1)) > left {
            return Err(CdrError::Truncated(self.body.len() + 4, what));
        }
        Ok(n)
    }

    pub fn string(&mut self, what: &'static str) -> Result<&'a str, CdrError> {
        let n = self.len(1, what)?;
        let bytes = &self.body[self.at..self.at + n];
        self.at += n;
        let text = bytes.strip_suffix(&[0]).unwrap_or(bytes);
        std::str::from_utf8(text).map_err(|_| CdrError::Text(what))
    }

    pub fn f32s(&mut self, what: &'static str) -> Result<Vec<f32>, CdrError> {
        let n = self.len(4, what)?;
        (0..n).map(|_| self.f32(what)).collect()
    }

    /// Skips `n` values of `N` bytes.
    pub fn skip<const N: usize>(&mut self, n: usize, what: &'static str) -> Result<(), CdrError> {
        for _ in 0..n {
            self.take::<N>(what)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::{CdrError, CdrReader, CdrWriter};

    #[test]
    fn what_is_written_reads_back_and_a_short_message_is_refused() {
        let mut w = CdrWriter::new();
        w.u32(7)
            .f64(1.5)
            .string("base_link")
            .f32s(&[1.0, 2.5])
            .i32(-3);
        let b = w.finish();
        let mut r = CdrReader::new(&b).unwrap();
        assert_eq!(r.u32("a").unwrap(), 7);
        assert_eq!(r.f64("b").unwrap(), 1.5);
        assert_eq!(r.string("c").unwrap(), "base_link");
        assert_eq!(r.f32s("d").unwrap(), vec![1.0, 2.5]);
        assert_eq!(r.i32("e").unwrap(), -3);
        assert!(matches!(r.u8("f"), Err(CdrError::Truncated(_, "f"))));
        // A sequence that declares more elements than the message holds.
        let mut w = CdrWriter::new();
        w.u32(1_000_000_000);
        let b = w.finish();
        assert!(CdrReader::new(&b).unwrap().f32s("ranges").is_err());
        assert!(matches!(
            CdrReader::new(&[7, 7, 0, 0]),
            Err(CdrError::Encapsulation(_))
        ));
    }

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
