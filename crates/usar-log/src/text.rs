//! Lines of a text log (gzipped or not), each at most [`limits::MAX_LINE_BYTES`], and the
//! fields of a record, refused with their line when they are not what the format expects.

use crate::{LogError, limits};
use std::fmt::Display;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::str::SplitAsciiWhitespace;

/// The lines of a log, numbered from 1.
pub(crate) struct Lines {
    pub path: PathBuf,
    reader: Box<dyn BufRead>,
    line_no: u64,
    buf: Vec<u8>,
    /// Bytes read so far (decompressed), against `usar_world::limits`' file size.
    read: u64,
}

impl Lines {
    pub fn open(path: &Path) -> Result<Self, LogError> {
        let io = |source| LogError::Io {
            path: path.to_path_buf(),
            source,
        };
        let mut file = BufReader::new(std::fs::File::open(path).map_err(io)?);
        // Gzip by its magic number, whatever the name.
        let gzipped = file.fill_buf().map_err(io)?.starts_with(&[0x1f, 0x8b]);
        let reader: Box<dyn BufRead> = if gzipped {
            Box::new(BufReader::new(flate2::bufread::MultiGzDecoder::new(file)))
        } else {
            Box::new(file)
        };
        Ok(Self::new(reader, path.to_path_buf()))
    }

    pub fn from_bytes(bytes: &[u8], name: &str) -> Self {
        Self::new(Box::new(std::io::Cursor::new(bytes.to_vec())), name.into())
    }

    fn new(reader: Box<dyn BufRead>, path: PathBuf) -> Self {
        Self {
            path,
            reader,
            line_no: 0,
            buf: Vec::new(),
            read: 0,
        }
    }

    /// The next line (number, text without its end), or `None` at the end of the file.
    pub fn next_line(&mut self) -> Result<Option<(u64, &str)>, LogError> {
        self.buf.clear();
        let cap = limits::MAX_LINE_BYTES as u64 + 1;
        let n = (&mut self.reader)
            .take(cap)
            .read_until(b'\n', &mut self.buf)
            .map_err(|source| LogError::Io {
                path: self.path.clone(),
                source,
            })?;
        if n == 0 {
            return Ok(None);
        }
        self.line_no += 1;
        self.read += n as u64;
        let max = usar_world::limits::limits().max_file_bytes;
        if self.read > max {
            return Err(self.error(format!(
                "more than {max} bytes of log (raise the limit with --max-file-mb)"
            )));
        }
        if self.buf.len() > limits::MAX_LINE_BYTES {
            return Err(self.error(format!(
                "a line of more than {} bytes (expected one record a line)",
                limits::MAX_LINE_BYTES
            )));
        }
        let line_no = self.line_no;
        let path = &self.path;
        let text = std::str::from_utf8(&self.buf).map_err(|_| LogError::Record {
            path: path.clone(),
            line: line_no,
            what: "bytes that are not text (expected an ASCII log record)".into(),
        })?;
        Ok(Some((line_no, text.trim_end_matches(['\n', '\r']))))
    }

    pub fn error(&self, what: String) -> LogError {
        LogError::Record {
            path: self.path.clone(),
            line: self.line_no,
            what,
        }
    }
}

/// The fields of one record after its keyword, read in order.
pub(crate) struct Fields<'a> {
    words: SplitAsciiWhitespace<'a>,
    keyword: &'a str,
    path: &'a Path,
    line: u64,
}

impl<'a> Fields<'a> {
    pub fn new(line: &'a str, path: &'a Path, line_no: u64) -> Option<Self> {
        let mut words = line.split_ascii_whitespace();
        let keyword = words.next()?;
        Some(Self {
            words,
            keyword,
            path,
            line: line_no,
        })
    }

    pub fn keyword(&self) -> &'a str {
        self.keyword
    }

    pub fn error(&self, what: String) -> LogError {
        LogError::Record {
            path: self.path.to_path_buf(),
            line: self.line,
            what: format!("{}: {what}", self.keyword),
        }
    }

    /// The next field (`name` says what it is, for the error; it is only formatted then).
    fn word(&mut self, name: &impl Display) -> Result<&'a str, LogError> {
        match self.words.next() {
            Some(w) => Ok(w),
            None => Err(self.error(format!("the record ends before its {name}"))),
        }
    }

    /// The next field as a finite number.
    pub fn number(&mut self, name: impl Display) -> Result<f64, LogError> {
        let word = self.word(&name)?;
        match word.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(self.error(format!("{name} is {word:?} (expected a finite number)"))),
        }
    }

    /// The next field as a reading: a number, where NaN or an infinity is kept (some logs
    /// write `nan` or `inf` for no reading).
    pub fn reading(&mut self, name: impl Display) -> Result<f64, LogError> {
        let word = self.word(&name)?;
        word.parse::<f64>()
            .map_err(|_| self.error(format!("{name} is {word:?} (expected a number)")))
    }

    /// The next field as a count of at most `max`.
    pub fn count(&mut self, name: impl Display, max: usize) -> Result<usize, LogError> {
        let word = self.word(&name)?;
        match word.parse::<usize>() {
            Ok(n) if n <= max => Ok(n),
            _ => Err(self.error(format!(
                "{name} is {word:?} (expected a whole number from 0 to {max})"
            ))),
        }
    }

    /// `n` readings.
    pub fn readings(&mut self, n: usize, scale: f64) -> Result<Vec<f32>, LogError> {
        (0..n)
            .map(|k| {
                self.reading(format_args!("reading {} of {n}", k + 1))
                    .map(|v| (v * scale) as f32)
            })
            .collect()
    }

    /// A pose `x y theta` (`scale` for x and y).
    pub fn pose(&mut self, name: &str, scale: f64) -> Result<usar_world::Pose2, LogError> {
        let x = self.number(format_args!("{name} x"))? * scale;
        let y = self.number(format_args!("{name} y"))? * scale;
        let theta = self.number(format_args!("{name} theta"))?;
        Ok(usar_world::Pose2::new(x, y, theta))
    }

    /// Skips `n` fields.
    pub fn skip(&mut self, n: usize, name: &str) -> Result<(), LogError> {
        for _ in 0..n {
            self.word(&name)?;
        }
        Ok(())
    }

    /// Fields left.
    pub fn rest(&mut self) -> usize {
        self.words.by_ref().count()
    }
}

/// Counts records against [`limits::MAX_RECORDS`].
pub(crate) fn check_records(lines: &Lines, records: usize) -> Result<(), LogError> {
    if records > limits::MAX_RECORDS {
        return Err(lines.error(format!(
            "more than {} records (a log that large is refused)",
            limits::MAX_RECORDS
        )));
    }
    Ok(())
}
