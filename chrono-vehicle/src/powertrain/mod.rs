//! The powertrain: engine ([`engine`]), torque converter ([`torque_converter`]) and
//! automatic transmission ([`transmission`]) as shafts of a
//! [`ShaftSystem`].
//!
//! Shafts and links it adds:
//!
//! ```text
//!  crankshaft --(converter torques)--> input shaft ==(gear row w_out = r w_in)==> output
//!  (engine torque T_e - T_p)            (turbine torque T_t)                      (driveshaft)
//! ```
//!
//! Each step, before the system steps, the owner calls
//! [`Powertrain::synchronize`]: it reads the shaft speeds, runs the shift schedule (a new
//! ratio is a new row value, since rows are rebuilt every step), evaluates the engine map
//! and the converter, and sets the shafts' applied torques. The output shaft is the
//! driveline's input ([`Powertrain::output_shaft`]).

pub mod engine;
pub mod torque_converter;
pub mod transmission;

use serde::{Deserialize, Serialize};

pub use engine::{Engine, EngineParams, RPM_TO_RAD_S};
pub use torque_converter::{ConverterTorques, TorqueConverter, TorqueConverterParams};
pub use transmission::{DriveMode, ShiftSpeed, Transmission, TransmissionParams};

use crate::driveline::{LinkId, ShaftId, ShaftSystem};
use crate::error::{Result, VehicleError};

/// Parameters of a [`Powertrain`] (JSON-ready; the default is the HMMWV).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PowertrainParams {
    /// The engine.
    pub engine: EngineParams,
    /// The torque converter.
    pub torque_converter: TorqueConverterParams,
    /// The transmission.
    pub transmission: TransmissionParams,
}

impl PowertrainParams {
    /// Check every field; errors name `powertrain.<part>.<field>`.
    pub fn validate(&self) -> Result<()> {
        self.engine.validate("powertrain.engine")?;
        self.torque_converter
            .validate("powertrain.torque_converter")?;
        self.transmission.validate("powertrain.transmission")
    }

    /// Read from JSON and validate.
    pub fn from_json(text: &str) -> Result<Self> {
        let p: Self = serde_json::from_str(text).map_err(|e| VehicleError::Data {
            path: "<powertrain>".into(),
            message: e.to_string(),
        })?;
        p.validate()?;
        Ok(p)
    }
}

/// Engine, torque converter and automatic gearbox on three shafts (see the
/// [module docs](self)).
#[derive(Debug, Clone)]
pub struct Powertrain {
    engine: Engine,
    converter: TorqueConverter,
    transmission: Transmission,
    crankshaft: ShaftId,
    input: ShaftId,
    output: ShaftId,
    gearbox: LinkId,
    throttle: f64,
    engine_speed: f64,
    engine_torque: f64,
    conv: ConverterTorques,
}

impl Powertrain {
    /// Build the powertrain's shafts (crankshaft, transmission input, output) and the
    /// gearbox row in `shafts`, in first gear. Errors name `powertrain.<part>.<field>`.
    pub fn new(params: &PowertrainParams, shafts: &mut ShaftSystem) -> Result<Self> {
        params.validate()?;
        let engine = Engine::new(&params.engine)?;
        let converter = TorqueConverter::new(&params.torque_converter)?;
        let transmission = Transmission::new(&params.transmission)?;
        let tp = &params.transmission;
        let crankshaft = shafts.add_shaft("crankshaft", params.engine.crankshaft_inertia)?;
        let input = shafts.add_shaft("transmission input", tp.input_shaft_inertia)?;
        let output = shafts.add_shaft("driveshaft", tp.output_shaft_inertia)?;
        let ratio = transmission.ratio().expect("starts in forward");
        let gearbox = shafts.add_gear(output, input, ratio)?;
        Ok(Self {
            engine,
            converter,
            transmission,
            crankshaft,
            input,
            output,
            gearbox,
            throttle: 0.0,
            engine_speed: 0.0,
            engine_torque: 0.0,
            conv: ConverterTorques::default(),
        })
    }

    /// Once per step before the system steps, at `time` (s) with `throttle` (clamped to
    /// `[0, 1]`; NaN is an error): read the crankshaft and input shaft speeds, run the
    /// shift schedule and set the gearbox row, and set the applied torques
    /// `T_e - T_p` on the crankshaft and `T_t` on the input shaft.
    pub fn synchronize(
        &mut self,
        time: f64,
        throttle: f64,
        shafts: &mut ShaftSystem,
    ) -> Result<()> {
        if throttle.is_nan() {
            return Err(VehicleError::invalid(
                "throttle",
                throttle,
                "must not be NaN",
            ));
        }
        self.throttle = throttle.clamp(0.0, 1.0);
        let we = shafts.speed(self.crankshaft);
        let wt = shafts.speed(self.input);
        self.transmission.update(time, we, wt);
        match self.transmission.ratio() {
            Some(r) => {
                shafts.set_gear_ratio(self.gearbox, r)?;
                shafts.set_link_enabled(self.gearbox, true)?;
            }
            None => shafts.set_link_enabled(self.gearbox, false)?,
        }
        self.engine_speed = we;
        self.engine_torque = self.engine.torque(self.throttle, we);
        self.conv = self.converter.torques(we, wt);
        shafts.set_torque(self.crankshaft, self.engine_torque - self.conv.pump_torque)?;
        shafts.set_torque(self.input, self.conv.turbine_torque)?;
        Ok(())
    }

    /// Select forward, neutral or reverse (takes effect at the next
    /// [`synchronize`](Self::synchronize)).
    pub fn set_drive_mode(&mut self, mode: DriveMode) {
        self.transmission.set_mode(mode);
    }

    /// The crankshaft.
    pub fn crankshaft(&self) -> ShaftId {
        self.crankshaft
    }
    /// The transmission input (turbine) shaft.
    pub fn input_shaft(&self) -> ShaftId {
        self.input
    }
    /// The output shaft (driveshaft): the driveline's input.
    pub fn output_shaft(&self) -> ShaftId {
        self.output
    }
    /// The gearbox's gear row.
    pub fn gearbox(&self) -> LinkId {
        self.gearbox
    }
    /// The transmission (gear state).
    pub fn transmission(&self) -> &Transmission {
        &self.transmission
    }
    /// Mutable transmission (manual gear selection).
    pub fn transmission_mut(&mut self) -> &mut Transmission {
        &mut self.transmission
    }
    /// The engine model.
    pub fn engine(&self) -> &Engine {
        &self.engine
    }
    /// The converter model.
    pub fn converter(&self) -> &TorqueConverter {
        &self.converter
    }
    /// Throttle used in the last synchronize, 0..1.
    pub fn throttle(&self) -> f64 {
        self.throttle
    }
    /// Engine (crankshaft) speed at the last synchronize, rad/s.
    pub fn engine_speed(&self) -> f64 {
        self.engine_speed
    }
    /// Engine speed at the last synchronize, rpm.
    pub fn engine_speed_rpm(&self) -> f64 {
        self.engine_speed / RPM_TO_RAD_S
    }
    /// Engine torque `throttle * map + losses` at the last synchronize, N m.
    pub fn engine_torque(&self) -> f64 {
        self.engine_torque
    }
    /// Converter state (speed ratio, pump and turbine torques) at the last synchronize.
    pub fn converter_state(&self) -> ConverterTorques {
        self.conv
    }
    /// Converter slip `1 - speed ratio`.
    pub fn converter_slip(&self) -> f64 {
        1.0 - self.conv.speed_ratio
    }
    /// Current gear: `1..=n` forward, 0 neutral, -1 reverse.
    pub fn current_gear(&self) -> i32 {
        self.transmission.gear()
    }
    /// Torque the gearbox delivered to the output shaft in the last step, N m (the gear
    /// row's reaction; 0 in neutral).
    pub fn output_torque(&self, shafts: &ShaftSystem) -> f64 {
        shafts.reaction(self.gearbox)
    }
}
