//! Piecewise-linear curves `y(x)` given as tables: spring and damper characteristics,
//! engine torque maps, torque-converter curves, shift schedules.
//!
//! Between two table points the curve is the straight line through them; outside the table
//! it either keeps the end value ([`Extrapolation::Constant`], e.g. an engine map) or
//! continues the end segment's slope ([`Extrapolation::Linear`], e.g. a spring table whose
//! stiffness keeps growing past its last point).

use serde::{Deserialize, Serialize};

use crate::error::{ChronoError, Result};

/// What a [`Curve`] does outside its table.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Extrapolation {
    /// Keep the first/last value.
    #[default]
    Constant,
    /// Continue the first/last segment's slope.
    Linear,
}

/// A piecewise-linear function given by points `(x_i, y_i)` with strictly increasing `x`.
///
/// In serde form it is `{"points": [[x0, y0], [x1, y1], ...], "extrapolation": "linear"}`
/// (`extrapolation` defaults to `"constant"`); [`Curve::validate`] checks a deserialized one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Curve {
    points: Vec<[f64; 2]>,
    #[serde(default)]
    extrapolation: Extrapolation,
}

impl Curve {
    /// A curve through `points` (at least one; `x` finite and strictly increasing, `y`
    /// finite). One point is a constant. The error names `field` and the offending point.
    pub fn new(field: &str, points: Vec<[f64; 2]>, extrapolation: Extrapolation) -> Result<Self> {
        let c = Self {
            points,
            extrapolation,
        };
        c.validate(field)?;
        Ok(c)
    }

    /// The constant curve `y = value`.
    pub fn constant(value: f64) -> Self {
        Self {
            points: vec![[0.0, value]],
            extrapolation: Extrapolation::Constant,
        }
    }

    /// The line `y = slope x` (a linear spring or damper), extrapolated linearly.
    pub fn linear(slope: f64) -> Self {
        Self {
            points: vec![[0.0, 0.0], [1.0, slope]],
            extrapolation: Extrapolation::Linear,
        }
    }

    /// Check the table (after deserializing): non-empty, finite, `x` strictly increasing.
    pub fn validate(&self, field: &str) -> Result<()> {
        if self.points.is_empty() {
            return Err(ChronoError::invalid(
                format!("{field}.points"),
                "[]",
                "a curve needs at least one point",
            ));
        }
        for (i, p) in self.points.iter().enumerate() {
            if !(p[0].is_finite() && p[1].is_finite()) {
                return Err(ChronoError::invalid(
                    format!("{field}.points[{i}]"),
                    format!("[{}, {}]", p[0], p[1]),
                    "points must be finite",
                ));
            }
            if i > 0 && p[0] <= self.points[i - 1][0] {
                return Err(ChronoError::invalid(
                    format!("{field}.points[{i}]"),
                    format!("[{}, {}]", p[0], p[1]),
                    format!(
                        "x must increase strictly (previous x = {})",
                        self.points[i - 1][0]
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The table points.
    pub fn points(&self) -> &[[f64; 2]] {
        &self.points
    }

    /// The extrapolation rule.
    pub fn extrapolation(&self) -> Extrapolation {
        self.extrapolation
    }

    /// Index `i` of the segment `[x_i, x_{i+1}]` that holds `x` (clamped to the end segments).
    fn segment(&self, x: f64) -> usize {
        let n = self.points.len();
        // First point with x_i > x, minus one: the segment's left end.
        let upper = self.points.partition_point(|p| p[0] <= x);
        upper.saturating_sub(1).min(n - 2)
    }

    /// `y(x)`.
    pub fn eval(&self, x: f64) -> f64 {
        let pts = &self.points;
        if pts.len() == 1 {
            return pts[0][1];
        }
        let (first, last) = (pts[0], pts[pts.len() - 1]);
        if self.extrapolation == Extrapolation::Constant {
            if x <= first[0] {
                return first[1];
            }
            if x >= last[0] {
                return last[1];
            }
        }
        let i = self.segment(x);
        let (a, b) = (pts[i], pts[i + 1]);
        a[1] + (b[1] - a[1]) * (x - a[0]) / (b[0] - a[0])
    }

    /// `dy/dx` at `x` (the slope of the segment holding `x`; 0 outside a constant-extrapolated
    /// table; at a table point, the slope of the segment to its right).
    pub fn slope(&self, x: f64) -> f64 {
        let pts = &self.points;
        if pts.len() == 1 {
            return 0.0;
        }
        if self.extrapolation == Extrapolation::Constant
            && (x < pts[0][0] || x >= pts[pts.len() - 1][0])
        {
            return 0.0;
        }
        let i = self.segment(x);
        let (a, b) = (pts[i], pts[i + 1]);
        (b[1] - a[1]) / (b[0] - a[0])
    }

    /// The same curve with every `x` and `y` scaled (unit conversions: inches to metres,
    /// rpm to rad/s, lbf to N).
    pub fn scaled(&self, sx: f64, sy: f64) -> Result<Self> {
        let mut points: Vec<[f64; 2]> =
            self.points.iter().map(|p| [p[0] * sx, p[1] * sy]).collect();
        if sx < 0.0 {
            points.reverse();
        }
        Self::new("curve.scaled", points, self.extrapolation)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(ext: Extrapolation) -> Curve {
        Curve::new("t", vec![[0.0, 0.0], [1.0, 2.0], [3.0, 3.0]], ext).unwrap()
    }

    #[test]
    fn interpolates_between_points() {
        let c = table(Extrapolation::Constant);
        assert_eq!(c.eval(0.5), 1.0);
        assert_eq!(c.eval(1.0), 2.0);
        assert_eq!(c.eval(2.0), 2.5);
        assert_eq!(c.slope(0.5), 2.0);
        assert_eq!(c.slope(2.0), 0.5);
    }

    #[test]
    fn extrapolates_by_the_chosen_rule() {
        let c = table(Extrapolation::Constant);
        assert_eq!(c.eval(-1.0), 0.0);
        assert_eq!(c.eval(10.0), 3.0);
        assert_eq!(c.slope(10.0), 0.0);
        let l = table(Extrapolation::Linear);
        assert_eq!(l.eval(-1.0), -2.0);
        assert_eq!(l.eval(5.0), 4.0);
        assert_eq!(l.slope(-1.0), 2.0);
    }

    #[test]
    fn constant_and_linear_helpers() {
        assert_eq!(Curve::constant(4.0).eval(-3.0), 4.0);
        assert_eq!(Curve::linear(3.0).eval(-2.0), -6.0);
        assert_eq!(Curve::linear(3.0).slope(7.0), 3.0);
    }

    #[test]
    fn bad_tables_name_the_point() {
        let e = Curve::new(
            "spring",
            vec![[0.0, 1.0], [0.0, 2.0]],
            Extrapolation::Linear,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("spring.points[1]"), "{e}");
        let e = Curve::new("map", vec![[0.0, f64::NAN]], Extrapolation::Linear)
            .unwrap_err()
            .to_string();
        assert!(e.contains("map.points[0]"), "{e}");
        assert!(Curve::new("m", vec![], Extrapolation::Linear).is_err());
    }

    #[test]
    fn serde_round_trip_and_scaling() {
        let c: Curve =
            serde_json::from_str(r#"{"points": [[0, 0], [2, 4]], "extrapolation": "linear"}"#)
                .unwrap();
        c.validate("c").unwrap();
        assert_eq!(c.eval(3.0), 6.0);
        let s = c.scaled(0.5, 10.0).unwrap();
        assert_eq!(s.eval(1.0), 40.0);
        let r = c.scaled(-1.0, 1.0).unwrap();
        assert_eq!(r.eval(-1.0), 2.0);
    }
}
