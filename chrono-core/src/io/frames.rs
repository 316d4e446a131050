//! A series of VTK frames with its ParaView collection: one recorder for every kind of
//! frame (rigid shapes, grains, particles, finite-element meshes).
//!
//! A [`FrameSeries`] decides when a frame is due ([`Every`]: every `n` steps, or every
//! `dt` seconds of simulated time), names the frames `<prefix>_NNNNNN.<extension>`, calls
//! the writer the caller gives with the frame's path, and at the end writes
//! `<prefix>.pvd` ([`write_pvd`]) so ParaView plays the series. A disabled series
//! ([`FrameSeries::disabled`], or [`FrameSeries::new`] with no directory) writes nothing
//! and costs one branch per call, so scenes record unconditionally.

use std::path::{Path, PathBuf};

use crate::error::{ChronoError, Result};
use crate::io::{io_error, write_pvd};

/// When a frame is due.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Every {
    /// At every step that is a multiple of `n` (step 0 included); `0` counts as `1`.
    Steps(u64),
    /// At the first step at or after each multiple of `dt` seconds of simulated time
    /// (`t = 0` included).
    Seconds(f64),
}

/// A series of frames written into one directory, with its `.pvd` collection.
#[derive(Debug, Clone)]
pub struct FrameSeries {
    dir: Option<PathBuf>,
    prefix: String,
    extension: String,
    every: Every,
    next_time: f64,
    frames: Vec<(f64, String)>,
}

impl FrameSeries {
    /// Frames `<prefix>_NNNNNN.<extension>` (`extension` without the dot, for example
    /// `"vtp"` or `"vtu"`) into `dir` (created at the first frame), when due by `every`.
    /// `dir = None` gives a disabled series. A non-positive or non-finite
    /// `Every::Seconds` interval is an error naming `every`.
    pub fn new(
        dir: Option<impl Into<PathBuf>>,
        prefix: &str,
        extension: &str,
        every: Every,
    ) -> Result<Self> {
        if let Every::Seconds(dt) = every
            && !(dt.is_finite() && dt > 0.0)
        {
            return Err(ChronoError::invalid(
                "every",
                dt,
                "must be a positive number of seconds",
            ));
        }
        Ok(Self {
            dir: dir.map(Into::into),
            prefix: prefix.to_string(),
            extension: extension.to_string(),
            every,
            next_time: 0.0,
            frames: Vec::new(),
        })
    }

    /// A series that never writes.
    pub fn disabled() -> Self {
        Self {
            dir: None,
            prefix: String::new(),
            extension: String::new(),
            every: Every::Steps(1),
            next_time: 0.0,
            frames: Vec::new(),
        }
    }

    /// Whether frames are written at all.
    pub fn is_enabled(&self) -> bool {
        self.dir.is_some()
    }

    /// Whether a frame is due at `step` and simulated time `time` (s).
    pub fn is_due(&self, step: u64, time: f64) -> bool {
        self.dir.is_some()
            && match self.every {
                Every::Steps(n) => step.is_multiple_of(n.max(1)),
                // A tolerance of a picosecond: a time that lands on the multiple up to
                // round-off counts as on it.
                Every::Seconds(_) => time + 1e-12 >= self.next_time,
            }
    }

    /// Writes a frame when due: `write` gets the frame's path and writes the file.
    /// Returns whether a frame was written.
    pub fn record<E>(
        &mut self,
        step: u64,
        time: f64,
        write: impl FnOnce(&Path) -> std::result::Result<(), E>,
    ) -> std::result::Result<bool, E>
    where
        E: From<ChronoError>,
    {
        if !self.is_due(step, time) {
            return Ok(false);
        }
        let Some(dir) = &self.dir else {
            return Ok(false);
        };
        if self.frames.is_empty() {
            std::fs::create_dir_all(dir).map_err(|e| io_error(dir, e))?;
        }
        if let Every::Seconds(dt) = self.every {
            // The next multiple of dt after `time` (skips multiples a long step jumped over).
            self.next_time = ((time + 1e-12) / dt).floor() * dt + dt;
        }
        let name = format!(
            "{}_{:06}.{}",
            self.prefix,
            self.frames.len(),
            self.extension
        );
        write(&dir.join(&name))?;
        self.frames.push((time, name));
        Ok(true)
    }

    /// The frames written so far: `(time (s), file name)`.
    pub fn frames(&self) -> &[(f64, String)] {
        &self.frames
    }

    /// Writes `<prefix>.pvd` listing the frames (nothing when disabled). May be called
    /// more than once; each call rewrites the collection.
    pub fn finish(&self) -> Result<()> {
        let Some(dir) = &self.dir else { return Ok(()) };
        if self.frames.is_empty() {
            std::fs::create_dir_all(dir).map_err(|e| io_error(dir, e))?;
        }
        let frames: Vec<(f64, &str)> = self.frames.iter().map(|(t, n)| (*t, n.as_str())).collect();
        write_pvd(dir.join(format!("{}.pvd", self.prefix)), &frames)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn touch(p: &Path) -> Result<()> {
        std::fs::write(p, b"x").map_err(|e| io_error(p, e))
    }

    #[test]
    fn steps_schedule_names_and_collection() {
        let dir = std::env::temp_dir().join(format!("chrono_frames_steps_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let mut s = FrameSeries::new(Some(&dir), "grains", "vtp", Every::Steps(3)).unwrap();
        let mut written = 0;
        for step in 0..10u64 {
            if s.record(step, step as f64 * 0.1, touch).unwrap() {
                written += 1;
            }
        }
        assert_eq!(written, 4); // 0, 3, 6, 9
        assert_eq!(s.frames()[1].1, "grains_000001.vtp");
        assert!((s.frames()[3].0 - 0.9).abs() < 1e-12);
        s.finish().unwrap();
        let pvd = std::fs::read_to_string(dir.join("grains.pvd")).unwrap();
        assert_eq!(pvd.matches("<DataSet").count(), 4);
        assert!(dir.join("grains_000003.vtp").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn seconds_schedule_skips_jumped_multiples() {
        let dir = std::env::temp_dir().join(format!("chrono_frames_secs_{}", std::process::id()));
        let mut s = FrameSeries::new(Some(&dir), "f", "vtp", Every::Seconds(0.1)).unwrap();
        let times = [0.0, 0.05, 0.1 - 1e-14, 0.15, 0.35, 0.39, 0.4];
        let due: Vec<bool> = times
            .iter()
            .enumerate()
            .map(|(k, &t)| s.record(k as u64, t, touch).unwrap())
            .collect();
        assert_eq!(due, [true, false, true, false, true, false, true]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn disabled_writes_nothing_and_bad_interval_is_an_error() {
        let mut s = FrameSeries::disabled();
        assert!(!s.is_enabled());
        let wrote = s
            .record(0, 0.0, |_| -> Result<()> { panic!("must not be called") })
            .unwrap();
        assert!(!wrote);
        s.finish().unwrap();
        let e = FrameSeries::new(None::<PathBuf>, "f", "vtp", Every::Seconds(0.0)).unwrap_err();
        assert!(e.to_string().contains("every"), "{e}");
        assert!(FrameSeries::new(None::<PathBuf>, "f", "vtp", Every::Seconds(f64::NAN)).is_err());
    }
}
