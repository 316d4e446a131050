//! Published reference data used by the validation cases, embedded at compile time from
//! the repository's `data/reference/` (one copy; each file opens with `#` lines naming its
//! source, paper and data set; `data/reference/README.md` lists them).
//!
//! Embedding keeps `cargo xtask validate` independent of the working directory: the data
//! travel inside the binary.

use std::sync::OnceLock;

/// `(file name, contents)` of every embedded reference file.
const FILES: &[(&str, &str)] = &[
    (
        "dambreak_martin_moyce_n2_1.csv",
        include_str!("../../data/reference/dambreak_martin_moyce_n2_1.csv"),
    ),
    (
        "dambreak_martin_moyce_n2_1_trixi_digitization.csv",
        include_str!("../../data/reference/dambreak_martin_moyce_n2_1_trixi_digitization.csv"),
    ),
    (
        "dambreak_martin_moyce_n2_2_a2.25in.csv",
        include_str!("../../data/reference/dambreak_martin_moyce_n2_2_a2.25in.csv"),
    ),
    (
        "dambreak_martin_moyce_n2_2_a1.125in.csv",
        include_str!("../../data/reference/dambreak_martin_moyce_n2_2_a1.125in.csv"),
    ),
    (
        "dambreak_koshizuka_oka_1996.csv",
        include_str!("../../data/reference/dambreak_koshizuka_oka_1996.csv"),
    ),
    (
        "poiseuille_startup_series.csv",
        include_str!("../../data/reference/poiseuille_startup_series.csv"),
    ),
    (
        "couette_startup_series.csv",
        include_str!("../../data/reference/couette_startup_series.csv"),
    ),
    (
        "shell_sze2004_3-1_cantilever_end_shear.csv",
        include_str!("../../data/reference/shell_sze2004_3-1_cantilever_end_shear.csv"),
    ),
    (
        "sloshing_viscous_wu2001_Re2_Re20.csv",
        include_str!("../../data/reference/sloshing_viscous_wu2001_Re2_Re20.csv"),
    ),
    (
        "sloshing_viscous_wu2001_Re200_peaks.csv",
        include_str!("../../data/reference/sloshing_viscous_wu2001_Re200_peaks.csv"),
    ),
];

/// The rows of an embedded reference CSV: `#` comment lines and one header line are
/// skipped, every other line is a row of numbers. An unknown name or a malformed line is
/// an error naming the file (and the line).
pub fn csv(name: &str) -> anyhow::Result<Vec<Vec<f64>>> {
    let (_, text) = FILES.iter().find(|(n, _)| *n == name).ok_or_else(|| {
        anyhow::anyhow!(
            "reference data `{name}` is not embedded (known: {})",
            FILES.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")
        )
    })?;
    parse_csv(name, text)
}

fn parse_csv(name: &str, text: &str) -> anyhow::Result<Vec<Vec<f64>>> {
    let mut rows = Vec::new();
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .skip(1)
    {
        let row: Result<Vec<f64>, _> = line.split(',').map(|s| s.trim().parse::<f64>()).collect();
        rows.push(
            row.map_err(|e| anyhow::anyhow!("data/reference/{name}: bad line `{line}`: {e}"))?,
        );
    }
    Ok(rows)
}

/// The first two columns of an embedded file as `(x, y)` pairs, parsed once.
fn pairs(cell: &'static OnceLock<Vec<(f64, f64)>>, name: &str) -> &'static [(f64, f64)] {
    cell.get_or_init(|| {
        // The embedded files are fixed at compile time and parsed by the tests below,
        // so a failure here is a build defect, not bad user input.
        csv(name)
            .unwrap_or_else(|e| panic!("embedded reference data: {e}"))
            .iter()
            .map(|r| (r[0], r[1]))
            .collect()
    })
}

/// Martin and Moyce (1952), square column `n^2 = 1`: the surge front `(T, Z)` with
/// `T = t sqrt(2 g / a)`, `Z = x / a` (`data/reference/dambreak_martin_moyce_n2_1.csv`,
/// digits from the lethe dam-break example, cited there to Martin and Moyce; the `Z`
/// values are the experiment's gauge positions).
///
/// J. C. Martin and W. J. Moyce, Phil. Trans. R. Soc. Lond. A 244 (1952) 312-324.
pub fn martin_moyce_n2_1() -> &'static [(f64, f64)] {
    static CELL: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    pairs(&CELL, "dambreak_martin_moyce_n2_1.csv")
}

/// The alternative manual digitization of the same experiment (TrixiParticles.jl,
/// `validation/dam_break_2d/exp_surge_front.csv`) as `(t sqrt(g / a), Z)`: its time
/// axis is `T / sqrt(2)`. The spread of the two digitizations is the experimental
/// uncertainty.
pub fn martin_moyce_n2_1_alt() -> &'static [(f64, f64)] {
    static CELL: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    pairs(&CELL, "dambreak_martin_moyce_n2_1_trixi_digitization.csv")
}

/// Martin and Moyce (1952), Fig. 3, a column twice as high as wide (`n^2 = 2`) with
/// `a = 2.25 in` (the width of the square column's data): the surge front `(T, Z)`,
/// `T = t sqrt(2 g / a)`, `Z = x / a` (`data/reference/dambreak_martin_moyce_n2_2_a2.25in.csv`,
/// digits from PySPH's `db_exp_data.py`).
pub fn martin_moyce_n2_2() -> &'static [(f64, f64)] {
    static CELL: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    pairs(&CELL, "dambreak_martin_moyce_n2_2_a2.25in.csv")
}

/// The same experiment with the smaller column, `a = 1.125 in`
/// (`data/reference/dambreak_martin_moyce_n2_2_a1.125in.csv`): its spread against
/// [`martin_moyce_n2_2`] is the experiment's scale effect and uncertainty.
pub fn martin_moyce_n2_2_small() -> &'static [(f64, f64)] {
    static CELL: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    pairs(&CELL, "dambreak_martin_moyce_n2_2_a1.125in.csv")
}

/// Koshizuka and Oka (1996), Nucl. Sci. Eng. 123:421-434: the leading edge of a column
/// `L = 0.146 m` wide and `2 L` high (`n^2 = 2`), `(T, Z)` with `T = t sqrt(2 g / L)`,
/// `Z = x / L` (`data/reference/dambreak_koshizuka_oka_1996.csv`, digits from PySPH's
/// `db_exp_data.py`).
pub fn koshizuka_oka_1996() -> &'static [(f64, f64)] {
    static CELL: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    pairs(&CELL, "dambreak_koshizuka_oka_1996.csv")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_embedded_file_parses_with_rectangular_rows() {
        for (name, _) in FILES {
            let rows = csv(name).unwrap();
            assert!(rows.len() >= 5, "{name}: {} rows", rows.len());
            let w = rows[0].len();
            assert!(w >= 2 && rows.iter().all(|r| r.len() == w), "{name}");
        }
    }

    #[test]
    fn martin_moyce_tables() {
        let mm = martin_moyce_n2_1();
        assert_eq!(mm.len(), 14);
        assert_eq!(mm[0], (0.0, 1.0));
        assert_eq!(mm[13], (2.96, 3.67));
        assert!(mm.windows(2).all(|w| w[1].0 > w[0].0 && w[1].1 > w[0].1));
        let alt = martin_moyce_n2_1_alt();
        assert_eq!(alt.len(), 10);
        assert_eq!(alt[9], (1.92861, 3.00078));
        let (big, small, ko) = (
            martin_moyce_n2_2(),
            martin_moyce_n2_2_small(),
            koshizuka_oka_1996(),
        );
        assert_eq!((big.len(), small.len(), ko.len()), (15, 10, 9));
        assert_eq!(big[3], (2.547, 2.995));
        assert_eq!(small[4], (2.95, 3.728));
        assert_eq!(ko[0], (0.0, 1.0));
        for d in [big, small, ko] {
            assert!(d.windows(2).all(|w| w[1].0 > w[0].0 && w[1].1 > w[0].1));
        }
    }

    #[test]
    fn unknown_and_malformed_data_are_errors_naming_the_file() {
        let e = csv("nope.csv").unwrap_err().to_string();
        assert!(e.contains("nope.csv"), "{e}");
        let e = parse_csv("x.csv", "# c\na,b\n1,2\n3,oops\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("x.csv") && e.contains("oops"), "{e}");
    }
}
