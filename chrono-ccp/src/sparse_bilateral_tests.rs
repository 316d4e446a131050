//! [`UpLooking`] against faer's simplicial factorization: the same factor and the same
//! solutions, bit for bit, on mechanism-like matrices (rows on one or two blocks, a hub
//! block many rows touch, dependent rows that need the regularized pivots).

use chrono_core::rng::Rng;
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholeskyRaw, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, MatMut, Par, Side};

use crate::up_looking::UpLooking;

/// A PSD `N = J W J' + E` with `n` rows on `blocks` blocks of 3 dof, upper triangle as
/// triplets in column order. Some rows repeat an earlier one (a singular `N`).
fn mechanism(n: usize, blocks: usize, rng: &mut Rng) -> Vec<Triplet<usize, usize, f64>> {
    let mut rows: Vec<Vec<(usize, [f64; 3])>> = Vec::new();
    for _ in 0..n {
        if !rows.is_empty() && rng.uniform() < 0.1 {
            let k = rng.int(0, rows.len() - 1);
            rows.push(rows[k].clone());
            continue;
        }
        let mut row = Vec::new();
        let first = if rng.uniform() < 0.5 {
            0
        } else {
            rng.int(0, blocks - 1)
        };
        let mut touch = vec![first];
        if rng.uniform() < 0.7 {
            let b = rng.int(0, blocks - 1);
            if b != first {
                touch.push(b);
            }
        }
        for b in touch {
            row.push((b, std::array::from_fn(|_| rng.range(-1.0, 1.0))));
        }
        rows.push(row);
    }
    let w: Vec<f64> = (0..blocks)
        .map(|b| if b == 0 { 1e-3 } else { 1.0 + b as f64 })
        .collect();
    let mut t = Vec::new();
    for j in 0..n {
        for i in 0..=j {
            let mut s = if i == j && rng.uniform() < 0.2 {
                1e-6
            } else {
                0.0
            };
            let mut shared = false;
            for (bi, ci) in &rows[i] {
                for (bj, cj) in &rows[j] {
                    if bi == bj {
                        shared = true;
                        s += w[*bi] * (ci[0] * cj[0] + ci[1] * cj[1] + ci[2] * cj[2]);
                    }
                }
            }
            if shared || i == j {
                t.push(Triplet::new(i, j, s));
            }
        }
    }
    t
}

#[test]
fn up_looking_is_bit_identical_to_faer_simplicial() {
    let mut rng = Rng::new(23);
    let (mut compared, mut regularized) = (0, 0);
    for case in 0..40 {
        let n = 4 + case * 3;
        let triplets = mechanism(n, 2 + n / 5, &mut rng);
        let a = SparseColMat::try_new_from_triplets(n, n, &triplets).unwrap();
        let symbolic = factorize_symbolic_cholesky(
            a.symbolic(),
            Side::Upper,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .unwrap();
        let SymbolicCholeskyRaw::Simplicial(l) = symbolic.raw() else {
            continue;
        };
        let (fwd, inv): (Vec<usize>, Vec<usize>) = match symbolic.perm() {
            Some(p) => (p.arrays().0.to_vec(), p.arrays().1.to_vec()),
            None => ((0..n).collect(), (0..n).collect()),
        };
        let s = a.symbolic();
        let mut up = UpLooking::new(
            s.col_ptr(),
            s.row_idx(),
            &fwd,
            &inv,
            l.col_ptr(),
            l.row_idx(),
        )
        .expect("the pattern of L agrees with faer's");
        let scale = a.val().iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let cols = 1 + case % 6;
        let mut mem = MemBuffer::new(StackReq::any_of(&[
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(cols, Par::Seq),
        ]));
        let mut l_values = vec![0.0; symbolic.len_val()];
        let reg = LltRegularization {
            dynamic_regularization_delta: scale,
            dynamic_regularization_epsilon: 1e-12 * scale,
        };
        symbolic
            .factorize_numeric_llt(
                &mut l_values,
                a.as_ref(),
                Side::Upper,
                reg,
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .unwrap();
        regularized += up.factor(a.val(), scale, 1e-12 * scale).unwrap().min(1);
        let rhs: Vec<f64> = (0..n * cols).map(|_| rng.range(-1.0, 1.0)).collect();
        let mut x_faer = rhs.clone();
        LltRef::new(&symbolic, &l_values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut x_faer, n, cols),
            Par::Seq,
            MemStack::new(&mut mem),
        );
        let mut x_up = rhs.clone();
        up.solve(&mut x_up, cols);
        for (k, (p, q)) in x_faer.iter().zip(&x_up).enumerate() {
            assert_eq!(
                p.to_bits(),
                q.to_bits(),
                "case {case}, entry {k}: {p} vs {q}"
            );
        }
        // A second factorization on the same pattern, other values.
        let scaled: Vec<f64> = a.val().iter().map(|v| 0.75 * v).collect();
        let mut b = a.clone();
        b.val_mut().copy_from_slice(&scaled);
        symbolic
            .factorize_numeric_llt(
                &mut l_values,
                b.as_ref(),
                Side::Upper,
                reg,
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .unwrap();
        up.factor(&scaled, scale, 1e-12 * scale).unwrap();
        let (mut x_faer, mut x_up) = (rhs.clone(), rhs);
        LltRef::new(&symbolic, &l_values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut x_faer, n, cols),
            Par::Seq,
            MemStack::new(&mut mem),
        );
        up.solve(&mut x_up, cols);
        for (p, q) in x_faer.iter().zip(&x_up) {
            assert_eq!(p.to_bits(), q.to_bits(), "case {case} refactored");
        }
        compared += 1;
    }
    assert!(compared >= 20, "only {compared} simplicial cases");
    assert!(
        regularized >= 5,
        "only {regularized} cases with regularized pivots"
    );
}

#[test]
fn up_looking_rejects_a_pattern_that_is_not_its_own() {
    // A 2 x 2 full matrix: L has an entry below the diagonal; an L pattern without it
    // is refused.
    let (col_ptr, row_idx) = ([0, 1, 3], [0, 0, 1]);
    let id = [0, 1];
    assert!(UpLooking::new(&col_ptr, &row_idx, &id, &id, &[0, 2, 3], &[0, 1, 1]).is_some());
    assert!(UpLooking::new(&col_ptr, &row_idx, &id, &id, &[0, 1, 2], &[0, 1]).is_none());
}
