//! The matrix-free product of sphere contacts against the dense reference
//! `N = D M^-1 D' + E` on random problems.

use nalgebra::{DMatrix, DVector, Matrix3, UnitQuaternion, Vector3};
use proptest::prelude::*;

use super::*;
use crate::math::tangent_frame;

/// A random scene: `n_s` spheres (isotropic rigid bodies, random rotations), one
/// anisotropic body and a particle; contacts between random pairs (or a sphere and a fixed
/// side), most with their frames, plus a few rows without frames and a frame with wrong
/// arms (both must fall back to the explicit rows).
fn scene(seed: u64, n_s: usize, n_c: usize) -> (CcpProblem, DMatrix<f64>, usize) {
    let mut rng = crate::rng::Rng::splitmix64(seed);
    let mut vars = Variables::new();
    let mut rot = Vec::new();
    for _ in 0..n_s {
        let m = rng.range(0.5, 2.0);
        let j = rng.range(0.01, 0.1);
        vars.add(MassOperator::rigid_body(m, Matrix3::identity() * j).unwrap());
        rot.push(UnitQuaternion::from_euler_angles(
            rng.range(-3.0, 3.0),
            rng.range(-1.5, 1.5),
            rng.range(-3.0, 3.0),
        ));
    }
    let aniso = vars.add(
        MassOperator::rigid_body(1.0, Matrix3::from_diagonal(&Vector3::new(0.1, 0.2, 0.3)))
            .unwrap(),
    );
    let particle = vars.add(MassOperator::particle(0.3).unwrap());
    let mut rows = ConstraintRows::new();
    let mut dense_rows: Vec<Vec<(BlockId, Vec<f64>)>> = Vec::new();
    let mut eps_list = Vec::new();
    let mut framed = 0;
    for c in 0..n_c {
        let n = Vector3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        )
        .normalize();
        let (u, w) = tangent_frame(&n);
        let a = rng.int(0, n_s); // n_s: fixed side
        let mut b = rng.int(0, n_s - 1);
        if b == a {
            b = (b + 1) % n_s;
        }
        let side_a = (a < n_s).then_some(BlockId(a as u32));
        let side_b = Some(BlockId(b as u32));
        let arm = |rng: &mut crate::rng::Rng| {
            Vector3::new(
                rng.range(-0.1, 0.1),
                rng.range(-0.1, 0.1),
                rng.range(-0.1, 0.1),
            )
        };
        let (ra, rb) = (arm(&mut rng), arm(&mut rng));
        let mut spec = Vec::new();
        for d in [n, u, w] {
            let mut row = Vec::new();
            for (side, blk, r) in [(0, side_a, ra), (1, side_b, rb)] {
                let Some(blk) = blk else { continue };
                let ds = if side == 0 { -d } else { d };
                let q = rot[blk.0 as usize].inverse();
                let ang = (q * r).cross(&(q * ds));
                row.push((blk, vec![ds.x, ds.y, ds.z, ang.x, ang.y, ang.z]));
            }
            spec.push(row);
        }
        let ent = |k: usize| -> Vec<RowEntry<'_>> {
            spec[k]
                .iter()
                .map(|(b, c)| RowEntry {
                    block: *b,
                    coefs: c,
                })
                .collect()
        };
        let eps = [rng.range(0.0, 0.01), 0.0, 0.0];
        let id = rows.push_friction(0.5, [&ent(0), &ent(1), &ent(2)], [0.0; 3], eps);
        if c % 7 != 3 {
            // Every 11th frame lies about its arm: rejected at assembly.
            let ra_given = if c % 11 == 5 {
                ra * 1.5 + Vector3::x()
            } else {
                ra
            };
            rows.set_contact_frame(
                id,
                ContactFrame {
                    normal: n.into(),
                    blocks: [side_a, side_b],
                    arms: [ra_given.into(), rb.into()],
                },
            );
            framed += 1;
        }
        dense_rows.extend(spec);
        eps_list.extend(eps);
    }
    // A bilateral row on sphere 0, the anisotropic body and the particle: sphere 0 and its
    // contacts must use the explicit rows.
    let bil = vec![
        (BlockId(0), vec![0.3, -0.2, 0.1, 0.05, 0.0, -0.04]),
        (aniso, vec![1.0, 0.0, 0.5, 0.1, 0.2, 0.3]),
        (particle, vec![0.0, 1.0, -1.0]),
    ];
    let be: Vec<RowEntry<'_>> = bil
        .iter()
        .map(|(b, c)| RowEntry {
            block: *b,
            coefs: c,
        })
        .collect();
    rows.push_bilateral(&be, 0.0, 1e-3);
    let k: Vec<f64> = (0..vars.ndof()).map(|i| (i as f64 * 0.7).sin()).collect();
    let mut p = CcpProblem::new();
    p.assemble(&vars, &rows, &k).unwrap();
    // Dense D in assembled order: the bilateral row first.
    let m = p.n_rows();
    let mut d = DMatrix::<f64>::zeros(m, vars.ndof());
    let mut eps = vec![1e-3];
    eps.extend(eps_list);
    for (i, row) in std::iter::once(&bil).chain(&dense_rows).enumerate() {
        for (blk, c) in row {
            let off = vars.offset(*blk);
            for (j, v) in c.iter().enumerate() {
                d[(i, off + j)] += v;
            }
        }
    }
    let mut minv = DMatrix::<f64>::zeros(vars.ndof(), vars.ndof());
    for col in 0..vars.ndof() {
        let mut x = vec![0.0; vars.ndof()];
        x[col] = 1.0;
        let mut y = vec![0.0; vars.ndof()];
        vars.apply_inverse(&x, &mut y);
        minv.set_column(col, &DVector::from_column_slice(&y));
    }
    let nn = &d * minv * d.transpose() + DMatrix::from_diagonal(&DVector::from_vec(eps));
    (p, nn, framed)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// `apply_n` and `gradient` (matrix-free where frames qualify, explicit elsewhere)
    /// equal the dense `N g` (+ `r`) to a rounding bound: 1e-13 times the sum of the
    /// magnitudes of the terms.
    #[test]
    fn matrix_free_apply_n_equals_the_dense_product(
        seed in any::<u64>(),
        n_s in 2usize..40,
        n_c in 1usize..60,
    ) {
        let (p, nn, _) = scene(seed, n_s, n_c);
        let m = p.n_rows();
        let mut rng = crate::rng::Rng::splitmix64(seed ^ 0x5eed);
        let g: Vec<f64> = (0..m).map(|_| rng.range(-1.0, 1.0)).collect();
        let mut work = CcpWork::for_problem(&p);
        let mut out = vec![0.0; m];
        p.apply_n(&g, &mut out, &mut work);
        let mut grad = vec![0.0; m];
        p.gradient(&g, &mut grad, &mut work);
        let gd = DVector::from_column_slice(&g);
        let dense = &nn * &gd;
        let mag = nn.abs() * gd.abs();
        for i in 0..m {
            let bound = 1e-13 * (mag[i] + 1.0);
            prop_assert!((out[i] - dense[i]).abs() <= bound, "row {i}: {} vs {}", out[i], dense[i]);
            prop_assert!((grad[i] - dense[i] - p.r()[i]).abs() <= bound + 1e-13 * p.r()[i].abs());
        }
    }
}

/// `minv_d` equals the row-order sums of `g_i M^-1 D_i` bit for bit (each block's terms
/// in row order, zero impulses skipped), whether the problem keeps the block order (a joint
/// row on a sphere) or reads `M^-1 D` through the spheres' contact sides (friction triplets
/// on spheres only: no block order is built); some impulses zero.
#[test]
fn minv_d_equals_the_row_sums_with_or_without_the_block_order() {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for (seed, all) in [(3, false), (5, true), (9, false), (11, true)] {
        let (p, _, _) = scene(seed, 20, 30 + seed as usize);
        let mut rows = ConstraintRows::new();
        let fs = p.sections().friction.start;
        if all {
            rows = p.constraint_rows();
        } else {
            // the matrix-free triplets alone: every block with rows a pure sphere's
            for k in (0..p.sections().friction.len() / 3).filter(|&k| p.mf_contact(k).is_some()) {
                p.push_rows(fs + 3 * k..fs + 3 * k + 3, &mut rows);
            }
        }
        let mut q = CcpProblem::new();
        q.assemble(p.variables(), &rows, p.momentum()).unwrap();
        let nt = q.sections().friction.len() / 3;
        assert!(nt > 0, "seed {seed}");
        assert_eq!(q.n_matrix_free() == nt, !all, "seed {seed}");
        let g: Vec<f64> = (0..q.n_rows())
            .map(|i| {
                if i % 5 == 2 {
                    0.0
                } else {
                    (i as f64 * 0.7).sin()
                }
            })
            .collect();
        let mut want = vec![0.0; q.ndof()];
        for (i, &gi) in g.iter().enumerate() {
            if gi == 0.0 {
                continue;
            }
            for (_, off, _, minv) in q.row_entries(i) {
                for (k, m) in minv.iter().enumerate() {
                    want[off + k] += gi * m;
                }
            }
        }
        let mut v = vec![f64::NAN; q.ndof()];
        q.minv_d(&g, &mut v);
        assert_eq!(bits(&v), bits(&want), "seed {seed}, joint row {all}");
        // and `minv_d_explicit`: the same on every block but the matrix-free spheres' (0)
        let mut x = vec![f64::NAN; q.ndof()];
        q.minv_d_explicit(&g, &mut x);
        for b in 0..q.variables().len() {
            let r = q.variables().range(BlockId(b as u32));
            let (xb, vb) = (&x[r.clone()], &v[r]);
            let zero = xb.iter().all(|y| y.to_bits() == 0);
            assert!(
                bits(xb) == bits(vb) || zero,
                "seed {seed}, block {b}: {xb:?}"
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// The SIMD passes (this CPU's level) and their one-lane form give the bits of the
    /// plain scalar passes (sphere by sphere, contact by contact), for any task and run
    /// split: the product does not depend on the SIMD level.
    #[test]
    fn simd_passes_equal_the_scalar_passes_bit_for_bit(
        seed in any::<u64>(),
        n_s in 2usize..40,
        n_c in 1usize..90,
        task in 1usize..9,
    ) {
        let (p, _, _) = scene(seed, n_s, n_c);
        let mf = &p.mf;
        let mut rng = crate::rng::Rng::splitmix64(seed ^ 0xb175);
        let g: Vec<f64> = (0..p.n_rows()).map(|_| rng.range(-1.0, 1.0)).collect();
        let nw = 6 * mf.n_bodies();
        let (mut w_ref, mut w_simd, mut w_one) = (vec![0.0; nw], vec![1.0; nw], vec![2.0; nw]);
        mf.gather_reference(&g, &mut w_ref);
        mf.gather(&g, &mut w_simd);
        mf.gather_one_lane(&g, &mut w_one, task);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        prop_assert_eq!(bits(&w_ref), bits(&w_simd));
        prop_assert_eq!(bits(&w_ref), bits(&w_one));
        // The rows of runs of consecutive contacts (as laid out in a friction-only problem:
        // row data of contact `c` at `3 c..`), with and without the shift.
        let nc = mf.c_row.len();
        let eps: Vec<f64> = (0..3 * nc).map(|_| rng.range(0.0, 0.01)).collect();
        let gg: Vec<f64> = (0..3 * nc).map(|_| rng.range(-1.0, 1.0)).collect();
        let r: Vec<f64> = (0..3 * nc).map(|_| rng.range(-1.0, 1.0)).collect();
        for shift in [None, Some(&r[..])] {
            let (mut o, mut o1) = (vec![0.0; 3 * nc], vec![0.0; 3 * nc]);
            let mut c0 = 0;
            while c0 < nc {
                let len = (task * 5).min(nc - c0);
                let rr = 3 * c0..3 * (c0 + len);
                let rows = |out| frames_simd::RowData {
                    eps: &eps[rr.clone()],
                    g: &gg[rr.clone()],
                    shift: shift.map(|x| &x[rr.clone()]),
                    out,
                };
                let of: Vec<u32> = (c0 as u32..(c0 + len) as u32).collect();
                mf.triplets_task(&w_ref, &of, rows(&mut o[rr.clone()]), |_, _| unreachable!());
                mf.triplet_one_lane(&w_ref, c0, rows(&mut o1[rr.clone()]));
                c0 += len;
            }
            for c in 0..nc {
                let d = mf.triplet(c, &w_ref);
                for k in 0..3 {
                    let i = 3 * c + k;
                    let x = d[k] + eps[i] * gg[i];
                    let want = shift.map_or(x, |r| x + r[i]);
                    prop_assert_eq!(want.to_bits(), o[i].to_bits());
                    prop_assert_eq!(want.to_bits(), o1[i].to_bits());
                }
            }
        }
    }
}

#[test]
fn frames_qualify_only_where_they_match_and_survive_a_rebuild() {
    let (p, _, framed) = scene(7, 30, 30);
    // Wrong arms and the contacts of sphere 0 are left out; most framed contacts qualify.
    let used = p.n_matrix_free();
    assert!(used > 0 && used < framed, "{used} of {framed}");
    let mut q = CcpProblem::new();
    q.assemble(p.variables(), &p.constraint_rows(), p.momentum())
        .unwrap();
    assert_eq!(q.n_matrix_free(), used);
    let g: Vec<f64> = (0..p.n_rows()).map(|i| (i as f64 * 0.3).cos()).collect();
    let (mut a, mut b) = (vec![0.0; g.len()], vec![0.0; g.len()]);
    p.apply_n(&g, &mut a, &mut CcpWork::for_problem(&p));
    q.apply_n(&g, &mut b, &mut CcpWork::for_problem(&q));
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a), bits(&b));
}

#[test]
fn frames_survive_a_problem_file_bit_for_bit() {
    let (p, _, _) = scene(11, 30, 40);
    assert!(p.n_matrix_free() > 0);
    let g: Vec<f64> = (0..p.n_rows()).map(|i| (i as f64 * 0.7).sin()).collect();
    let mut a = vec![0.0; g.len()];
    p.apply_n(&g, &mut a, &mut CcpWork::for_problem(&p));
    let file = ProblemFile::from_problem(&p, "frames");
    let dir = std::env::temp_dir();
    for (name, format) in [
        ("chrono_frames_test.ccp", ProblemFormat::Binary),
        ("chrono_frames_test.json", ProblemFormat::Json),
    ] {
        let path = dir.join(format!("{}_{name}", std::process::id()));
        file.save(&path, format).unwrap();
        let q = ProblemFile::load_problem(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(q.n_matrix_free(), p.n_matrix_free());
        let mut b = vec![0.0; g.len()];
        q.apply_n(&g, &mut b, &mut CcpWork::for_problem(&q));
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a), bits(&b), "{name}");
    }
}

/// The held sub-problem of every other contact: its variables compacted to the bodies its
/// rows touch, the sphere frames kept (renumbered), `N_RR x` and `r_R + N_RO g_O` equal to
/// the dense reference (to 1e-12 of the sum of the terms' magnitudes), an update equal to a
/// fresh build bit for bit, bad row lists and `gamma` lengths named.
#[test]
fn held_subproblem_compacts_keeps_frames_and_updates_bit_for_bit() {
    let (p, nn, _) = scene(5, 30, 40);
    let m = p.n_rows();
    let fr = p.sections().friction.clone();
    let rows: Vec<usize> = fr.clone().step_by(6).flat_map(|i| i..i + 3).collect();
    let g: Vec<f64> = (0..m)
        .map(|i| 0.1 * (i as f64 * 0.37).sin().abs())
        .collect();
    let mut h = HeldSubproblem::new();
    h.build(&p, &rows, &g).unwrap();
    let sub = h.problem();
    assert_eq!(h.rows(), &rows[..]);
    assert!(sub.variables().len() < p.variables().len());
    assert!(sub.n_matrix_free() > 0, "frames lost");
    let x: Vec<f64> = (0..rows.len()).map(|j| (j as f64 * 0.9).cos()).collect();
    let mut y = vec![0.0; rows.len()];
    sub.apply_n(&x, &mut y, &mut CcpWork::for_problem(sub));
    for (a, &i) in rows.iter().enumerate() {
        let terms: Vec<f64> = rows
            .iter()
            .enumerate()
            .map(|(b, &j)| nn[(i, j)] * x[b])
            .collect();
        let bound = 1e-12 * terms.iter().map(|t| t.abs()).sum::<f64>().max(1e-300);
        assert!(
            (y[a] - terms.iter().sum::<f64>()).abs() <= bound,
            "N x row {i}"
        );
        let held: Vec<f64> = (0..m)
            .filter(|j| !rows.contains(j))
            .map(|j| nn[(i, j)] * g[j])
            .collect();
        let expect = p.r()[i] + held.iter().sum::<f64>();
        let bound = 1e-12 * (p.r()[i].abs() + held.iter().map(|t| t.abs()).sum::<f64>());
        assert!((sub.r()[a] - expect).abs() <= bound, "r row {i}");
    }
    let g2: Vec<f64> = g.iter().map(|v| 2.0 * v + 0.01).collect();
    h.update(&p, &g2).unwrap();
    let mut fresh = HeldSubproblem::new();
    fresh.build(&p, &rows, &g2).unwrap();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(h.problem().r()), bits(fresh.problem().r()));
    let e = h.build(&p, &rows[1..], &g).unwrap_err().to_string();
    assert!(e.contains("subproblem rows"), "{e}");
    let e = h.build(&p, &rows, &g[1..]).unwrap_err().to_string();
    assert!(e.contains("gamma.len()"), "{e}");
}

/// `assemble_taking` gives `assemble`'s problem bit for bit: a single group (its arrays
/// swapped in), two groups (copied), and again into the same problem (whose old arrays
/// went to the rows: nothing stale is read); the rows are left empty.
#[test]
fn assemble_taking_equals_assemble_bit_for_bit() {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let same = |a: &CcpProblem, b: &CcpProblem| {
        assert_eq!(a.n_rows(), b.n_rows());
        assert_eq!(a.n_matrix_free(), b.n_matrix_free());
        assert_eq!(bits(a.r()), bits(b.r()));
        assert_eq!(bits(a.diag()), bits(b.diag()));
        assert_eq!(bits(a.scales()), bits(b.scales()));
        for i in 0..a.n_rows() {
            let ea: Vec<_> = a.row_entries(i).collect();
            let eb: Vec<_> = b.row_entries(i).collect();
            assert_eq!(ea.len(), eb.len());
            for (x, y) in ea.iter().zip(&eb) {
                assert_eq!((x.0, x.1), (y.0, y.1));
                assert_eq!((bits(x.2), bits(x.3)), (bits(y.2), bits(y.3)));
            }
        }
        let g: Vec<f64> = (0..a.n_rows()).map(|i| (i as f64 * 0.3).cos()).collect();
        let (mut x, mut y) = (vec![0.0; g.len()], vec![0.0; g.len()]);
        a.apply_n(&g, &mut x, &mut CcpWork::for_problem(a));
        b.apply_n(&g, &mut y, &mut CcpWork::for_problem(b));
        assert_eq!(bits(&x), bits(&y));
        let (mut v, mut w) = (vec![0.0; a.ndof()], vec![0.0; b.ndof()]);
        a.velocities(&g, &mut v);
        b.velocities(&g, &mut w);
        assert_eq!(bits(&v), bits(&w));
    };
    let mut taken = CcpProblem::new();
    for (seed, all) in [(3, false), (5, true), (9, false)] {
        let (p, _, _) = scene(seed, 20, 30 + seed as usize);
        // The friction triplets alone (one group) or with the scene's joint row.
        let mut rows = ConstraintRows::new();
        if all {
            rows = p.constraint_rows();
        } else {
            p.push_rows(p.sections().friction.clone(), &mut rows);
        }
        let groups = (0..N_GROUPS)
            .filter(|&g| rows.groups[g].n_rows() > 0)
            .count();
        assert_eq!(groups, if all { 2 } else { 1 }, "seed {seed}");
        let mut fresh = CcpProblem::new();
        fresh.assemble(p.variables(), &rows, p.momentum()).unwrap();
        taken
            .assemble_taking(p.variables(), &mut rows, p.momentum())
            .unwrap();
        assert_eq!(rows.total_rows(), 0, "seed {seed}: rows not emptied");
        same(&fresh, &taken);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// A fused triplet's three dot products and three `M^-1 D` updates are the bits of
    /// the row-by-row methods, also through a window of the dof vector; triplets on the
    /// particle or the bilateral-touched sphere are fused only where their rows allow.
    #[test]
    fn fused_triplets_match_the_row_by_row_path(
        seed in any::<u64>(),
        n_s in 2usize..30,
        n_c in 1usize..60,
    ) {
        let (p, _, _) = scene(seed, n_s, n_c);
        let mut rng = crate::rng::Rng::splitmix64(seed ^ 0xf05e);
        let w: Vec<f64> = (0..p.ndof()).map(|_| rng.range(-1.0, 1.0)).collect();
        let fr = p.sections().friction.clone();
        let mut fused = 0;
        for t in fr.step_by(3) {
            let Some(f) = p.fused_triplet(t) else { continue };
            fused += 1;
            let dots = p.fused_dots_in(&f, &w, 0);
            for r in 0..3 {
                prop_assert_eq!(dots[r].to_bits(), p.row_dot(t + r, &w).to_bits());
            }
            // through the window from the triplet's lowest dof
            let lo = p.row_entries(t).map(|(_, off, _, _)| off).min().unwrap_or(0);
            prop_assert_eq!(p.fused_dots_in(&f, &w[lo..], lo), dots);
            let mut dg = [rng.range(-1.0, 1.0), 0.0, rng.range(-1.0, 1.0)];
            if t % 2 == 0 {
                dg[1] = rng.range(-1.0, 1.0);
            }
            let (mut a, mut b) = (w.clone(), w.clone());
            p.fused_add_minv_in(&f, &dg, &mut a[lo..], lo);
            for r in 0..3 {
                if dg[r] != 0.0 {
                    p.row_add_minv(t + r, dg[r], &mut b);
                }
            }
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            prop_assert_eq!(bits(&a), bits(&b));
        }
        prop_assert!(fused > 0 || n_c < 3, "no triplet fused");
    }

    /// One contact at a time on the pure spheres' world-frame velocities
    /// (`mf_dots_in`, `mf_add_in`, `mf_gather`): the rows of the dense `N g`, and an
    /// impulse change moves the velocities as gathering the changed impulses does.
    #[test]
    fn matrix_free_contacts_one_at_a_time_equal_the_dense_product(
        seed in any::<u64>(),
        n_s in 2usize..30,
        n_c in 1usize..60,
    ) {
        let (p, nn, _) = scene(seed, n_s, n_c);
        let m = p.n_rows();
        let mut rng = crate::rng::Rng::splitmix64(seed ^ 0x3a11);
        let g: Vec<f64> = (0..m).map(|_| rng.range(-1.0, 1.0)).collect();
        let mut ws = vec![0.0; 6 * p.mf_spheres()];
        p.mf_gather(&g, &mut ws);
        let gd = DVector::from_column_slice(&g);
        let dense = &nn * &gd;
        let mag = nn.abs() * gd.abs();
        let fr = p.sections().friction.clone();
        for (k, t) in fr.step_by(3).enumerate() {
            let Some(c) = p.mf_contact(k) else { continue };
            // the contact's block of N (with its compliance) against the dense one
            let b = p.mf_sphere_contact(c).block();
            let diag = p.mf_sphere_contact(c).block_diagonal();
            prop_assert_eq!([b[0], b[3], b[5]].map(f64::to_bits), diag.map(f64::to_bits));
            let mut q = 0;
            for i in 0..3 {
                for j in i..3 {
                    let e = if i == j { p.eps()[t + i] } else { 0.0 };
                    let want = nn[(t + i, t + j)];
                    prop_assert!((b[q] + e - want).abs() <= 1e-12 * (1.0 + want.abs()), "block {i}{j}: {} vs {want}", b[q] + e);
                    q += 1;
                }
            }
            let d = p.mf_dots_in(c, &ws, 0);
            for r in 0..3 {
                let got = d[r] + p.eps()[t + r] * g[t + r];
                let bound = 1e-13 * (mag[t + r] + 1.0);
                prop_assert!((got - dense[t + r]).abs() <= bound, "row {}: {} vs {}", t + r, got, dense[t + r]);
            }
            let dg = [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)];
            let mut moved = ws.clone();
            p.mf_add_in(c, &dg, &mut moved, 0);
            let mut g2 = g.clone();
            for r in 0..3 {
                g2[t + r] += dg[r];
            }
            let mut want = vec![0.0; ws.len()];
            p.mf_gather(&g2, &mut want);
            for (a, b) in moved.iter().zip(&want) {
                prop_assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{} vs {}", a, b);
            }
        }
        // the spheres are numbered in block order: the count below a block is monotone
        let nb = p.variables().len();
        let counts: Vec<usize> = (0..=nb).map(|b| p.mf_spheres_before(b)).collect();
        prop_assert!(counts.windows(2).all(|w| w[0] <= w[1]));
        prop_assert_eq!(counts[nb], p.mf_spheres());
    }
}
