//! An MCAP file of ROS 2 messages: one schema per message type, one channel per topic, each
//! message stamped with the simulated time (nanoseconds from the run's start).

use crate::RecordError;
use crate::msgs::MsgType;
use std::collections::BTreeMap;
use std::io::{Seek, Write};

/// See the [module documentation](self).
pub struct Recording<W: Write + Seek> {
    writer: mcap::Writer<W>,
    schemas: BTreeMap<&'static str, u16>,
    channels: BTreeMap<String, u16>,
    sequence: u32,
    /// Messages written so far.
    pub messages: u64,
}

impl<W: Write + Seek> Recording<W> {
    /// A recording into `w` (MCAP profile `ros2`).
    pub fn new(w: W) -> Result<Self, RecordError> {
        let writer = mcap::WriteOptions::new()
            .profile("ros2")
            .library(format!("usar-record {}", env!("CARGO_PKG_VERSION")))
            .compression(Some(mcap::Compression::Zstd))
            .compression_level(1)
            .create(w)?;
        Ok(Self {
            writer,
            schemas: BTreeMap::new(),
            channels: BTreeMap::new(),
            sequence: 0,
            messages: 0,
        })
    }

    /// Writes `data` (a CDR message of type `ty`) on `topic` at simulated time `t_s`.
    pub fn write(
        &mut self,
        topic: &str,
        ty: fn() -> MsgType,
        t_s: f64,
        data: &[u8],
    ) -> Result<(), RecordError> {
        let channel = match self.channels.get(topic) {
            Some(&c) => c,
            None => {
                let ty = ty();
                let schema = match self.schemas.get(ty.name) {
                    Some(&s) => s,
                    None => {
                        let s =
                            self.writer
                                .add_schema(ty.name, "ros2msg", ty.definition.as_bytes())?;
                        self.schemas.insert(ty.name, s);
                        s
                    }
                };
                let c = self
                    .writer
                    .add_channel(schema, topic, "cdr", &BTreeMap::new())?;
                self.channels.insert(topic.to_string(), c);
                c
            }
        };
        let time = (t_s.max(0.0) * 1e9).round() as u64;
        self.sequence = self.sequence.wrapping_add(1);
        self.writer.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id: channel,
                sequence: self.sequence,
                log_time: time,
                publish_time: time,
            },
            data,
        )?;
        self.messages += 1;
        Ok(())
    }

    /// Writes the summary and index; the file is complete.
    pub fn finish(mut self) -> Result<u64, RecordError> {
        self.writer.finish()?;
        Ok(self.messages)
    }
}

/// A recording written from inside a run that cannot be stopped by a failed write (a mission,
/// a build, an evaluation): the first error is kept, nothing more is written, and
/// [`Sticky::finish`] reports it.
pub(crate) struct Sticky<W: Write + Seek> {
    recording: Recording<W>,
    error: Option<RecordError>,
}

impl<W: Write + Seek> Sticky<W> {
    pub fn new(recording: Recording<W>) -> Self {
        Self {
            recording,
            error: None,
        }
    }

    /// Runs `write` unless a write failed before; whether the recording is still sound.
    pub fn write_with(
        &mut self,
        write: impl FnOnce(&mut Recording<W>) -> Result<(), RecordError>,
    ) -> bool {
        if self.error.is_none()
            && let Err(e) = write(&mut self.recording)
        {
            self.error = Some(e);
        }
        self.error.is_none()
    }

    /// Completes the file; the messages written, or the error that ended the recording.
    pub fn finish(self) -> Result<u64, RecordError> {
        match self.error {
            Some(e) => Err(e),
            None => self.recording.finish(),
        }
    }
}
