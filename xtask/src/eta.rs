//! The estimate of the time left in a run of several cases.
//!
//! Each case has an expected wall time: the time it took in the last run of the same
//! mode (`timings.json` in the output directory, written after every run), else its
//! share of the time budget ([`crate::budget`]), else the mean of the cases already
//! finished. The expectation of the cases still to come is scaled by how the finished
//! cases compared with theirs (a slower or busier machine than the budget's), and the
//! running case's remainder is taken from its own progress once it has made some.

use std::collections::BTreeMap;
use std::path::Path;

use serde_json::Value;

use crate::case::Mode;

/// Wall times of the last run per mode and case: `{"default": {"rigid-incline": 0.5}}`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Timings(BTreeMap<String, BTreeMap<String, f64>>);

impl Timings {
    /// The file name in the output directory.
    pub const FILE: &'static str = "timings.json";

    /// Reads `dir/timings.json`; empty when missing or unreadable (the estimate then
    /// falls back to the budget).
    pub fn load(dir: &Path) -> Self {
        let Ok(text) = std::fs::read_to_string(dir.join(Self::FILE)) else {
            return Self::default();
        };
        let Ok(Value::Object(modes)) = serde_json::from_str::<Value>(&text) else {
            return Self::default();
        };
        let mut t = Self::default();
        for (mode, cases) in modes {
            let Value::Object(cases) = cases else {
                continue;
            };
            for (name, v) in cases {
                if let Some(s) = v.as_f64().filter(|s| s.is_finite() && *s >= 0.0) {
                    t.0.entry(mode.clone()).or_default().insert(name, s);
                }
            }
        }
        t
    }

    /// The recorded wall time of `case` in `mode` (s).
    pub fn get(&self, mode: Mode, case: &str) -> Option<f64> {
        self.0.get(mode.as_str())?.get(case).copied()
    }

    /// Records a wall time (s).
    pub fn set(&mut self, mode: Mode, case: &str, wall_s: f64) {
        if wall_s.is_finite() && wall_s >= 0.0 {
            self.0
                .entry(mode.as_str().to_string())
                .or_default()
                .insert(case.to_string(), wall_s);
        }
    }

    /// Writes `dir/timings.json`.
    pub fn save(&self, dir: &Path) -> anyhow::Result<()> {
        let v: serde_json::Map<String, Value> = self
            .0
            .iter()
            .map(|(m, cases)| {
                let c: serde_json::Map<String, Value> = cases
                    .iter()
                    .map(|(k, v)| (k.clone(), crate::report::json_num(*v)))
                    .collect();
                (m.clone(), Value::Object(c))
            })
            .collect();
        std::fs::write(
            dir.join(Self::FILE),
            serde_json::to_string_pretty(&v)? + "\n",
        )?;
        Ok(())
    }
}

/// The running estimate for a sequence of cases.
#[derive(Clone, Debug)]
pub struct Eta {
    /// Expected wall time per case (s); `None` when nothing is known.
    expected: Vec<Option<f64>>,
    /// Actual wall time of the finished cases (s).
    actual: Vec<Option<f64>>,
}

impl Eta {
    /// An estimate over cases with the given expectations (s).
    pub fn new(expected: Vec<Option<f64>>) -> Self {
        let n = expected.len();
        Self {
            expected,
            actual: vec![None; n],
        }
    }

    /// Case `i` finished after `wall_s` seconds.
    pub fn finish(&mut self, i: usize, wall_s: f64) {
        if let Some(a) = self.actual.get_mut(i) {
            *a = Some(wall_s);
        }
    }

    /// How the finished cases compared with their expectation (actual / expected,
    /// clamped to [0.2, 5] so one odd case does not swing the estimate), 1 before any.
    fn speed_factor(&self) -> f64 {
        let (mut a, mut e) = (0.0, 0.0);
        for (act, exp) in self.actual.iter().zip(&self.expected) {
            if let (Some(act), Some(exp)) = (act, exp) {
                a += act;
                e += exp;
            }
        }
        if e > 0.0 {
            (a / e).clamp(0.2, 5.0)
        } else {
            1.0
        }
    }

    /// The expectation of case `i` (s), scaled by the speed factor; the mean of the
    /// finished cases when nothing is known of it.
    fn expect(&self, i: usize, factor: f64) -> f64 {
        match self.expected[i] {
            Some(e) => e * factor,
            None => {
                let done: Vec<f64> = self.actual.iter().flatten().copied().collect();
                if done.is_empty() {
                    0.0
                } else {
                    done.iter().sum::<f64>() / done.len() as f64
                }
            }
        }
    }

    /// Seconds left while case `current` runs, `elapsed` seconds in and `fraction`
    /// (0 to 1) done by its own progress report.
    pub fn remaining(&self, current: usize, elapsed: f64, fraction: f64) -> f64 {
        let factor = self.speed_factor();
        let expected_now = self.expect(current, factor);
        // Trust the case's own progress once it has made some (it knows its step count).
        let now_left = if fraction >= 0.05 && elapsed > 1.0 {
            elapsed / fraction.min(1.0) - elapsed
        } else {
            (expected_now - elapsed).max(0.0)
        };
        let later: f64 = (current + 1..self.expected.len())
            .map(|i| self.expect(i, factor))
            .sum();
        (now_left + later).max(0.0)
    }
}

/// A duration for humans: `45 s`, `3 min 20 s`, `1 h 05 min`.
pub fn fmt_duration(s: f64) -> String {
    if !s.is_finite() || s < 0.0 {
        return "?".into();
    }
    let s = s.round() as u64;
    match s {
        0..60 => format!("{s} s"),
        60..3600 => format!("{} min {:02} s", s / 60, s % 60),
        _ => format!("{} h {:02} min", s / 3600, (s % 3600) / 60),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn estimate_uses_expectations_scaled_by_the_finished_cases() {
        let mut eta = Eta::new(vec![Some(10.0), Some(20.0), Some(30.0)]);
        // Nothing done: the whole expectation.
        assert!((eta.remaining(0, 0.0, 0.0) - 60.0).abs() < 1e-12);
        // The first case took twice its expectation: the rest is expected twice as long.
        eta.finish(0, 20.0);
        assert!((eta.remaining(1, 0.0, 0.0) - 100.0).abs() < 1e-12);
        // Halfway through case 1 after 30 s by its own progress: 30 s more, then 60 s.
        assert!((eta.remaining(1, 30.0, 0.5) - 90.0).abs() < 1e-12);
    }

    #[test]
    fn unknown_cases_take_the_mean_and_factor_is_clamped() {
        let mut eta = Eta::new(vec![Some(1.0), None, None]);
        eta.finish(0, 100.0); // factor clamped to 5
        assert!((eta.remaining(1, 0.0, 0.0) - 200.0).abs() < 1e-12);
        let eta = Eta::new(vec![None, None]);
        assert_eq!(eta.remaining(0, 0.0, 0.0), 0.0);
    }

    #[test]
    fn timings_round_trip_and_tolerate_garbage() {
        let dir = std::env::temp_dir().join(format!("xtask_timings_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut t = Timings::default();
        t.set(Mode::Quick, "a", 1.5);
        t.set(Mode::Default, "b", f64::NAN); // ignored
        t.save(&dir).unwrap();
        let back = Timings::load(&dir);
        assert_eq!(back.get(Mode::Quick, "a"), Some(1.5));
        assert_eq!(back.get(Mode::Default, "b"), None);
        std::fs::write(dir.join(Timings::FILE), "not json").unwrap();
        assert_eq!(Timings::load(&dir), Timings::default());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn durations() {
        assert_eq!(fmt_duration(45.2), "45 s");
        assert_eq!(fmt_duration(200.0), "3 min 20 s");
        assert_eq!(fmt_duration(3900.0), "1 h 05 min");
        assert_eq!(fmt_duration(f64::NAN), "?");
    }
}
