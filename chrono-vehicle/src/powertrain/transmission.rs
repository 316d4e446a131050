//! The automatic transmission: gear ratios, reverse, and a shift schedule with latency.
//!
//! A gear ratio is a speed ratio `r = w_out / w_in` (output shaft over transmission input
//! shaft), so the gearbox multiplies torque by `1/r` (HMMWV first gear 0.2: five times).
//! The gearbox is a gear row `w_out - r w_in = 0` of the [`ShaftSystem`](crate::driveline::ShaftSystem);
//! shifting changes `r` of that row for the next step (neutral disables the row).
//!
//! Automatic shifting in [`DriveMode::Forward`], checked once per step in
//! [`Transmission::update`]: if at least `shift_latency` seconds have passed since the last
//! shift, the shift speed `w` (the engine's or the transmission input shaft's, see
//! [`ShiftSpeed`]) above `upshift_rpm` selects the next gear, below `downshift_rpm` the
//! previous one (one gear per shift).
//!
//! Reference: Chrono's `ChAutomaticTransmissionShafts` / `HMMWV_AutomaticTransmissionShafts`
//! as summarized in our notes (section 7: ratios -0.1; 0.2, 0.4, 0.8; up 2500 rpm, down
//! 1200 rpm, latency 1 s).

use serde::{Deserialize, Serialize};

use super::engine::RPM_TO_RAD_S;
use crate::error::{Result, VehicleError, check_non_negative, check_positive};

/// Which speed the shift schedule compares with its shift speeds.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ShiftSpeed {
    /// The crankshaft (engine) speed.
    #[default]
    Engine,
    /// The transmission input (turbine) shaft speed.
    InputShaft,
}

/// Forward, neutral or reverse.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DriveMode {
    /// Forward gears, shifted automatically.
    #[default]
    Forward,
    /// No connection between input and output.
    Neutral,
    /// The reverse gear.
    Reverse,
}

/// Parameters of a [`Transmission`]; the default is the HMMWV's.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransmissionParams {
    /// Forward speed ratios `w_out / w_in`, first gear first (finite, > 0, increasing).
    pub forward_ratios: Vec<f64>,
    /// Reverse speed ratio (finite, < 0).
    pub reverse_ratio: f64,
    /// Upshift above this speed, rpm.
    pub upshift_rpm: f64,
    /// Downshift below this speed, rpm (> 0, < `upshift_rpm`).
    pub downshift_rpm: f64,
    /// Minimum time between shifts, s (>= 0).
    pub shift_latency: f64,
    /// Which speed the schedule watches (default: the engine's).
    #[serde(default)]
    pub shift_speed: ShiftSpeed,
    /// Polar inertia of the transmission input (turbine) shaft, kg m^2 (> 0).
    pub input_shaft_inertia: f64,
    /// Polar inertia of the output shaft (the driveshaft), kg m^2 (> 0).
    pub output_shaft_inertia: f64,
}

impl Default for TransmissionParams {
    /// The HMMWV's (Project Chrono's `HMMWV_AutomaticTransmissionShafts`). The shaft inertias are not published there: 0.3 (input)
    /// and 0.5 (output, the notes' driveline shaft inertia) are our choice.
    fn default() -> Self {
        Self {
            forward_ratios: vec![0.2, 0.4, 0.8],
            reverse_ratio: -0.1,
            upshift_rpm: 2500.0,
            downshift_rpm: 1200.0,
            shift_latency: 1.0,
            shift_speed: ShiftSpeed::Engine,
            input_shaft_inertia: 0.3,
            output_shaft_inertia: 0.5,
        }
    }
}

impl TransmissionParams {
    /// Check every field; errors name `{prefix}.field`.
    pub fn validate(&self, prefix: &str) -> Result<()> {
        let f = |name: &str| format!("{prefix}.{name}");
        if self.forward_ratios.is_empty() {
            return Err(VehicleError::invalid(
                f("forward_ratios"),
                "[]",
                "needs at least one gear",
            ));
        }
        for (i, &r) in self.forward_ratios.iter().enumerate() {
            check_positive(&f(&format!("forward_ratios[{i}]")), r)?;
            if i > 0 && r <= self.forward_ratios[i - 1] {
                return Err(VehicleError::invalid(
                    f(&format!("forward_ratios[{i}]")),
                    r,
                    format!(
                        "must be > the previous gear's {}",
                        self.forward_ratios[i - 1]
                    ),
                ));
            }
        }
        if !(self.reverse_ratio.is_finite() && self.reverse_ratio < 0.0) {
            return Err(VehicleError::invalid(
                f("reverse_ratio"),
                self.reverse_ratio,
                "must be finite and < 0",
            ));
        }
        check_positive(&f("upshift_rpm"), self.upshift_rpm)?;
        check_positive(&f("downshift_rpm"), self.downshift_rpm)?;
        if self.downshift_rpm >= self.upshift_rpm {
            return Err(VehicleError::invalid(
                f("downshift_rpm"),
                self.downshift_rpm,
                format!("must be < upshift_rpm = {}", self.upshift_rpm),
            ));
        }
        check_non_negative(&f("shift_latency"), self.shift_latency)?;
        check_positive(&f("input_shaft_inertia"), self.input_shaft_inertia)?;
        check_positive(&f("output_shaft_inertia"), self.output_shaft_inertia)?;
        Ok(())
    }
}

/// The gear state of an automatic transmission (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct Transmission {
    params: TransmissionParams,
    mode: DriveMode,
    gear: usize,
    last_shift: f64,
}

impl Transmission {
    /// A transmission in first gear, forward (validated; errors name `transmission.<field>`).
    pub fn new(params: &TransmissionParams) -> Result<Self> {
        params.validate("transmission")?;
        Ok(Self {
            params: params.clone(),
            mode: DriveMode::Forward,
            gear: 1,
            last_shift: f64::NEG_INFINITY,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &TransmissionParams {
        &self.params
    }

    /// Forward, neutral or reverse.
    pub fn mode(&self) -> DriveMode {
        self.mode
    }

    /// Select forward, neutral or reverse (forward resumes in the current forward gear).
    pub fn set_mode(&mut self, mode: DriveMode) {
        self.mode = mode;
    }

    /// The current forward gear, 1-based (kept while in neutral or reverse).
    pub fn forward_gear(&self) -> usize {
        self.gear
    }

    /// The current gear as a signed number: `1..=n` forward, 0 neutral, -1 reverse.
    pub fn gear(&self) -> i32 {
        match self.mode {
            DriveMode::Forward => self.gear as i32,
            DriveMode::Neutral => 0,
            DriveMode::Reverse => -1,
        }
    }

    /// Select a forward gear (1-based) now, e.g. to start in another gear.
    pub fn set_forward_gear(&mut self, gear: usize) -> Result<()> {
        let n = self.params.forward_ratios.len();
        if gear == 0 || gear > n {
            return Err(VehicleError::invalid(
                "transmission gear",
                gear,
                format!("must be in 1..={n}"),
            ));
        }
        self.gear = gear;
        Ok(())
    }

    /// The speed ratio `w_out / w_in` of the engaged gear, `None` in neutral.
    pub fn ratio(&self) -> Option<f64> {
        match self.mode {
            DriveMode::Forward => Some(self.params.forward_ratios[self.gear - 1]),
            DriveMode::Neutral => None,
            DriveMode::Reverse => Some(self.params.reverse_ratio),
        }
    }

    /// The shift schedule at `time` (s) with engine speed `engine` and input shaft speed
    /// `input` (rad/s): returns true if it shifted.
    pub fn update(&mut self, time: f64, engine: f64, input: f64) -> bool {
        if self.mode != DriveMode::Forward || time - self.last_shift < self.params.shift_latency {
            return false;
        }
        let w = match self.params.shift_speed {
            ShiftSpeed::Engine => engine,
            ShiftSpeed::InputShaft => input,
        };
        let n = self.params.forward_ratios.len();
        if w > self.params.upshift_rpm * RPM_TO_RAD_S && self.gear < n {
            self.gear += 1;
        } else if w < self.params.downshift_rpm * RPM_TO_RAD_S && self.gear > 1 {
            self.gear -= 1;
        } else {
            return false;
        }
        self.last_shift = time;
        true
    }
}
