//! Tests of the assembled problem: storage against a dense reference, the cached blocks,
//! sub-problems, row reconstruction and errors.

use nalgebra::{DMatrix, DVector, Matrix3};

use super::*;

/// Two rigid bodies and a particle; one row of every group, a friction triplet and a
/// rolling contact, with compliance on some rows.
pub(super) fn sample() -> (CcpProblem, DMatrix<f64>, DMatrix<f64>, Vec<f64>) {
    let mut vars = Variables::new();
    let j = Matrix3::new(0.4, 0.02, 0.0, 0.02, 0.3, 0.01, 0.0, 0.01, 0.5);
    let a = vars.add(MassOperator::rigid_body(2.0, j).unwrap());
    let b = vars.add(MassOperator::rigid_body(1.5, j * 2.0).unwrap());
    let p = vars.add(MassOperator::particle(0.7).unwrap());
    let coef = |k: usize, n: usize| -> Vec<f64> {
        (0..n)
            .map(|i| ((i * 7 + k * 3) as f64 * 0.37).sin())
            .collect()
    };
    let rows_spec: Vec<Vec<(BlockId, Vec<f64>)>> = (0..12)
        .map(|k| match k % 3 {
            0 => vec![(a, coef(k, 6)), (b, coef(k + 20, 6))],
            1 => vec![(b, coef(k, 6)), (p, coef(k + 20, 3))],
            _ => vec![(p, coef(k, 3)), (a, coef(k + 20, 6))],
        })
        .collect();
    let e = |k: usize| -> Vec<RowEntry<'_>> {
        rows_spec[k]
            .iter()
            .map(|(blk, c)| RowEntry {
                block: *blk,
                coefs: c,
            })
            .collect()
    };
    let mut rows = ConstraintRows::new();
    // pushed out of group order on purpose
    rows.push_rolling_friction(
        [0.5, 0.1, 0.05],
        [&e(6), &e(7), &e(8), &e(9), &e(10), &e(11)],
        [0.01, 0.0, 0.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1e-3, 1e-3, 1e-3],
    );
    rows.push_unilateral(&e(0), -0.02, 0.0);
    rows.push_bilateral(&e(1), 0.03, 1e-2);
    rows.push_box(&e(2), 0.0, 0.0, -0.5, 0.5);
    rows.push_friction(0.3, [&e(3), &e(4), &e(5)], [0.0; 3], [0.0; 3]);
    let k: Vec<f64> = (0..vars.ndof()).map(|i| (i as f64 * 0.9).cos()).collect();
    let mut prob = CcpProblem::new();
    prob.assemble(&vars, &rows, &k).unwrap();
    // Dense D (rows in assembled order: bilateral, box, unilateral, friction, rolling).
    let order = [1, 2, 0, 3, 4, 5, 6, 7, 8, 9, 10, 11];
    let mut d = DMatrix::zeros(12, vars.ndof());
    for (i, &src) in order.iter().enumerate() {
        for (blk, c) in &rows_spec[src] {
            let off = vars.offset(*blk);
            for (jj, v) in c.iter().enumerate() {
                d[(i, off + jj)] += v;
            }
        }
    }
    let mut minv = DMatrix::zeros(vars.ndof(), vars.ndof());
    for col in 0..vars.ndof() {
        let mut x = vec![0.0; vars.ndof()];
        x[col] = 1.0;
        let mut y = vec![0.0; vars.ndof()];
        vars.apply_inverse(&x, &mut y);
        for r in 0..vars.ndof() {
            minv[(r, col)] = y[r];
        }
    }
    let eps = [
        1e-2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1e-3, 1e-3, 1e-3,
    ];
    let n = &d * &minv * d.transpose() + DMatrix::from_diagonal(&DVector::from_column_slice(&eps));
    (prob, n, d, k)
}

#[test]
fn apply_n_entries_and_blocks_match_the_dense_matrix() {
    let (p, n, _, _) = sample();
    assert_eq!(p.sections().rolling, 6..12);
    let mut work = CcpWork::for_problem(&p);
    let g: Vec<f64> = (0..12).map(|i| (i as f64 * 1.3).sin()).collect();
    let mut out = vec![0.0; 12];
    p.apply_n(&g, &mut out, &mut work);
    let dense = &n * DVector::from_column_slice(&g);
    for i in 0..12 {
        assert!((out[i] - dense[i]).abs() < 1e-12, "row {i}");
        for j in 0..12 {
            assert!((p.n_entry(i, j) - n[(i, j)]).abs() < 1e-12, "N[{i},{j}]");
        }
        assert!((p.diag()[i] - n[(i, i)]).abs() < 1e-12);
    }
    let t = p.cone_block(3).unwrap();
    assert_eq!(t.len(), 6);
    assert!((t[upper_index(3, 1, 2)] - n[(4, 5)]).abs() < 1e-12);
    let r = p.cone_block(6).unwrap();
    assert_eq!(r.len(), 21);
    assert!((r[upper_index(6, 2, 5)] - n[(8, 11)]).abs() < 1e-12);
    assert!(p.cone_block(4).is_none());
    // cone-averaged scale
    let mean: f64 = (6..12).map(|i| n[(i, i)]).sum::<f64>() / 6.0;
    assert!((p.residual_scale(7) - 1.0 / mean).abs() < 1e-12);
}

#[test]
fn row_entries_rebuild_the_off_diagonal_of_n() {
    // N_ij (i != j) = sum over the blocks both rows touch of D_i' (M^-1 D_j): from the
    // rows' two coefficient sets alone.
    let (p, n, _, _) = sample();
    for i in 0..p.n_rows() {
        for j in 0..p.n_rows() {
            if i == j {
                continue;
            }
            let mut s = 0.0;
            for (bi, oi, d, _) in p.row_entries(i) {
                for (bj, oj, _, md) in p.row_entries(j) {
                    if bi == bj {
                        assert_eq!(oi, oj);
                        s += d.iter().zip(md).map(|(a, b)| a * b).sum::<f64>();
                    }
                }
            }
            assert!((s - n[(i, j)]).abs() < 1e-12, "N[{i},{j}]");
        }
    }
}

#[test]
fn split_product_with_added_rows_matches_the_dense_matrix() {
    // The two halves of a product with some rows' impulses added in between (a Schur
    // solver's joint rows): `N g` of the whole `g`, whatever rows are added late.
    let (p, n, _, _) = sample();
    let mut work = CcpWork::for_problem(&p);
    let g: Vec<f64> = (0..12).map(|i| (i as f64 * 0.7 + 0.2).cos()).collect();
    let dense = &n * DVector::from_column_slice(&g);
    for late in [vec![], vec![0], vec![0, 1, 2], (0..12).collect::<Vec<_>>()] {
        let mut early = g.clone();
        for &i in &late {
            early[i] = 0.0;
        }
        p.velocity_changes_of(&early, &mut work);
        for &i in &late {
            p.add_row_velocity(i, g[i], &mut work);
        }
        let mut out = vec![f64::NAN; 12];
        p.rows_from_velocity(&g, &work, &mut out, None);
        for i in 0..12 {
            assert!(
                (out[i] - dense[i]).abs() < 1e-12,
                "rows {late:?} late: row {i}"
            );
        }
        // With the shift: the gradient.
        p.rows_from_velocity(&g, &work, &mut out, Some(p.r()));
        for i in 0..12 {
            assert!(
                (out[i] - dense[i] - p.r()[i]).abs() < 1e-12,
                "gradient row {i}"
            );
        }
    }
    // Nothing added late: the same bits as `apply_n`.
    let mut a = vec![0.0; 12];
    p.apply_n(&g, &mut a, &mut work);
    p.velocity_changes_of(&g, &mut work);
    let mut b = vec![0.0; 12];
    p.rows_from_velocity(&g, &work, &mut b, None);
    assert_eq!(a, b);
}

#[test]
fn rows_except_bilateral_leave_the_joint_rows_and_match_the_others_bit_for_bit() {
    // The sample's one bilateral row is row 0 (assembled order: bilateral first).
    let (p, _, _, _) = sample();
    assert_eq!(p.sections().bilateral, 0..1);
    let mut work = CcpWork::for_problem(&p);
    let g: Vec<f64> = (0..12).map(|i| (i as f64 * 0.3 - 1.1).sin()).collect();
    p.velocity_changes_of(&g, &mut work);
    for shift in [None, Some(p.r())] {
        let mut all = vec![0.0; 12];
        p.rows_from_velocity(&g, &work, &mut all, shift);
        let mut some = vec![7.5; 12];
        p.rows_from_velocity_except_bilateral(&g, &work, &mut some, shift);
        assert_eq!(some[0], 7.5, "the bilateral row is left as it was");
        assert_eq!(some[1..], all[1..], "the other rows: the same bits");
    }
}

#[test]
fn packed_rows_give_the_bits_of_the_problems_row_operations() {
    // The sample has rows on two rigid bodies (packed) and rows touching the particle
    // (3 dof: used through the problem); every row, in a shuffled order.
    let (p, _, _, _) = sample();
    let rows: Vec<usize> = (0..12).map(|k| (5 * k + 3) % 12).collect();
    let mut packed = super::PackedRows::default();
    packed.pack(&p, &rows);
    assert_eq!(packed.len(), 12);
    let v: Vec<f64> = (0..p.ndof())
        .map(|i| (i as f64 * 0.41 + 0.3).sin())
        .collect();
    for (k, &i) in rows.iter().enumerate() {
        assert_eq!(packed.dot(&p, k, &v).to_bits(), p.row_dot(i, &v).to_bits());
        let mut a = v.clone();
        let mut b = v.clone();
        packed.add_minv(&p, k, -0.7, &mut a);
        p.row_add_minv(i, -0.7, &mut b);
        assert_eq!(a, b, "row {i}");
    }
}

#[test]
fn r_and_velocities_match_the_definitions() {
    let (p, _, d, k) = sample();
    let mut vfree = vec![0.0; p.ndof()];
    p.variables().apply_inverse(&k, &mut vfree);
    let r = DVector::from_column_slice(p.b()) + &d * DVector::from_column_slice(&vfree);
    for i in 0..12 {
        assert!((p.r()[i] - r[i]).abs() < 1e-12);
    }
}

#[test]
fn rebuilt_rows_reassemble_bit_for_bit() {
    let (p, _, _, _) = sample();
    let mut q = CcpProblem::new();
    q.assemble(p.variables(), &p.constraint_rows(), p.momentum())
        .unwrap();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(q.r()), bits(p.r()));
    assert_eq!(bits(q.diag()), bits(p.diag()));
    assert_eq!(q.rolling_mu(), p.rolling_mu());
    assert_eq!(q.sections(), p.sections());
}

#[test]
fn subproblem_holds_the_other_rows_fixed() {
    let (p, n, _, _) = sample();
    let g: Vec<f64> = (0..12).map(|i| 0.1 * (i as f64 + 1.0)).collect();
    let mut sub = CcpProblem::new();
    p.subproblem(0..3, &g, &mut sub).unwrap();
    assert_eq!(sub.n_rows(), 3);
    // r_sub = r_R + N_RO g_O
    for i in 0..3 {
        let expect = p.r()[i] + (3..12).map(|j| n[(i, j)] * g[j]).sum::<f64>();
        assert!((sub.r()[i] - expect).abs() < 1e-12, "row {i}");
    }
    let e = p.subproblem(0..4, &g, &mut sub).unwrap_err().to_string();
    assert!(e.contains("cut"), "{e}");
}

#[test]
fn subproblem_of_a_row_list_keeps_n_and_holds_the_rest() {
    let (p, n, _, _) = sample();
    let g: Vec<f64> = (0..12).map(|i| 0.1 * (i as f64 + 1.0)).collect();
    // Bilateral row 0 and the rolling contact 6..12: not contiguous.
    let rows: Vec<usize> = [0].into_iter().chain(6..12).collect();
    let mut sub = CcpProblem::new();
    p.subproblem_rows(&rows, &g, &mut sub).unwrap();
    assert_eq!(sub.n_rows(), rows.len());
    assert_eq!(sub.sections().bilateral, 0..1);
    assert_eq!(sub.sections().rolling, 1..7);
    for (a, &i) in rows.iter().enumerate() {
        for (b, &j) in rows.iter().enumerate() {
            assert!(
                (sub.n_entry(a, b) - p.n_entry(i, j)).abs() < 1e-12,
                "N[{i},{j}]"
            );
        }
        let held: f64 = (0..12)
            .filter(|j| !rows.contains(j))
            .map(|j| n[(i, j)] * g[j])
            .sum();
        assert!((sub.r()[a] - (p.r()[i] + held)).abs() < 1e-12, "row {i}");
    }
    // A contiguous list gives the range's sub-problem bit for bit.
    let mut by_range = CcpProblem::new();
    p.subproblem(3..6, &g, &mut by_range).unwrap();
    p.subproblem_rows(&[3, 4, 5], &g, &mut sub).unwrap();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(sub.r()), bits(by_range.r()));
    for bad in [&[3, 4][..], &[4, 5, 6], &[1, 0], &[12]] {
        let e = p
            .subproblem_rows(bad, &g, &mut sub)
            .unwrap_err()
            .to_string();
        assert!(e.contains("subproblem rows"), "{e}");
    }
}

#[test]
fn bad_rows_are_errors_naming_the_field() {
    let mut vars = Variables::new();
    let a = vars.add(MassOperator::particle(1.0).unwrap());
    let c = [0.0, 0.0, 1.0];
    let e = [RowEntry {
        block: a,
        coefs: &c,
    }];
    let mut rows = ConstraintRows::new();
    rows.push_rolling_friction(
        [0.5, -0.1, 0.0],
        [&e, &e, &e, &e, &e, &e],
        [0.0; 6],
        [0.0; 6],
    );
    let err = CcpProblem::new()
        .assemble(&vars, &rows, &[0.0; 3])
        .unwrap_err()
        .to_string();
    assert!(err.contains("rolling") && err.contains("mu"), "{err}");
    let mut tiny = Variables::new();
    tiny.add(MassOperator::particle(1e-300).unwrap());
    let err = CcpProblem::new()
        .assemble(&tiny, &ConstraintRows::new(), &[1e300, 0.0, 0.0])
        .unwrap_err()
        .to_string();
    assert!(err.contains("M^-1 k"), "{err}");
}

/// Many rows (the checks run in parallel): the error names the first bad row in row order
/// and its first bad field, as the serial checks do.
#[test]
fn the_first_bad_row_of_many_is_named() {
    let mut vars = Variables::new();
    let a = vars.add(MassOperator::particle(1.0).unwrap());
    let n = 9000;
    for (bad_rows, want) in [
        (vec![(7000, 1), (8000, 0)], "rows.bilateral[7000].coefs[1]"),
        (vec![(8999, 2), (6000, 4)], "rows.bilateral[6000].b"),
        (vec![(4500, 5)], "rows.bilateral[4500].eps"),
        (vec![(8500, 6), (5000, 7)], "rows.bilateral[5000]"),
        (vec![(4200, 8)], "rows.bilateral[4200].coefs.len()"),
    ] {
        let mut rows = ConstraintRows::new();
        for i in 0..n {
            let mut c = [0.0, 0.0, 1.0];
            let (mut b, mut eps, mut block, mut len) = (0.0, -0.0, a, 3);
            for &(r, what) in &bad_rows {
                if r == i {
                    match what {
                        0..=2 => c[what] = f64::NAN,
                        4 => b = f64::INFINITY,
                        5 => eps = -1.0,
                        6 => eps = f64::NAN,
                        7 => block = BlockId(3),
                        _ => len = 2,
                    }
                }
            }
            let e = [RowEntry {
                block,
                coefs: &c[..len],
            }];
            rows.push_bilateral(&e, b, eps);
        }
        let err = CcpProblem::new()
            .assemble(&vars, &rows, &[0.0; 3])
            .unwrap_err()
            .to_string();
        assert!(err.contains(want), "{err} (want {want})");
    }
    // and the same many rows, all good (`eps = -0.0` among them), assemble
    let mut rows = ConstraintRows::new();
    for i in 0..n {
        let c = [0.0, 1.0, i as f64];
        let e = [RowEntry {
            block: a,
            coefs: &c,
        }];
        rows.push_bilateral(&e, 0.5, if i % 2 == 0 { -0.0 } else { 1e-6 });
    }
    CcpProblem::new().assemble(&vars, &rows, &[0.0; 3]).unwrap();
}

/// A coupled 5-dof SPD block and a particle, rows touching both: `N` against the dense
/// definition, `v+ = H^-1 (k + D g)`, and a file round trip (the block is saved densely).
#[test]
fn coupled_block_in_the_problem() {
    use std::sync::Arc;
    let n = 5;
    let h = DMatrix::from_fn(n, n, |i, j| {
        if i == j {
            3.0 + i as f64
        } else {
            0.4 / (1.0 + (i as f64 - j as f64).abs())
        }
    });
    let op = Arc::new(DenseMass::new(h.clone()).unwrap());
    let mut vars = Variables::new();
    let c = vars.add(MassOperator::coupled(op).unwrap());
    let p = vars.add(MassOperator::particle(0.7).unwrap());
    let coef = |k: usize, m: usize| -> Vec<f64> {
        (0..m)
            .map(|i| ((i * 5 + k * 3) as f64 * 0.41).sin())
            .collect()
    };
    let spec: Vec<(Vec<f64>, Vec<f64>)> = (0..4).map(|k| (coef(k, n), coef(k + 9, 3))).collect();
    let mut rows = ConstraintRows::new();
    for (i, (cc, cp)) in spec.iter().enumerate() {
        let e = [
            RowEntry {
                block: c,
                coefs: cc,
            },
            RowEntry {
                block: p,
                coefs: cp,
            },
        ];
        if i < 2 {
            rows.push_bilateral(&e, 0.01 * i as f64, 0.0);
        } else {
            rows.push_unilateral(&e, -0.02, 1e-3);
        }
    }
    let k: Vec<f64> = (0..vars.ndof()).map(|i| (i as f64 * 0.7).cos()).collect();
    let mut prob = CcpProblem::new();
    prob.assemble(&vars, &rows, &k).unwrap();

    let mut d = DMatrix::zeros(4, n + 3);
    for (i, (cc, cp)) in spec.iter().enumerate() {
        for j in 0..n {
            d[(i, j)] = cc[j];
        }
        for j in 0..3 {
            d[(i, n + j)] = cp[j];
        }
    }
    let mut minv = DMatrix::zeros(n + 3, n + 3);
    minv.view_mut((0, 0), (n, n))
        .copy_from(&h.clone().try_inverse().unwrap());
    for j in 0..3 {
        minv[(n + j, n + j)] = 1.0 / 0.7;
    }
    let eps = DVector::from_column_slice(&[0.0, 0.0, 1e-3, 1e-3]);
    let dense_n = &d * &minv * d.transpose() + DMatrix::from_diagonal(&eps);
    let g = [0.3, -0.2, 0.5, 0.1];
    let mut out = [0.0; 4];
    let mut work = CcpWork::for_problem(&prob);
    prob.apply_n(&g, &mut out, &mut work);
    let want = &dense_n * DVector::from_column_slice(&g);
    for i in 0..4 {
        assert!((out[i] - want[i]).abs() < 1e-12, "row {i}");
    }
    let mut v = vec![0.0; n + 3];
    prob.velocities(&g, &mut v);
    let kv = DVector::from_column_slice(&k) + d.transpose() * DVector::from_column_slice(&g);
    let want = &minv * kv;
    for i in 0..n + 3 {
        assert!((v[i] - want[i]).abs() < 1e-12, "dof {i}");
    }

    let dir = std::env::temp_dir();
    for ext in ["json", "bin"] {
        let path = dir.join(format!("chrono-core-coupled-{}.{ext}", std::process::id()));
        ProblemFile::save_problem(&prob, "coupled", &path).unwrap();
        let q = ProblemFile::load_problem(&path).unwrap();
        std::fs::remove_file(&path).ok();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(q.r()), bits(prob.r()), "{ext}");
        assert_eq!(bits(q.diag()), bits(prob.diag()), "{ext}");
    }
}

/// Two 1-dof scalar blocks (shaft inertias) and a gear row `w_a - 3 w_b = 0`: `diag(N)`
/// is `1/J_a + 9/J_b`, `r` is the free row velocity, and a file round trip keeps the
/// scalar blocks as scalar blocks, bit for bit.
#[test]
fn scalar_blocks_in_the_problem_and_in_files() {
    let (ja, jb) = (0.5, 2.0);
    let mut vars = Variables::new();
    let a = vars.add(MassOperator::scalar(ja).unwrap());
    let b = vars.add(MassOperator::scalar(jb).unwrap());
    let mut rows = ConstraintRows::new();
    rows.push_bilateral(
        &[
            RowEntry {
                block: a,
                coefs: &[1.0],
            },
            RowEntry {
                block: b,
                coefs: &[-3.0],
            },
        ],
        0.0,
        0.0,
    );
    let k = [ja * 2.0, jb * 1.0];
    let mut prob = CcpProblem::new();
    prob.assemble(&vars, &rows, &k).unwrap();
    assert_eq!(prob.ndof(), 2);
    assert!((prob.diag()[0] - (1.0 / ja + 9.0 / jb)).abs() < 1e-15);
    assert!((prob.r()[0] - (2.0 - 3.0 * 1.0)).abs() < 1e-15);
    let dir = std::env::temp_dir();
    for ext in ["json", "bin"] {
        let path = dir.join(format!("chrono-core-scalar-{}.{ext}", std::process::id()));
        ProblemFile::save_problem(&prob, "scalar", &path).unwrap();
        let q = ProblemFile::load_problem(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(q.variables(), prob.variables(), "{ext}");
        assert_eq!(q.r()[0].to_bits(), prob.r()[0].to_bits(), "{ext}");
    }
}

/// The rows of [`spans_and_batches`]: 70 rows on a 12-dof coupled block `A` (more than one
/// batch of columns of `H^-1 D`), each also on one of two rigid bodies, every seventh on a
/// second coupled block `B` (9 dof). `A`'s coefficients are sparse with the span at the
/// start, at the end, a single one, none (an empty span) or two with zeros between.
/// With `turned`, the single and the empty ones move (the same layout, other spans: a
/// mesh node's row after the mesh turned).
fn span_rows(turned: bool) -> Vec<Vec<(usize, Vec<f64>)>> {
    let val = |k: usize, p: usize| 0.5 + ((k * 7 + p * 3) as f64 * 0.37).sin().abs();
    (0..70)
        .map(|k| {
            let mut a = vec![0.0; 12];
            let at: Vec<usize> = match (k % 5, turned) {
                (0, _) => vec![0, 1, 2],
                (1, _) => vec![9, 10, 11],
                (2, false) => vec![k % 12],
                (2, true) => vec![(k + 5) % 12],
                (3, false) => vec![],
                (3, true) => vec![11],
                _ => vec![3, 7],
            };
            for p in at {
                a[p] = val(k, p);
            }
            let sign = if k % 3 == 0 { -1.0 } else { 1.0 };
            let body: Vec<f64> = (0..6).map(|p| sign * val(k + 100, p)).collect();
            let mut row = vec![(0, a), (2 + k % 2, body)];
            if k % 7 == 0 {
                let mut b = vec![0.0; 9];
                b[k % 9] = val(k + 200, 0);
                row.push((1, b));
            }
            row
        })
        .collect()
}

/// Problem of [`span_rows`]: blocks `A`, `B` (coupled), two rigid bodies; rows 0..35
/// bilateral, the rest unilateral with compliance (assembled in push order). Returns the
/// problem and the dense `D`.
fn span_problem(turned: bool) -> (CcpProblem, DMatrix<f64>) {
    use std::sync::Arc;
    let spd = |n: usize, s: f64| {
        DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                s + i as f64
            } else {
                0.4 / (1.0 + (i as f64 - j as f64).abs())
            }
        })
    };
    let mut vars = Variables::new();
    let mut blocks = vec![
        vars.add(MassOperator::coupled(Arc::new(DenseMass::new(spd(12, 3.0)).unwrap())).unwrap()),
        vars.add(MassOperator::coupled(Arc::new(DenseMass::new(spd(9, 2.0)).unwrap())).unwrap()),
    ];
    let j = Matrix3::new(0.4, 0.02, 0.0, 0.02, 0.3, 0.01, 0.0, 0.01, 0.5);
    blocks.push(vars.add(MassOperator::rigid_body(2.0, j).unwrap()));
    blocks.push(vars.add(MassOperator::rigid_body(1.5, j * 2.0).unwrap()));
    let spec = span_rows(turned);
    let mut rows = ConstraintRows::new();
    let mut d = DMatrix::zeros(spec.len(), vars.ndof());
    for (i, row) in spec.iter().enumerate() {
        let e: Vec<RowEntry<'_>> = (row.iter())
            .map(|(b, c)| RowEntry {
                block: blocks[*b],
                coefs: c,
            })
            .collect();
        if i < 35 {
            rows.push_bilateral(&e, 0.01 * i as f64, 0.0);
        } else {
            rows.push_unilateral(&e, -0.02, 1e-3 * (i % 4) as f64);
        }
        for (b, c) in row {
            let off = vars.offset(blocks[*b]);
            for (jj, v) in c.iter().enumerate() {
                d[(i, off + jj)] += v;
            }
        }
    }
    let k: Vec<f64> = (0..vars.ndof()).map(|i| (i as f64 * 0.7).cos()).collect();
    let mut prob = CcpProblem::new();
    prob.assemble(&vars, &rows, &k).unwrap();
    (prob, d)
}

/// The assembly's shortcuts on coupled blocks are bit-neutral: `H^-1 D_i` solved in
/// batches of columns, and the sums over `D_i` (`n_entry`, `diag(N)`, `row_dot`, planned
/// entries of `N`) limited to the non-zero span of each entry.
///
/// - Bit for bit (tolerance 0): each coupled entry's `M^-1 D_i` against a one-column solve
///   of its own coefficients; `n_entry` and `diag` against the same sums over every
///   coefficient (the skipped products are exact zeros, `s + 0 b = s`); planned entries
///   against `n_entry`, also with a plan made on the problem before its spans moved (the
///   layout is the same, only where the non-zeros sit changed).
/// - Against the dense definition `N = D M^-1 D' + E`, `r = b + D M^-1 k`, `N g`: to
///   `1e-12 max(1, |x|)`, the round-off of sums of at most 27 products of O(1) numbers
///   taken in another order (about 1e-15 each); a dropped product is O(0.1).
#[test]
fn spans_and_batches_are_bit_neutral_on_coupled_blocks() {
    let bits = |x: f64| x.to_bits();
    let (before, _) = span_problem(false);
    let n_rows = before.n_rows();
    let positions: Vec<(usize, usize)> = (0..n_rows)
        .flat_map(|i| (0..n_rows).map(move |j| (i, j)))
        .collect();
    let mut plan = NEntryPlan::default();
    before
        .plan_n_entries(positions.iter().copied(), &mut plan)
        .unwrap();
    let mut planned = vec![0.0; plan.len()];
    for turned in [false, true] {
        let (prob, d) = span_problem(turned);
        let vars = prob.variables();
        let ndof = prob.ndof();
        // M^-1 D: each coupled entry's column as one solve gives it.
        for i in 0..n_rows {
            for (blk, _, c, m) in prob.row_entries(i) {
                if let MassOperator::Coupled(op) = vars.mass(blk) {
                    let mut y = vec![0.0; c.len()];
                    op.apply_inverse(c, &mut y);
                    let same = y.iter().zip(m).all(|(a, b)| bits(*a) == bits(*b));
                    assert!(same, "turned {turned}: M^-1 D of row {i}, block {blk:?}");
                }
            }
        }
        // Every coefficient, in n_entry's order.
        let full = |i: usize, j: usize| {
            let mut s = if i == j { prob.eps()[i] } else { 0.0 };
            for (bi, _, c, _) in prob.row_entries(i) {
                for (bj, _, _, m) in prob.row_entries(j) {
                    if bi == bj {
                        for (a, b) in c.iter().zip(m) {
                            s += a * b;
                        }
                    }
                }
            }
            s
        };
        // The dense definition.
        let mut minv = DMatrix::zeros(ndof, ndof);
        let mut e = vec![0.0; ndof];
        let mut col = vec![0.0; ndof];
        for jj in 0..ndof {
            e[jj] = 1.0;
            vars.apply_inverse(&e, &mut col);
            e[jj] = 0.0;
            minv.column_mut(jj).copy_from_slice(&col);
        }
        let dense_n = &d * &minv * d.transpose()
            + DMatrix::from_diagonal(&DVector::from_column_slice(prob.eps()));
        let close = |x: f64, want: f64| (x - want).abs() <= 1e-12 * want.abs().max(1.0);
        prob.fill_n_entries(&mut plan, &mut planned).unwrap();
        for (&(i, j), &p) in positions.iter().zip(&planned) {
            let n = prob.n_entry(i, j);
            assert_eq!(bits(n), bits(full(i, j)), "turned {turned}: N[{i},{j}]");
            assert_eq!(bits(p), bits(n), "turned {turned}: planned N[{i},{j}]");
            assert!(
                close(n, dense_n[(i, j)]),
                "turned {turned}: N[{i},{j}] {n} vs dense {}",
                dense_n[(i, j)]
            );
        }
        for i in 0..n_rows {
            assert_eq!(bits(prob.diag()[i]), bits(full(i, i)), "diag {i}");
        }
        let v_free = &minv * DVector::from_column_slice(prob.momentum());
        let r_dense = DVector::from_column_slice(prob.b()) + &d * &v_free;
        let g: Vec<f64> = (0..n_rows).map(|i| (i as f64 * 0.53).sin()).collect();
        let mut out = vec![0.0; n_rows];
        let mut work = CcpWork::for_problem(&prob);
        prob.apply_n(&g, &mut out, &mut work);
        let ng = &dense_n * DVector::from_column_slice(&g);
        for i in 0..n_rows {
            assert!(close(prob.r()[i], r_dense[i]), "turned {turned}: r[{i}]");
            assert!(close(out[i], ng[i]), "turned {turned}: (N g)[{i}]");
        }
    }
}
