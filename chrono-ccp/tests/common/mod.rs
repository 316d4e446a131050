//! Shared builders and checks of the chrono-ccp integration tests. Problems are built only
//! through chrono-core's public descriptor API, as a physics item would.
#![allow(dead_code)]

use chrono_core::descriptor::{
    BlockId, CcpProblem, CcpWork, ConstraintRows, MassOperator, PER_BODY_ROWS, RowEntry, Variables,
};
use chrono_core::math::{Matrix3, Vector3};
use nalgebra::DMatrix;

/// Gravity, m/s^2.
pub const G: f64 = 9.81;

/// SplitMix64: a tiny seeded generator so that a failing proptest seed reproduces exactly.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64)
    }
    /// Uniform integer in `[lo, hi]`.
    pub fn int(&mut self, lo: usize, hi: usize) -> usize {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as usize
    }
}

/// Coefficients `[d, r x d]` of a rigid body (identity orientation, so body frame = world
/// frame) for the velocity along `d` of the material point at `r` from its center of mass.
pub fn rigid_coefs(r: Vector3<f64>, d: Vector3<f64>) -> [f64; 6] {
    let a = r.cross(&d);
    [d.x, d.y, d.z, a.x, a.y, a.z]
}

/// `N` as a dense matrix, column by column through `apply_n`.
pub fn dense_n(problem: &CcpProblem) -> DMatrix<f64> {
    let m = problem.n_rows();
    let mut work = CcpWork::for_problem(problem);
    let mut n = DMatrix::zeros(m, m);
    let mut e = vec![0.0; m];
    let mut col = vec![0.0; m];
    for j in 0..m {
        e.fill(0.0);
        e[j] = 1.0;
        problem.apply_n(&e, &mut col, &mut work);
        for i in 0..m {
            n[(i, j)] = col[i];
        }
    }
    n
}

/// `N g + r`.
pub fn gradient(problem: &CcpProblem, gamma: &[f64]) -> Vec<f64> {
    let mut c = vec![0.0; problem.n_rows()];
    problem.gradient(gamma, &mut c, &mut CcpWork::for_problem(problem));
    c
}

/// The objective `1/2 g'N g + r'g`.
pub fn objective(problem: &CcpProblem, gamma: &[f64]) -> f64 {
    let c = gradient(problem, gamma);
    gamma
        .iter()
        .zip(&c)
        .zip(problem.r())
        .map(|((g, c), r)| 0.5 * g * (c + r))
        .sum()
}

/// The common residual of `gamma`.
pub fn residual(problem: &CcpProblem, gamma: &[f64]) -> f64 {
    let c = gradient(problem, gamma);
    problem.residual(gamma, &c, &mut CcpWork::for_problem(problem))
}

/// Check the complementarity conditions of the CCP explicitly, row by row, with velocity
/// tolerance `tol` (m/s); impulse tolerances are `tol` times the row's step scale
/// `1 / N_ii` (the scaling of the residual, which makes the two comparable).
pub fn check_complementarity(problem: &CcpProblem, gamma: &[f64], tol: f64) -> Result<(), String> {
    let c = gradient(problem, gamma);
    let s = problem.sections();
    let (lo, hi) = problem.box_bounds();
    for i in 0..problem.n_rows() {
        if !gamma[i].is_finite() || !c[i].is_finite() {
            return Err(format!(
                "row {i}: non-finite g = {} or c = {}",
                gamma[i], c[i]
            ));
        }
    }
    for i in s.bilateral.clone() {
        if c[i].abs() > tol {
            return Err(format!(
                "bilateral row {i}: |c| = {:e} > {tol:e}",
                c[i].abs()
            ));
        }
    }
    for i in s.boxed.clone() {
        let k = i - s.boxed.start;
        let (g, tg) = (gamma[i], tol * problem.residual_scale(i));
        if g < lo[k] || g > hi[k] {
            return Err(format!(
                "box row {i}: g = {g} outside [{}, {}]",
                lo[k], hi[k]
            ));
        }
        let (at_lo, at_hi) = (g - lo[k] <= tg, hi[k] - g <= tg);
        let ok = match (at_lo, at_hi) {
            (true, true) => true,
            (true, false) => c[i] >= -tol,
            (false, true) => c[i] <= tol,
            (false, false) => c[i].abs() <= tol,
        };
        if !ok {
            return Err(format!(
                "box row {i}: g = {g} in [{}, {}] with c = {:e}",
                lo[k], hi[k], c[i]
            ));
        }
    }
    for i in s.unilateral.clone() {
        let (g, sc) = (gamma[i], problem.residual_scale(i));
        if g < 0.0 {
            return Err(format!("unilateral row {i}: g = {g} < 0"));
        }
        if c[i] < -tol {
            return Err(format!("unilateral row {i}: c = {:e} < -{tol:e}", c[i]));
        }
        if (g * c[i]).abs() > tol * (g + sc * c[i].abs() + sc * tol) {
            return Err(format!(
                "unilateral row {i}: g c = {:e} (g = {g:e}, c = {:e})",
                g * c[i],
                c[i]
            ));
        }
    }
    for (k, t) in s.friction.clone().step_by(3).enumerate() {
        let mu = problem.friction_mu()[k];
        let (gn, gt) = (gamma[t], gamma[t + 1].hypot(gamma[t + 2]));
        if gn < 0.0 || gt > mu * gn * (1.0 + 1e-12) + 1e-300 {
            return Err(format!(
                "triplet {t}: g = {:?} outside the cone mu = {mu}",
                &gamma[t..t + 3]
            ));
        }
        let (cn, ct) = (c[t], c[t + 1].hypot(c[t + 2]));
        // -c in the polar cone  <=>  mu |c_t| <= c_n
        if mu * ct - cn > tol * (1.0 + mu) {
            return Err(format!(
                "triplet {t}: -c = {:?} not in the polar cone (mu = {mu})",
                &c[t..t + 3]
            ));
        }
        let sc = problem.residual_scale(t);
        let gc: f64 = (0..3).map(|j| gamma[t + j] * c[t + j]).sum();
        let gnorm = (gn * gn + gt * gt).sqrt();
        let cnorm = (cn * cn + ct * ct).sqrt();
        if gc.abs() > 2.0 * tol * (gnorm + sc * cnorm + sc * tol) {
            return Err(format!(
                "triplet {t}: g'c = {gc:e} (g = {:?}, c = {:?})",
                &gamma[t..t + 3],
                &c[t..t + 3]
            ));
        }
    }
    for (k, t) in s.rolling.clone().step_by(6).enumerate() {
        let mu = problem.rolling_mu()[k];
        let g = &gamma[t..t + 6];
        let norms = [g[1].hypot(g[2]), g[3].abs(), g[4].hypot(g[5])];
        if g[0] < 0.0 || (0..3).any(|j| norms[j] > mu[j] * g[0] * (1.0 + 1e-12) + 1e-300) {
            return Err(format!(
                "rolling contact {t}: g = {g:?} outside the cone mu = {mu:?}"
            ));
        }
        // -c in the polar cone  <=>  c in the dual cone  <=>  c_n >= sum_j mu_j |c_j|
        let cv = &c[t..t + 6];
        let cn = [cv[1].hypot(cv[2]), cv[3].abs(), cv[4].hypot(cv[5])];
        let dual = cv[0] - (0..3).map(|j| mu[j] * cn[j]).sum::<f64>();
        if dual < -tol * (1.0 + mu.iter().sum::<f64>()) {
            return Err(format!(
                "rolling contact {t}: c = {cv:?} not in the dual cone (mu = {mu:?})"
            ));
        }
        let sc = problem.residual_scale(t);
        let gc: f64 = (0..6).map(|j| g[j] * cv[j]).sum();
        let gnorm = g.iter().map(|x| x * x).sum::<f64>().sqrt();
        let cnorm = cv.iter().map(|x| x * x).sum::<f64>().sqrt();
        if gc.abs() > 3.0 * tol * (gnorm + sc * cnorm + sc * tol) {
            return Err(format!(
                "rolling contact {t}: g'c = {gc:e} (g = {g:?}, c = {cv:?})"
            ));
        }
    }
    let n = PER_BODY_ROWS;
    for (k, t) in s.rolling_per_body.clone().step_by(n).enumerate() {
        let m = problem.rolling_per_body_mu()[k];
        // Parts (first row, length, coefficient): sliding, spin, body A, body B.
        let parts = [(1, 2, m[0]), (3, 1, m[1]), (4, 3, m[2]), (7, 3, m[2])];
        let norm = |x: &[f64], (s, len, _): (usize, usize, f64)| {
            x[s..s + len].iter().map(|v| v * v).sum::<f64>().sqrt()
        };
        let g = &gamma[t..t + n];
        if g[0] < 0.0
            || parts
                .iter()
                .any(|&p| norm(g, p) > p.2 * g[0] * (1.0 + 1e-12) + 1e-300)
        {
            return Err(format!(
                "per-body rolling contact {t}: g = {g:?} outside the cone mu = {m:?}"
            ));
        }
        // -c in the polar cone  <=>  c_n >= sum_parts mu_p |c_p|
        let cv = &c[t..t + n];
        let dual = cv[0] - parts.iter().map(|&p| p.2 * norm(cv, p)).sum::<f64>();
        if dual < -tol * (1.0 + m[0] + m[1] + 2.0 * m[2]) {
            return Err(format!(
                "per-body rolling contact {t}: c = {cv:?} not in the dual cone (mu = {m:?})"
            ));
        }
        let sc = problem.residual_scale(t);
        let gc: f64 = (0..n).map(|j| g[j] * cv[j]).sum();
        let gnorm = g.iter().map(|x| x * x).sum::<f64>().sqrt();
        let cnorm = cv.iter().map(|x| x * x).sum::<f64>().sqrt();
        if gc.abs() > 4.0 * tol * (gnorm + sc * cnorm + sc * tol) {
            return Err(format!(
                "per-body rolling contact {t}: g'c = {gc:e} (g = {g:?}, c = {cv:?})"
            ));
        }
    }
    Ok(())
}

/// One particle of mass `m` (kg) on the ground (normal +z, tangents +x, +y) with friction
/// `mu`, velocity `v` before the step of `h` s under gravity: returns the problem.
pub fn particle_on_ground(m: f64, mu: f64, v: [f64; 3], h: f64) -> CcpProblem {
    let mut vars = Variables::new();
    let p = vars.add(MassOperator::particle(m).unwrap());
    let mut rows = ConstraintRows::new();
    let n = [RowEntry {
        block: p,
        coefs: &[0.0, 0.0, 1.0],
    }];
    let u = [RowEntry {
        block: p,
        coefs: &[1.0, 0.0, 0.0],
    }];
    let w = [RowEntry {
        block: p,
        coefs: &[0.0, 1.0, 0.0],
    }];
    rows.push_friction(mu, [&n, &u, &w], [0.0; 3], [0.0; 3]);
    let k = [m * v[0], m * v[1], m * (v[2] - G * h)];
    let mut problem = CcpProblem::new();
    problem.assemble(&vars, &rows, &k).unwrap();
    problem
}

/// A stack of `levels` unit cubes on the ground, the mass tripling per level (the top box of
/// 5 is 81 times the bottom one), 4 corner contacts (friction `mu`) per interface, at rest,
/// one step of `h` s under gravity. Rows are built directly (identity orientations).
pub fn box_stack(levels: usize, mu: f64, h: f64) -> CcpProblem {
    box_stack_ratio(levels, 3.0, mu, h)
}

/// [`box_stack`] with mass ratio `ratio` between consecutive levels.
pub fn box_stack_ratio(levels: usize, ratio: f64, mu: f64, h: f64) -> CcpProblem {
    let mut vars = Variables::new();
    let mut masses = Vec::new();
    let mut ids: Vec<BlockId> = Vec::new();
    for i in 0..levels {
        let m = ratio.powi(i as i32);
        let j = Matrix3::from_diagonal_element(m / 6.0);
        ids.push(vars.add(MassOperator::rigid_body(m, j).unwrap()));
        masses.push(m);
    }
    let mut rows = ConstraintRows::new();
    let dirs = [Vector3::z(), Vector3::x(), Vector3::y()];
    for level in 0..levels {
        // contact between `level - 1` (or the ground) and `level`, on the bottom face of `level`
        for (sx, sy) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
            let r_up = Vector3::new(sx, sy, -0.5);
            let r_down = Vector3::new(sx, sy, 0.5);
            let up: Vec<[f64; 6]> = dirs.iter().map(|d| rigid_coefs(r_up, *d)).collect();
            let down: Vec<[f64; 6]> = dirs.iter().map(|d| rigid_coefs(r_down, -d)).collect();
            let row = |j: usize| {
                let mut e = vec![RowEntry {
                    block: ids[level],
                    coefs: &up[j],
                }];
                if level > 0 {
                    e.push(RowEntry {
                        block: ids[level - 1],
                        coefs: &down[j],
                    });
                }
                e
            };
            let (rn, ru, rw) = (row(0), row(1), row(2));
            rows.push_friction(mu, [&rn, &ru, &rw], [0.0; 3], [0.0; 3]);
        }
    }
    let mut k = vec![0.0; vars.ndof()];
    for (i, m) in masses.iter().enumerate() {
        k[6 * i + 2] = -m * G * h;
    }
    let mut problem = CcpProblem::new();
    problem.assemble(&vars, &rows, &k).unwrap();
    problem
}

/// A random small CCP (seeded): 1–4 variable blocks (particles and rigid bodies with full
/// inertia tensors), up to 2 bilateral, 2 box, 3 unilateral rows and 3 friction triplets,
/// each row touching 1 or 2 blocks with coefficients in [-1, 1], random `b`, random `k`,
/// `mu` in [0, 1]. Well posed: if the rows are not clearly independent (`lambda_min(N) <
/// 1e-3 lambda_max(N)`), every row gets a compliance `eps` in [0.01, 0.1] (scaled by the
/// mean diagonal), which makes `N` positive definite; some problems get it anyway.
pub fn random_problem(seed: u64) -> CcpProblem {
    let mut rng = Rng(seed);
    let nb = rng.int(1, 4);
    let mut vars = Variables::new();
    for _ in 0..nb {
        let m = rng.uniform(0.5, 2.0);
        if rng.int(0, 1) == 0 {
            vars.add(MassOperator::particle(m).unwrap());
        } else {
            let mut j = Matrix3::from_diagonal(&Vector3::new(
                rng.uniform(0.1, 1.0),
                rng.uniform(0.1, 1.0),
                rng.uniform(0.1, 1.0),
            ));
            for (a, b) in [(0, 1), (0, 2), (1, 2)] {
                let x = rng.uniform(-0.03, 0.03);
                j[(a, b)] = x;
                j[(b, a)] = x;
            }
            vars.add(MassOperator::rigid_body(m, j).unwrap());
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
                (id, (0..nd).map(|_| rng.uniform(-1.0, 1.0)).collect())
            })
            .collect()
    };
    let mut spec_rows = Vec::new(); // (group, entries, b, lo, hi)
    for (group, &count) in counts.iter().enumerate() {
        let n_rows = if group == 3 { 3 * count } else { count };
        for _ in 0..n_rows {
            let e = row(&mut rng);
            let b = rng.uniform(-0.5, 0.5);
            let lo = rng.uniform(-1.0, 0.0);
            let hi = lo + rng.uniform(0.0, 1.5);
            spec_rows.push((group, e, b, lo, hi));
        }
    }
    let mus: Vec<f64> = (0..counts[3])
        .map(|_| {
            if rng.int(0, 5) == 0 {
                0.0
            } else {
                rng.uniform(0.0, 1.0)
            }
        })
        .collect();
    let k: Vec<f64> = (0..vars.ndof()).map(|_| rng.uniform(-1.0, 1.0)).collect();
    let force_eps = rng.int(0, 2) == 0;
    let eps_frac = rng.uniform(0.01, 0.1);
    // Rolling contacts (drawn last, so the rest of a seed's problem is unchanged).
    let n_roll = rng.int(0, 3).saturating_sub(1);
    let mut roll_rows = Vec::new();
    for _ in 0..n_roll {
        let rows6: Vec<_> = (0..6)
            .map(|_| (row(&mut rng), rng.uniform(-0.5, 0.5)))
            .collect();
        let mu = [
            rng.uniform(0.0, 1.0),
            if rng.int(0, 3) == 0 {
                0.0
            } else {
                rng.uniform(0.0, 0.5)
            },
            if rng.int(0, 3) == 0 {
                0.0
            } else {
                rng.uniform(0.0, 0.5)
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
            .map(|_| (row(&mut rng), rng.uniform(-0.5, 0.5)))
            .collect();
        let mu = [
            rng.uniform(0.0, 1.0),
            rng.uniform(0.0, 0.5),
            rng.uniform(0.0, 0.5),
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
        p.assemble(&vars, &rows, &k).unwrap();
        p
    };
    let p = build(0.0);
    let n = dense_n(&p);
    let mean_diag = p.diag().iter().sum::<f64>() / p.n_rows() as f64;
    let eig = n.symmetric_eigenvalues();
    let (lmin, lmax) = (eig.min(), eig.max());
    if force_eps || lmin < 1e-3 * lmax {
        build(eps_frac * mean_diag)
    } else {
        p
    }
}

/// Particles on a lattice (spacing 1), frictional contacts between lattice neighbours and
/// with the ground, random small gaps `b` and random velocities.
pub fn lattice(nx: usize, ny: usize, nz: usize, seed: u64) -> CcpProblem {
    let mut rng = Rng(seed);
    let mut vars = Variables::new();
    let idx = |x: usize, y: usize, z: usize| (z * ny + y) * nx + x;
    let mut ids = Vec::new();
    for _ in 0..nx * ny * nz {
        ids.push(vars.add(MassOperator::particle(rng.uniform(0.5, 1.5)).unwrap()));
    }
    let axes: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let neg = |a: [f64; 3]| [-a[0], -a[1], -a[2]];
    let frame = |a: usize| (axes[a], axes[(a + 1) % 3], axes[(a + 2) % 3]);
    let mut rows = ConstraintRows::new();
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let i = ids[idx(x, y, z)];
                let gap = |rng: &mut Rng| rng.uniform(-0.01, 0.01);
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
            _ => unreachable!(),
        };
        kp[0] = m * rng.uniform(-0.1, 0.1);
        kp[1] = m * rng.uniform(-0.1, 0.1);
        kp[2] = m * (rng.uniform(-0.1, 0.1) - G * 0.01);
    }
    let mut problem = CcpProblem::new();
    problem.assemble(&vars, &rows, &k).unwrap();
    problem
}
