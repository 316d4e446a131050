//! The quadrature of one marker per cell under compression (issue 25's snow compaction,
//! `docs/mpm.md` "The lag and the layer alternation"): a uniform stress on compressed
//! markers is no longer balanced on the grid.

use nalgebra::{Matrix3, Vector3};

use crate::*;

/// The grid's axial force per node layer `k = 1..cells` (P2G's stress impulse over `dt`,
/// summed over the layer's nodes) of a column one cell wide, `n` markers one per `s dx`
/// along z under one uniform uniaxial stress (their current volumes `s dx^3` tile
/// `[0, n s dx]` exactly), over the uniform stress's force on a section; and the same
/// from the 1-D lattice sum `sum_p s dx dN_k/dz(z_p)`.
fn compressed_column_residual(n: usize, s: f64) -> (Vec<f64>, Vec<f64>) {
    let dx = 0.1;
    let cells = (n as f64 * s).ceil() as usize + 1;
    let spec = GridSpec::new([0.0; 3], [1, 1, cells], dx)
        .unwrap()
        .with_walls(0, Wall::Slip, Wall::Slip)
        .with_walls(1, Wall::Slip, Wall::Slip)
        .with_walls(2, Wall::Slip, Wall::Open);
    let mat = FixedCorotated::elastic(1e5, 0.3).unwrap();
    let settings = MpmSettings {
        gravity: [0.0; 3],
        cfl: 0.5,
        f_bar: crate::fbar::FBar::Off,
    };
    let mut body = MpmBody::new(spec, mat.into(), settings).unwrap();
    // the stress of a 10 % compression; the reference volume such that the current ones,
    // `V0 det F_E = s dx^3`, tile the column
    let fe = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 0.9));
    for p in 0..n {
        let z = (p as f64 + 0.5) * s * dx;
        let v0 = s * dx * dx * dx / 0.9;
        body.markers
            .push(
                1.0,
                v0,
                Vector3::new(0.5 * dx, 0.5 * dx, z),
                Vector3::zeros(),
            )
            .unwrap();
        body.markers.fe[p] = fe;
    }
    let dt = 1e-3;
    body.p2g(dt);
    let tau = mat.kirchhoff(&fe, &Matrix3::identity())[(2, 2)];
    // sum over the layer's nodes of -dt V0 tau_zz dw/dz, over the section force
    let scale = -dt * tau * dx * dx / 0.9;
    let nb = spec.blocks();
    let mut grid = vec![0.0; cells];
    for (kb, &bk) in body.grid().active.iter().enumerate() {
        let b = crate::grid::unkey(bk, nb);
        for q in 0..crate::grid::BLOCK3 {
            let bl = crate::grid::BLOCK;
            let iz = (b[2] * bl + q % bl) as i64 - crate::grid::GHOST;
            if (1..cells as i64).contains(&iz) {
                grid[iz as usize] += body.grid().mom[kb * crate::grid::BLOCK3 + q][2] / scale;
            }
        }
    }
    let lattice: Vec<f64> = (0..cells)
        .map(|k| {
            if k == 0 {
                return 0.0;
            }
            (0..n)
                .map(|p| {
                    let r = (p as f64 + 0.5) * s - k as f64; // (z_p - z_k) / dx
                    let a = r.abs();
                    // dN_k/dz at z_p, times dx: the quadratic B-spline's derivative
                    let dn = if a < 0.5 {
                        -2.0 * r
                    } else if a < 1.5 {
                        -r.signum() * (1.5 - a)
                    } else {
                        0.0
                    };
                    // the force on node k, -V0 tau dN_k/dz(z_p) = -V0 tau dn / dx, over
                    // -tau dx^2 / s
                    s * dn
                })
                .sum()
        })
        .collect();
    (grid, lattice)
}

#[test]
fn one_marker_per_cell_compressed_leaves_a_uniform_stress_out_of_balance() {
    // The snow column's mechanism (docs/mpm.md, `mpm-snow`, 2026-12-06): with one marker
    // per cell the markers' point quadrature of the stress divergence is exact while the
    // markers sit at the cell centres, but a column compressed to `s` leaves a uniform
    // stress with interior nodal forces of order 0.1 of the section force (the lattice's
    // aliasing of the spline's derivative): the equilibrium then needs non-uniform
    // stresses, which the snow's hardening turns into the layers' `J_P` alternation.
    let mut worst = [0.0f64; 2];
    for (c, s) in [1.0, 0.75].into_iter().enumerate() {
        let (grid, lattice) = compressed_column_residual(8, s);
        // the grid's forces are the lattice sum at every node
        for k in 1..grid.len() {
            assert!(
                (grid[k] - lattice[k]).abs() < 1e-12,
                "s {s}, node {k}: grid {} lattice {}",
                grid[k],
                lattice[k]
            );
        }
        // the interior: nodes at least 1.5 dx below the column's free end
        let top = (8.0 * s - 1.5f64).floor() as usize;
        worst[c] = (1..=top).map(|k| grid[k].abs()).fold(0.0, f64::max);
    }
    assert!(
        worst[0] < 1e-12,
        "aligned: largest interior residual {}",
        worst[0]
    );
    assert!(
        worst[1] > 0.05 && worst[1] < 0.2,
        "compressed to 0.75: largest interior residual {}",
        worst[1]
    );
}
