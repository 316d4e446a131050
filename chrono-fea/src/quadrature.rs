//! Gauss–Legendre quadrature on the unit interval.

/// Points and weights of the `n`-point Gauss–Legendre rule mapped to `[0, 1]` (weights
/// sum to 1), `n` in 1..=5. Exact for polynomials of degree `2 n - 1`.
/// Abscissae on `[-1, 1]` from Abramowitz & Stegun (1964), Table 25.4.
pub fn gauss_unit(n: usize) -> &'static [(f64, f64)] {
    match n {
        1 => &GAUSS1,
        2 => &GAUSS2,
        3 => &GAUSS3,
        4 => &GAUSS4,
        _ => &GAUSS5,
    }
}

const fn map(x: f64, w: f64) -> (f64, f64) {
    (0.5 * (x + 1.0), 0.5 * w)
}

const GAUSS1: [(f64, f64); 1] = [map(0.0, 2.0)];
const A2: f64 = 0.577_350_269_189_625_8;
const GAUSS2: [(f64, f64); 2] = [map(-A2, 1.0), map(A2, 1.0)];
const A3: f64 = 0.774_596_669_241_483_4;
const GAUSS3: [(f64, f64); 3] = [map(-A3, 5.0 / 9.0), map(0.0, 8.0 / 9.0), map(A3, 5.0 / 9.0)];
const A4: f64 = 0.339_981_043_584_856_3;
const B4: f64 = 0.861_136_311_594_052_6;
const W4A: f64 = 0.652_145_154_862_546_1;
const W4B: f64 = 0.347_854_845_137_453_9;
const GAUSS4: [(f64, f64); 4] = [map(-B4, W4B), map(-A4, W4A), map(A4, W4A), map(B4, W4B)];
const A5: f64 = 0.538_469_310_105_683_1;
const B5: f64 = 0.906_179_845_938_664;
const W5O: f64 = 0.568_888_888_888_888_9;
const W5A: f64 = 0.478_628_670_499_366_5;
const W5B: f64 = 0.236_926_885_056_189_1;
const GAUSS5: [(f64, f64); 5] = [
    map(-B5, W5B),
    map(-A5, W5A),
    map(0.0, W5O),
    map(A5, W5A),
    map(B5, W5B),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_integrate_their_degree_exactly() {
        for n in 1..=5 {
            for deg in 0..2 * n {
                let q: f64 = gauss_unit(n)
                    .iter()
                    .map(|&(x, w)| w * x.powi(deg as i32))
                    .sum();
                let exact = 1.0 / (deg as f64 + 1.0);
                assert!(
                    (q - exact).abs() < 1e-14,
                    "n {n} degree {deg}: {q} vs {exact}"
                );
            }
        }
    }
}
