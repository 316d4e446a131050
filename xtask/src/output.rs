//! What a case run returns: metrics, checks against references, a time series, what to
//! plot, the step count and an optional speed-against-error sweep.

use std::collections::BTreeMap;

/// How a [`Check`] compares its value with the reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CheckKind {
    /// `|value - reference| <= tolerance * |reference|`.
    Relative,
    /// `|value - reference| <= tolerance`.
    Absolute,
    /// `value <= tolerance` (the reference is 0): for quantities that should be small,
    /// such as a drift or a penetration.
    Below,
}

impl CheckKind {
    /// Short name used in reports: `rel`, `abs`, `max`.
    pub fn short(self) -> &'static str {
        match self {
            CheckKind::Relative => "rel",
            CheckKind::Absolute => "abs",
            CheckKind::Below => "max",
        }
    }
}

/// A metric compared with a reference value. `pass` is false when any number is not
/// finite.
#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    /// Name of the metric checked.
    pub metric: String,
    /// The measured value.
    pub value: f64,
    /// The reference (published or analytic) value; 0 for [`CheckKind::Below`].
    pub reference: f64,
    /// The tolerance; its meaning depends on `kind`.
    pub tolerance: f64,
    /// How value and reference are compared.
    pub kind: CheckKind,
    /// Whether the check passed.
    pub pass: bool,
}

impl Check {
    fn new(
        metric: impl Into<String>,
        value: f64,
        reference: f64,
        tolerance: f64,
        kind: CheckKind,
    ) -> Self {
        let mut check = Self {
            metric: metric.into(),
            value,
            reference,
            tolerance,
            kind,
            pass: false,
        };
        let finite = value.is_finite() && reference.is_finite() && tolerance.is_finite();
        check.pass = finite
            && match kind {
                CheckKind::Relative => (value - reference).abs() <= tolerance * reference.abs(),
                CheckKind::Absolute => (value - reference).abs() <= tolerance,
                CheckKind::Below => value <= tolerance,
            };
        check
    }

    /// Passes when `|value - reference| <= tolerance * |reference|`.
    pub fn relative(metric: impl Into<String>, value: f64, reference: f64, tolerance: f64) -> Self {
        Self::new(metric, value, reference, tolerance, CheckKind::Relative)
    }

    /// Passes when `|value - reference| <= tolerance`.
    pub fn absolute(metric: impl Into<String>, value: f64, reference: f64, tolerance: f64) -> Self {
        Self::new(metric, value, reference, tolerance, CheckKind::Absolute)
    }

    /// Passes when `value <= limit` (reference 0).
    pub fn below(metric: impl Into<String>, value: f64, limit: f64) -> Self {
        Self::new(metric, value, 0.0, limit, CheckKind::Below)
    }

    /// The error in the unit of the tolerance: relative error, absolute error, or the
    /// value itself for [`CheckKind::Below`].
    pub fn error(&self) -> f64 {
        let diff = (self.value - self.reference).abs();
        match self.kind {
            CheckKind::Relative if self.reference == 0.0 => {
                if diff == 0.0 {
                    0.0
                } else {
                    f64::INFINITY
                }
            }
            CheckKind::Relative => diff / self.reference.abs(),
            CheckKind::Absolute => diff,
            CheckKind::Below => self.value,
        }
    }
}

/// A table of numbers: a time series (first column is x, usually `t`), or a reference
/// curve. Keep it to at most a few thousand rows (record every n-th step).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    /// Column names; the first one is the x axis.
    pub columns: Vec<String>,
    /// Rows, each with one value per column.
    pub rows: Vec<Vec<f64>>,
}

impl Series {
    /// An empty series with the given column names.
    pub fn new<S: Into<String>>(columns: impl IntoIterator<Item = S>) -> Self {
        Self {
            columns: columns.into_iter().map(Into::into).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row.
    ///
    /// # Panics
    /// When the row length differs from the number of columns (a bug in the case).
    pub fn push(&mut self, row: &[f64]) {
        assert_eq!(
            row.len(),
            self.columns.len(),
            "series row has {} values for {} columns",
            row.len(),
            self.columns.len()
        );
        self.rows.push(row.to_vec());
    }

    /// The index of a column.
    pub fn column_index(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|c| c == name)
    }

    /// The values of a column.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let i = self.column_index(name)?;
        Some(self.rows.iter().map(|r| r[i]).collect())
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }
}

/// Which columns to draw in `plot.png`.
///
/// Empty `x` means the first column of the series; empty `y` means every other column.
/// `reference_y` columns are drawn dashed; they are looked up in
/// [`CaseOutput::reference_series`] when it is set, otherwise in the series itself.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlotSpec {
    /// The x column (default: the first column).
    pub x: String,
    /// The y columns of the series (default: all but x).
    pub y: Vec<String>,
    /// The reference columns, drawn dashed.
    pub reference_y: Vec<String>,
    /// Plot title (default: the case name).
    pub title: String,
    /// x axis label, with unit (default: the x column name).
    pub x_label: String,
    /// y axis label, with unit.
    pub y_label: String,
}

impl PlotSpec {
    /// A plot of the `y` columns against the first column, with a title and axis labels.
    pub fn new(title: &str, x_label: &str, y_label: &str, y: &[&str]) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            y: y.iter().map(|s| s.to_string()).collect(),
            ..Self::default()
        }
    }

    /// Adds reference columns (drawn dashed).
    pub fn with_reference(mut self, reference_y: &[&str]) -> Self {
        self.reference_y = reference_y.iter().map(|s| s.to_string()).collect();
        self
    }
}

/// One run of a resolution or time-step sweep, for the speed-against-error plot.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPoint {
    /// What was varied, e.g. `"h=1e-3"`.
    pub label: String,
    /// The error of that run against the reference.
    pub error: f64,
    /// The wall time of that run, in seconds.
    pub wall_s: f64,
}

/// The result of a case run. Build it with [`CaseOutput::new`], [`metric`](Self::metric)
/// and [`check`](Self::check), then set the series fields.
#[derive(Clone, Debug, Default)]
pub struct CaseOutput {
    /// Named scalar results.
    pub metrics: BTreeMap<String, f64>,
    /// Comparisons with references; the case passes when all pass.
    pub checks: Vec<Check>,
    /// The time series written to `series.csv` and plotted.
    pub series: Series,
    /// An optional reference curve (e.g. published data) drawn dashed.
    pub reference_series: Option<Series>,
    /// What to draw in `plot.png`.
    pub plot: PlotSpec,
    /// Number of time steps taken (for steps/s).
    pub steps: u64,
    /// Optional sweep for `speed_vs_error.png`.
    pub sweep: Vec<SweepPoint>,
}

impl CaseOutput {
    /// An empty output.
    pub fn new() -> Self {
        Self::default()
    }

    /// Records a metric (without a check).
    pub fn metric(&mut self, name: impl Into<String>, value: f64) -> &mut Self {
        self.metrics.insert(name.into(), value);
        self
    }

    /// Records a check, and its value as a metric of the same name.
    pub fn check(&mut self, check: Check) -> &mut Self {
        self.metrics.insert(check.metric.clone(), check.value);
        self.checks.push(check);
        self
    }

    /// Whether every check passed (true when there are none).
    pub fn all_pass(&self) -> bool {
        self.checks.iter().all(|c| c.pass)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_check() {
        assert!(Check::relative("a", 1.01, 1.0, 0.02).pass);
        assert!(!Check::relative("a", 1.03, 1.0, 0.02).pass);
        assert!(Check::relative("a", -1.01, -1.0, 0.02).pass);
        let c = Check::relative("a", 1.05, 1.0, 0.1);
        assert!((c.error() - 0.05).abs() < 1e-12);
        assert_eq!(Check::relative("a", 0.0, 0.0, 0.1).error(), 0.0);
        assert!(!Check::relative("a", 1e-9, 0.0, 0.1).pass);
    }

    #[test]
    fn absolute_and_below_checks() {
        assert!(Check::absolute("a", 1.0005, 1.0, 1e-3).pass);
        assert!(!Check::absolute("a", 1.002, 1.0, 1e-3).pass);
        assert!((Check::absolute("a", 0.5, 1.0, 1e-3).error() - 0.5).abs() < 1e-15);
        let b = Check::below("drift", 1e-4, 1e-3);
        assert!(b.pass && b.reference == 0.0 && b.error() == 1e-4);
        assert!(!Check::below("drift", 2e-3, 1e-3).pass);
        assert!(Check::below("drift", -5.0, 1e-3).pass);
    }

    #[test]
    fn non_finite_values_fail() {
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(!Check::relative("a", v, 1.0, 1e9).pass);
            assert!(!Check::absolute("a", v, 1.0, 1e9).pass);
            assert!(!Check::below("a", v, 1e9).pass);
            assert!(!Check::absolute("a", 1.0, v, 1e9).pass);
        }
        assert!(!Check::below("a", f64::NEG_INFINITY, 1.0).pass);
        assert!(!Check::absolute("a", 1.0, 1.0, f64::NAN).pass);
    }

    #[test]
    fn output_builder_and_series() {
        let mut out = CaseOutput::new();
        out.metric("m", 2.0).check(Check::below("c", 1.0, 2.0));
        assert_eq!(out.metrics.len(), 2);
        assert!(out.all_pass());
        out.check(Check::below("d", 3.0, 2.0));
        assert!(!out.all_pass());

        let mut s = Series::new(["t", "x"]);
        s.push(&[0.0, 1.0]);
        s.push(&[1.0, 2.0]);
        assert_eq!(s.column("x"), Some(vec![1.0, 2.0]));
        assert_eq!(s.column("y"), None);
        assert_eq!(s.len(), 2);
    }

    #[test]
    #[should_panic(expected = "series row has 1 values for 2 columns")]
    fn series_row_length_mismatch_panics() {
        Series::new(["t", "x"]).push(&[0.0]);
    }
}
