//! CSV time series.
//!
//! One header line with the column names, then one line per row of `f64`, comma
//! separated, at full precision (the shortest text that parses back to the same `f64`;
//! `NaN`, `inf`, `-inf` for non-finite values). Column names that contain a comma, a quote
//! or a line break are quoted (RFC 4180).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use super::{fmt_f64, io_error};
use crate::error::{ChronoError, Result};

/// Writes a CSV time series row by row. Call [`finish`](Self::finish) to flush and see
/// write errors; dropping the writer flushes too but ignores errors.
#[derive(Debug)]
pub struct CsvWriter {
    path: PathBuf,
    writer: BufWriter<File>,
    ncols: usize,
    line: String,
}

impl CsvWriter {
    /// Create (or truncate) the file at `path` and write the header.
    pub fn create(path: impl AsRef<Path>, columns: &[&str]) -> Result<Self> {
        let path = path.as_ref().to_path_buf();
        if columns.is_empty() {
            return Err(ChronoError::invalid(
                "columns",
                "[]",
                "a CSV file needs at least one column",
            ));
        }
        let file = File::create(&path).map_err(|e| io_error(&path, e))?;
        let mut w = Self {
            writer: BufWriter::new(file),
            ncols: columns.len(),
            line: String::new(),
            path,
        };
        for (k, c) in columns.iter().enumerate() {
            if k > 0 {
                w.line.push(',');
            }
            if c.contains([',', '"', '\n', '\r']) {
                w.line.push('"');
                w.line.push_str(&c.replace('"', "\"\""));
                w.line.push('"');
            } else {
                w.line.push_str(c);
            }
        }
        w.write_line()?;
        Ok(w)
    }

    /// The number of columns.
    pub fn columns(&self) -> usize {
        self.ncols
    }

    /// Append one row; its length must equal the number of columns.
    pub fn write_row(&mut self, row: &[f64]) -> Result<()> {
        if row.len() != self.ncols {
            return Err(ChronoError::invalid(
                "row.len()",
                row.len(),
                format!(
                    "must equal the number of columns ({}) of {}",
                    self.ncols,
                    self.path.display()
                ),
            ));
        }
        for (k, x) in row.iter().enumerate() {
            if k > 0 {
                self.line.push(',');
            }
            fmt_f64(*x, &mut self.line);
        }
        self.write_line()
    }

    /// Flush buffered rows to the file (e.g. periodically in a long run).
    pub fn flush(&mut self) -> Result<()> {
        self.writer.flush().map_err(|e| io_error(&self.path, e))
    }

    /// Flush and close the file, reporting any error.
    pub fn finish(mut self) -> Result<()> {
        self.flush()
    }

    fn write_line(&mut self) -> Result<()> {
        self.line.push('\n');
        let res = self
            .writer
            .write_all(self.line.as_bytes())
            .map_err(|e| io_error(&self.path, e));
        self.line.clear();
        res
    }
}

/// Write a whole table at once: a header of `columns` and the `rows`.
pub fn write_csv<R: AsRef<[f64]>>(
    path: impl AsRef<Path>,
    columns: &[&str],
    rows: &[R],
) -> Result<()> {
    let mut w = CsvWriter::create(path, columns)?;
    for r in rows {
        w.write_row(r.as_ref())?;
    }
    w.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("chrono-core-io-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn writes_header_and_full_precision_rows() {
        let path = temp("series.csv");
        let mut w = CsvWriter::create(&path, &["t", "x,1", "v"]).unwrap();
        w.write_row(&[0.0, 1.0 / 3.0, -2.5e-12]).unwrap();
        w.write_row(&[0.001, 1e20, f64::NAN]).unwrap();
        let e = w.write_row(&[1.0]).unwrap_err().to_string();
        assert!(
            e.contains("row.len()") && e.contains('1') && e.contains('3'),
            "{e}"
        );
        w.finish().unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "t,\"x,1\",v");
        assert_eq!(lines.len(), 3);
        let row: Vec<f64> = lines[1].split(',').map(|s| s.parse().unwrap()).collect();
        assert_eq!(row, vec![0.0, 1.0 / 3.0, -2.5e-12]);
        let row: Vec<f64> = lines[2].split(',').map(|s| s.parse().unwrap()).collect();
        assert!(row[0] == 0.001 && row[1] == 1e20 && row[2].is_nan());
    }

    #[test]
    fn one_shot_and_errors_name_the_file() {
        let path = temp("table.csv");
        write_csv(&path, &["a", "b"], &[[1.0, 2.0], [3.0, 4.0]]).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "a,b\n1,2\n3,4\n");
        let bad = temp("no/such/dir/x.csv");
        let e = write_csv(&bad, &["a"], &[[1.0]]).unwrap_err();
        assert!(
            matches!(&e, ChronoError::Io { path, .. } if path.contains("no/such/dir")),
            "{e}"
        );
    }
}
