//! Traction control: the driver cuts the throttle when the driven wheels slip.

use crate::error::{Result, check_non_negative};

/// Throttle cut by wheel slip. With the slip `s = (w R - v) / max(|w R|, 0.5 m/s)` (`w R`
/// the wheels' mean surface speed, `v` the forward speed; the floor keeps a standing start
/// finite), the throttle is scaled by `1 - 5 (s - s_max)`, clamped to `[0, 1]`: full
/// throttle up to `s_max`, none from `s_max + 0.2`. On loose ground a locked driveline at
/// full throttle spins its wheels at ~95 % slip and digs in; this keeps them near `s_max`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TractionControl {
    /// The largest slip allowed, `s_max` (0 = off).
    pub max_slip: f64,
}

impl TractionControl {
    /// Traction control allowing the slip `max_slip` (finite, `>= 0`; 0 turns it off).
    pub fn new(max_slip: f64) -> Result<Self> {
        check_non_negative("traction_control.max_slip", max_slip)?;
        Ok(Self { max_slip })
    }

    /// The throttle after the cut, from the driver's `throttle`, the wheels' mean surface
    /// speed `wheel_surface_speed` and the forward speed `speed` (m/s).
    pub fn limit(&self, throttle: f64, wheel_surface_speed: f64, speed: f64) -> f64 {
        if self.max_slip <= 0.0 {
            return throttle;
        }
        let wr = wheel_surface_speed;
        let slip = (wr - speed) / wr.abs().max(0.5);
        throttle * (1.0 - 5.0 * (slip - self.max_slip)).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cuts_the_throttle_above_the_slip_limit() {
        let tc = TractionControl::new(0.4).unwrap();
        assert_eq!(tc.limit(1.0, 2.0, 2.0), 1.0);
        // Slip 0.5: 1 - 5 (0.1) = 0.5.
        assert!((tc.limit(1.0, 4.0, 2.0) - 0.5).abs() < 1e-12);
        assert_eq!(tc.limit(1.0, 10.0, 0.0), 0.0);
        assert!(TractionControl::new(-1.0).is_err());
    }
}
