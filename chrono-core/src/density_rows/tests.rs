//! Tests of the density rows: the lattice sums to `rho_0`, the row coefficients are the
//! negated gradient of `C_i` (central differences, free particles and a body's block), the
//! right-hand side by surface mode.

use super::*;
use crate::descriptor::{BlockId, ConstraintRows, RowEntry, RowGroup};
use crate::particles::{GridConfig, KernelKind};

/// A small cloud: `n_free` free particles (a perturbed lattice), then fixed markers (a
/// floor layer), then body markers (two bodies).
struct Cloud {
    kernel: Kernel,
    mass: f64,
    pos: [Vec<f64>; 3],
    n_free: usize,
    n_static: usize,
    owner: Vec<u32>,
    origin: Vec<[f64; 3]>,
}

const DP: f64 = 0.1;
const RHO: f64 = 1000.0;

fn cloud() -> Cloud {
    let kernel = Kernel::new(KernelKind::WendlandC2, 1.2 * DP, 3).unwrap();
    let mass = lattice_mass(&kernel, DP, RHO);
    let mut pts = Vec::new();
    // a deterministic perturbation, up to 0.2 dp
    let jitter = |k: usize, a: usize| 0.2 * DP * (((k * 7 + a * 13) % 11) as f64 / 10.0 - 0.5);
    let mut k = 0;
    for z in 0..3 {
        for y in 0..3 {
            for x in 0..3 {
                let p = [x as f64 * DP, y as f64 * DP, (z as f64 + 1.0) * DP];
                pts.push(std::array::from_fn(|a| p[a] + jitter(k, a)));
                k += 1;
            }
        }
    }
    let n_free = pts.len();
    for y in -1..4 {
        for x in -1..4 {
            pts.push([x as f64 * DP, y as f64 * DP, 0.0]);
        }
    }
    let n_static = pts.len();
    let mut owner = Vec::new();
    for (b, x0) in [(0u32, 3.0 * DP), (1, -DP)] {
        for z in 1..4 {
            pts.push([x0 + 0.03 * b as f64, DP, z as f64 * DP + 0.02]);
            owner.push(b);
        }
    }
    let origin = vec![[3.3 * DP, DP, 2.0 * DP], [-1.2 * DP, 0.9 * DP, 2.1 * DP]];
    Cloud {
        kernel,
        mass,
        pos: std::array::from_fn(|a| pts.iter().map(|p| p[a]).collect()),
        n_free,
        n_static,
        owner,
        origin,
    }
}

/// `C_i` of particle `i` for the positions `pos`.
fn constraint(c: &Cloud, pos: &[Vec<f64>; 3], i: usize) -> f64 {
    let (grid, nbrs) = neighbours(c, pos);
    let f = field(c, pos, &grid, &nbrs);
    f.density(i) / RHO - 1.0
}

fn neighbours(c: &Cloud, pos: &[Vec<f64>; 3]) -> (CellGrid, NeighborList) {
    let config = GridConfig::bounded(c.kernel.support(), [-1.0; 3], [1.0; 3]);
    let mut grid = CellGrid::new(config).unwrap();
    let p = [&pos[0][..], &pos[1][..], &pos[2][..]];
    grid.build(p).unwrap();
    let mut nbrs = NeighborList::new();
    grid.neighbor_list(p, c.kernel.support(), &mut nbrs)
        .unwrap();
    (grid, nbrs)
}

fn field<'a>(
    c: &'a Cloud,
    pos: &'a [Vec<f64>; 3],
    grid: &'a CellGrid,
    nbrs: &'a NeighborList,
) -> DensityField<'a> {
    DensityField {
        kernel: &c.kernel,
        mass: c.mass,
        rho_0: RHO,
        grid,
        pos: [&pos[0], &pos[1], &pos[2]],
        nbrs,
        n_free: c.n_free,
        n_static: c.n_static,
        marker_owner: &c.owner,
        body_origin: &c.origin,
    }
}

#[test]
fn the_lattice_sums_to_the_rest_density() {
    for dim in [2, 3] {
        let kernel = Kernel::new(KernelKind::WendlandC2, 1.3 * DP, dim).unwrap();
        let m = lattice_mass(&kernel, DP, RHO);
        // the direct sum of an interior lattice point, independently written
        let mut rho = 0.0;
        for k in -4i32..=4 {
            for j in -4i32..=4 {
                for i in -4i32..=4 {
                    if dim == 2 && j != 0 {
                        continue;
                    }
                    let r = DP * f64::from(i * i + j * j + k * k).sqrt();
                    rho += m * kernel.w(r);
                }
            }
        }
        assert!((rho / RHO - 1.0).abs() < 1e-12, "dim {dim}: {rho}");
    }
}

#[test]
fn the_row_is_minus_the_gradient_of_the_constraint() {
    let c = cloud();
    let (grid, nbrs) = neighbours(&c, &c.pos);
    let f = field(&c, &c.pos, &grid, &nbrs);
    let delta = 1e-6;
    let mut checked = 0;
    for i in [0, 4, 13, 20] {
        let mut row = RowBuf::default();
        f.row(i, &mut row);
        assert_eq!(row.particles[0], i as u32);
        // every free particle: the coefficient, or 0 when it is not in the row
        for j in 0..c.n_free {
            for a in 0..3 {
                let mut p = c.pos.clone();
                p[a][j] += delta;
                let up = constraint(&c, &p, i);
                p[a][j] -= 2.0 * delta;
                let down = constraint(&c, &p, i);
                let fd = -(up - down) / (2.0 * delta);
                let coef = row
                    .particles
                    .iter()
                    .position(|&q| q as usize == j)
                    .map_or(0.0, |k| row.coefs[3 * k + a]);
                assert!(
                    (coef - fd).abs() < 1e-6 * (1.0 + fd.abs()),
                    "row {i}, particle {j}, axis {a}: {coef} vs {fd}"
                );
                checked += usize::from(coef != 0.0);
            }
        }
        // each body: translate all its markers (linear part), rotate them about x_b
        // (angular part)
        for b in 0..2u32 {
            let block = row
                .bodies
                .iter()
                .find(|e| e.0 == b)
                .map_or([0.0; 6], |e| e.1);
            for a in 0..3 {
                let moved = |s: f64| {
                    let mut p = c.pos.clone();
                    for (m, &o) in c.owner.iter().enumerate() {
                        if o == b {
                            p[a][c.n_static + m] += s;
                        }
                    }
                    constraint(&c, &p, i)
                };
                let fd = -(moved(delta) - moved(-delta)) / (2.0 * delta);
                assert!((block[a] - fd).abs() < 1e-6 * (1.0 + fd.abs()));
                let turned = |s: f64| {
                    let mut p = c.pos.clone();
                    let x_b = c.origin[b as usize];
                    for (m, &o) in c.owner.iter().enumerate() {
                        if o == b {
                            let k = c.n_static + m;
                            let arm = [p[0][k] - x_b[0], p[1][k] - x_b[1], p[2][k] - x_b[2]];
                            // small rotation s about axis a: dx = s e_a x arm
                            let mut w = [0.0; 3];
                            w[a] = s;
                            let d = [
                                w[1] * arm[2] - w[2] * arm[1],
                                w[2] * arm[0] - w[0] * arm[2],
                                w[0] * arm[1] - w[1] * arm[0],
                            ];
                            for e in 0..3 {
                                p[e][k] += d[e];
                            }
                        }
                    }
                    constraint(&c, &p, i)
                };
                let fd = -(turned(delta) - turned(-delta)) / (2.0 * delta);
                assert!(
                    (block[3 + a] - fd).abs() < 1e-6 * (1.0 + fd.abs()),
                    "row {i}, body {b}, angular {a}: {} vs {fd}",
                    block[3 + a]
                );
                checked += usize::from(block[a] != 0.0);
            }
        }
    }
    // the test reaches real couplings, bodies included
    assert!(checked > 60, "{checked}");
}

#[test]
fn a_fixed_marker_row_has_no_entry_on_other_fixed_markers() {
    let c = cloud();
    let (grid, nbrs) = neighbours(&c, &c.pos);
    let f = field(&c, &c.pos, &grid, &nbrs);
    let mut rows = vec![RowBuf::default(); c.n_static - c.n_free];
    let mut rho = vec![0.0; rows.len()];
    f.wall_rows(&mut rows, &mut rho);
    let mut with_entries = 0;
    for (m, row) in rows.iter().enumerate() {
        assert!(row.particles.iter().all(|&p| (p as usize) < c.n_free));
        assert_eq!(rho[m], f.density(c.n_free + m));
        with_entries += usize::from(!row.particles.is_empty());
    }
    assert!(with_entries > 0);
}

#[test]
fn the_right_hand_side_follows_the_surface_mode() {
    let coefs = [1.0, 0.0, 0.0];
    let entries = [RowEntry {
        block: BlockId(0),
        coefs: &coefs,
    }];
    let (h, eps, known, rate) = (1e-2, 1e-3, 0.5, 2.0);
    let cases = [
        // mode, C, group, b
        (
            SurfaceMode::OneSided,
            -0.1,
            RowGroup::Unilateral,
            known + 10.0,
        ),
        (
            SurfaceMode::OneSided,
            0.01,
            RowGroup::Bilateral,
            known - 1.0,
        ),
        (
            SurfaceMode::OneSided,
            0.1,
            RowGroup::Bilateral,
            known - rate,
        ),
        (
            SurfaceMode::Unilateral,
            -0.1,
            RowGroup::Unilateral,
            known + 10.0,
        ),
        (
            SurfaceMode::Unilateral,
            0.1,
            RowGroup::Unilateral,
            known - rate,
        ),
        (SurfaceMode::Clamped, -0.1, RowGroup::Bilateral, known),
        (SurfaceMode::Clamped, 0.01, RowGroup::Bilateral, known - 1.0),
    ];
    for (mode, c, group, b) in cases {
        let mut rows = ConstraintRows::new();
        let id = push_density_row(&mut rows, &entries, c, h, eps, known, mode, rate);
        assert_eq!(id.group, group, "{mode:?} C {c}");
        let g = &rows.groups[group as usize];
        assert!(
            (g.b[0] - b).abs() < 1e-12,
            "{mode:?} C {c}: b {} vs {b}",
            g.b[0]
        );
        assert_eq!(g.eps[0], eps);
    }
    // kappa rho_0 / (h^2 m) = 1e-9 * 1000 / (1e-6 * 2)
    assert!((compliance(1e-9, 1000.0, 1e-3, 2.0) - 0.5).abs() < 1e-12);
    assert!(SurfaceMode::parse("sideways").is_err());
}

/// A block of `7^3` free particles on the lattice (jittered by up to `jitter` dp per
/// axis, deterministically), no markers; the centre particle has a full support.
fn block(jitter: f64) -> (Cloud, usize) {
    let kernel = Kernel::new(KernelKind::WendlandC2, 1.2 * DP, 3).unwrap();
    let mass = lattice_mass(&kernel, DP, RHO);
    let mut pts = Vec::new();
    let mut k = 0usize;
    for z in -3i32..=3 {
        for y in -3i32..=3 {
            for x in -3i32..=3 {
                let p = [x, y, z].map(|v| f64::from(v) * DP);
                // a pseudo-random offset in [-jitter/2, jitter/2] dp per axis
                let off = |a: usize| {
                    let h = (k * 2654435761 + a * 40503) % 1000;
                    jitter * DP * (h as f64 / 999.0 - 0.5)
                };
                pts.push([p[0] + off(0), p[1] + off(1), p[2] + off(2)]);
                k += 1;
            }
        }
    }
    let n = pts.len();
    let c = Cloud {
        kernel,
        mass,
        pos: std::array::from_fn(|a| pts.iter().map(|p| p[a]).collect()),
        n_free: n,
        n_static: n,
        owner: Vec::new(),
        origin: Vec::new(),
    };
    (c, n / 2)
}

/// `D_i . v` of row `row` for the velocity field `v(x)`.
fn row_rate(row: &RowBuf, pos: &[Vec<f64>; 3], v: impl Fn([f64; 3]) -> [f64; 3]) -> f64 {
    row.particles
        .iter()
        .zip(row.coefs.chunks_exact(3))
        .map(|(&p, c)| {
            let p = p as usize;
            let u = v([pos[0][p], pos[1][p], pos[2][p]]);
            c[0] * u[0] + c[1] * u[1] + c[2] * u[2]
        })
        .sum()
}

#[test]
fn the_corrected_row_reads_a_shear_of_a_disordered_packing_as_no_compression() {
    let shear = |x: [f64; 3]| [x[2], 0.0, 0.0];
    let expansion = |x: [f64; 3]| x;
    let translation = |_: [f64; 3]| [0.3, -0.2, 0.1];
    // on the lattice the moment matrix is isotropic and close to the identity
    let (c, i) = block(0.0);
    let (grid, nbrs) = neighbours(&c, &c.pos);
    let f = field(&c, &c.pos, &grid, &nbrs);
    let m = f.moment(i);
    for (a, row) in m.iter().enumerate() {
        for (b, &e) in row.iter().enumerate() {
            let want = if a == b { m[0][0] } else { 0.0 };
            assert!((e - want).abs() < 1e-12, "lattice M[{a}][{b}] = {e}");
        }
    }
    assert!((m[0][0] - 1.0).abs() < 0.05, "lattice M = {} I", m[0][0]);
    // a disordered packing: the plain row sees the shear, the corrected one does not
    let (c, i) = block(0.4);
    let (grid, nbrs) = neighbours(&c, &c.pos);
    let f = field(&c, &c.pos, &grid, &nbrs);
    let (mut plain, mut corr) = (RowBuf::default(), RowBuf::default());
    f.row(i, &mut plain);
    f.row_corrected(i, &mut corr, 0.5);
    let p_shear = row_rate(&plain, &c.pos, shear);
    let c_shear = row_rate(&corr, &c.pos, shear);
    let c_exp = row_rate(&corr, &c.pos, expansion);
    assert!(p_shear.abs() > 1e-3, "plain row's shear rate {p_shear}");
    assert!(
        c_shear.abs() < 1e-12,
        "corrected row's shear rate {c_shear}"
    );
    // the rate of v = A x is tr A (the row is -grad C, so `D . v = -dC/dt = div v`)
    assert!(
        (c_exp - 3.0).abs() < 1e-12,
        "corrected row's expansion rate {c_exp}"
    );
    for r in [&plain, &corr] {
        let t = row_rate(r, &c.pos, translation);
        assert!(t.abs() < 1e-12, "translation rate {t}");
    }
    // a threshold above the smallest eigenvalue keeps the plain row
    let mut kept = RowBuf::default();
    f.row_corrected(i, &mut kept, 10.0);
    assert_eq!(kept.coefs, plain.coefs);
}
