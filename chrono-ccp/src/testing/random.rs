//! Seeded random problems: small CCPs of every row kind, particle lattices.

use chrono_core::descriptor::{
    BlockId, CcpProblem, ConstraintRows, MassOperator, PER_BODY_ROWS, RowEntry, Variables,
};
use chrono_core::math::{GRAVITY, Matrix3, Vector3};
use chrono_core::rng::Rng;

use super::dense_n;

/// A random small CCP (seeded): 1–4 variable blocks (particles and rigid bodies with full
/// inertia tensors), up to 2 bilateral, 2 box, 3 unilateral rows and 3 friction triplets,
/// each row touching 1 or 2 blocks with coefficients in [-1, 1], random `b`, random `k`,
/// `mu` in [0, 1]. Well posed: if the rows are not clearly independent (`lambda_min(N) <
/// 1e-3 lambda_max(N)`), every row gets a compliance `eps` in [0.01, 0.1] (scaled by the
/// mean diagonal), which makes `N` positive definite; some problems get it anyway.
pub fn random_problem(seed: u64) -> chrono_core::Result<CcpProblem> {
    let mut rng = Rng::splitmix64(seed);
    let nb = rng.int(1, 4);
    let mut vars = Variables::new();
    for _ in 0..nb {
        let m = rng.range(0.5, 2.0);
        if rng.int(0, 1) == 0 {
            vars.add(MassOperator::particle(m)?);
        } else {
            let mut j = Matrix3::from_diagonal(&Vector3::new(
                rng.range(0.1, 1.0),
                rng.range(0.1, 1.0),
                rng.range(0.1, 1.0),
            ));
            for (a, b) in [(0, 1), (0, 2), (1, 2)] {
                let x = rng.range(-0.03, 0.03);
                j[(a, b)] = x;
                j[(b, a)] = x;
            }
            vars.add(MassOperator::rigid_body(m, j)?);
        }
    }
    let counts = [rng.int(0, 2), rng.int(0, 2), rng.int(0, 3), rng.int(0, 3)];
    let counts = if counts.iter().all(|&c| c == 0) {
        [0, 0, 1, 1]
    } else {
        counts
    };
    let row = |rng: &mut Rng| -> Vec<(BlockId, Vec<f64>)> {
        let first = rng.int(0, nb - 1);
        let mut blocks = vec![first];
        if nb > 1 && rng.int(0, 1) == 1 {
            let second = (first + rng.int(1, nb - 1)) % nb;
            blocks.push(second);
        }
        blocks
            .into_iter()
            .map(|b| {
                let id = BlockId(b as u32);
                let nd = vars.block_ndof(id);
                (id, (0..nd).map(|_| rng.range(-1.0, 1.0)).collect())
            })
            .collect()
    };
    let mut spec_rows = Vec::new(); // (group, entries, b, lo, hi)
    for (group, &count) in counts.iter().enumerate() {
        let n_rows = if group == 3 { 3 * count } else { count };
        for _ in 0..n_rows {
            let e = row(&mut rng);
            let b = rng.range(-0.5, 0.5);
            let lo = rng.range(-1.0, 0.0);
            let hi = lo + rng.range(0.0, 1.5);
            spec_rows.push((group, e, b, lo, hi));
        }
    }
    let mus: Vec<f64> = (0..counts[3])
        .map(|_| {
            if rng.int(0, 5) == 0 {
                0.0
            } else {
                rng.range(0.0, 1.0)
            }
        })
        .collect();
    let k: Vec<f64> = (0..vars.ndof()).map(|_| rng.range(-1.0, 1.0)).collect();
    let force_eps = rng.int(0, 2) == 0;
    let eps_frac = rng.range(0.01, 0.1);
    // Rolling contacts (drawn last, so the rest of a seed's problem is unchanged).
    let n_roll = rng.int(0, 3).saturating_sub(1);
    let mut roll_rows = Vec::new();
    for _ in 0..n_roll {
        let rows6: Vec<_> = (0..6)
            .map(|_| (row(&mut rng), rng.range(-0.5, 0.5)))
            .collect();
        let mu = [
            rng.range(0.0, 1.0),
            if rng.int(0, 3) == 0 {
                0.0
            } else {
                rng.range(0.0, 0.5)
            },
            if rng.int(0, 3) == 0 {
                0.0
            } else {
                rng.range(0.0, 0.5)
            },
        ];
        roll_rows.push((rows6, mu));
    }
    // A per-body rolling contact (10 rows, two 3-row balls) in a third of the problems,
    // drawn after the rolling contacts for the same reason.
    let n_per_body = usize::from(rng.int(0, 2) == 0);
    let mut per_body_rows = Vec::new();
    for _ in 0..n_per_body {
        let rows10: Vec<_> = (0..PER_BODY_ROWS)
            .map(|_| (row(&mut rng), rng.range(-0.5, 0.5)))
            .collect();
        let mu = [
            rng.range(0.0, 1.0),
            rng.range(0.0, 0.5),
            rng.range(0.0, 0.5),
        ];
        per_body_rows.push((rows10, mu));
    }

    let build = |eps: f64| {
        let mut rows = ConstraintRows::new();
        fn entries(e: &[(BlockId, Vec<f64>)]) -> Vec<RowEntry<'_>> {
            e.iter()
                .map(|(b, c)| RowEntry {
                    block: *b,
                    coefs: c,
                })
                .collect()
        }
        let mut t = 0;
        let mut i = 0;
        while i < spec_rows.len() {
            let (group, e, b, lo, hi) = &spec_rows[i];
            match group {
                0 => {
                    rows.push_bilateral(&entries(e), *b, eps);
                }
                1 => {
                    rows.push_box(&entries(e), *b, eps, *lo, *hi);
                }
                2 => {
                    rows.push_unilateral(&entries(e), *b, eps);
                }
                _ => {
                    let (e1, e2) = (&spec_rows[i + 1].1, &spec_rows[i + 2].1);
                    let bs = [*b, spec_rows[i + 1].2, spec_rows[i + 2].2];
                    rows.push_friction(
                        mus[t],
                        [&entries(e), &entries(e1), &entries(e2)],
                        bs,
                        [eps; 3],
                    );
                    t += 1;
                    i += 2;
                }
            }
            i += 1;
        }
        for (rows6, mu) in &roll_rows {
            let e: Vec<Vec<RowEntry>> = rows6.iter().map(|(e, _)| entries(e)).collect();
            let mut b = [0.0; 6];
            for j in 0..6 {
                b[j] = rows6[j].1;
            }
            rows.push_rolling_friction(
                *mu,
                [&e[0], &e[1], &e[2], &e[3], &e[4], &e[5]],
                b,
                [eps; 6],
            );
        }
        for (rows10, mu) in &per_body_rows {
            let e: Vec<Vec<RowEntry>> = rows10.iter().map(|(e, _)| entries(e)).collect();
            rows.push_rolling_per_body(
                *mu,
                std::array::from_fn(|j| &e[j][..]),
                std::array::from_fn(|j| rows10[j].1),
                [eps; PER_BODY_ROWS],
            );
        }
        let mut p = CcpProblem::new();
        p.assemble(&vars, &rows, &k)?;
        Ok(p)
    };
    let p = build(0.0)?;
    let n = dense_n(&p);
    let mean_diag = p.diag().iter().sum::<f64>() / p.n_rows() as f64;
    let eig = n.symmetric_eigenvalues();
    let (lmin, lmax) = (eig.min(), eig.max());
    if force_eps || lmin < 1e-3 * lmax {
        build(eps_frac * mean_diag)
    } else {
        Ok(p)
    }
}

/// Particles on a lattice (spacing 1), frictional contacts between lattice neighbours and
/// with the ground, random small gaps `b` and random velocities.
pub fn lattice(nx: usize, ny: usize, nz: usize, seed: u64) -> chrono_core::Result<CcpProblem> {
    let mut rng = Rng::splitmix64(seed);
    let mut vars = Variables::new();
    let idx = |x: usize, y: usize, z: usize| (z * ny + y) * nx + x;
    let mut ids = Vec::new();
    for _ in 0..nx * ny * nz {
        ids.push(vars.add(MassOperator::particle(rng.range(0.5, 1.5))?));
    }
    let axes: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let neg = |a: [f64; 3]| [-a[0], -a[1], -a[2]];
    let frame = |a: usize| (axes[a], axes[(a + 1) % 3], axes[(a + 2) % 3]);
    let mut rows = ConstraintRows::new();
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let i = ids[idx(x, y, z)];
                let gap = |rng: &mut Rng| rng.range(-0.01, 0.01);
                if z == 0 {
                    let (n, u, w) = frame(2);
                    let rn = [RowEntry {
                        block: i,
                        coefs: &n,
                    }];
                    let ru = [RowEntry {
                        block: i,
                        coefs: &u,
                    }];
                    let rw = [RowEntry {
                        block: i,
                        coefs: &w,
                    }];
                    rows.push_friction(0.5, [&rn, &ru, &rw], [gap(&mut rng), 0.0, 0.0], [0.0; 3]);
                }
                for (a, (dx, dy, dz)) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)].into_iter().enumerate() {
                    let (x2, y2, z2) = (x + dx, y + dy, z + dz);
                    if x2 >= nx || y2 >= ny || z2 >= nz {
                        continue;
                    }
                    let j = ids[idx(x2, y2, z2)];
                    let (n, u, w) = frame(a);
                    let (nn, nu, nw) = (neg(n), neg(u), neg(w));
                    let rn = [
                        RowEntry {
                            block: j,
                            coefs: &n,
                        },
                        RowEntry {
                            block: i,
                            coefs: &nn,
                        },
                    ];
                    let ru = [
                        RowEntry {
                            block: j,
                            coefs: &u,
                        },
                        RowEntry {
                            block: i,
                            coefs: &nu,
                        },
                    ];
                    let rw = [
                        RowEntry {
                            block: j,
                            coefs: &w,
                        },
                        RowEntry {
                            block: i,
                            coefs: &nw,
                        },
                    ];
                    rows.push_friction(
                        0.3,
                        [&rn, &ru, &rw],
                        [gap(&mut rng), 0.0, 0.0],
                        [0.0, 1e-6, 1e-6],
                    );
                }
            }
        }
    }
    let mut k = vec![0.0; vars.ndof()];
    for (p, kp) in k.chunks_mut(3).enumerate() {
        let m = match vars.mass(ids[p]) {
            MassOperator::Particle { mass } => *mass,
            _ => unreachable!("the lattice holds particles only"),
        };
        kp[0] = m * rng.range(-0.1, 0.1);
        kp[1] = m * rng.range(-0.1, 0.1);
        kp[2] = m * (rng.range(-0.1, 0.1) + GRAVITY.z * 0.01);
    }
    let mut problem = CcpProblem::new();
    problem.assemble(&vars, &rows, &k)?;
    Ok(problem)
}
