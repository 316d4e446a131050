//! The checks of the rows an assembly is given ([`CcpProblem::assemble`]): each row's
//! blocks, coefficient counts and finite values, one at a time (naming the first bad field)
//! or a whole group in streaming passes.
//!
//! [`CcpProblem::assemble`]: super::CcpProblem::assemble

use rayon::prelude::*;

use super::rows::GroupRows;
use super::variables::{BlockId, Variables};
use crate::error::{ChronoError, Result};

/// Check row `i` of group `g` (named `name`) against the variables: every entry names an
/// existing block and carries that block's number of finite coefficients, `b` is finite
/// and `eps` finite and `>= 0`. The error names the first bad field in that order.
pub(super) fn check_row(g: &GroupRows, i: usize, vars: &Variables, name: &str) -> Result<()> {
    let nblocks = vars.len();
    let (e0, e1) = (g.row_ptr[i] as usize, g.row_ptr[i + 1] as usize);
    for e in e0..e1 {
        let blk = g.ent_block[e] as usize;
        if blk >= nblocks {
            return Err(ChronoError::UnknownHandle {
                kind: "variable block",
                index: blk,
                field: format!("rows.{name}[{i}]"),
            });
        }
        let nd = vars.block_ndof(BlockId(blk as u32));
        let c0 = g.ent_coef[e] as usize;
        let c1 = if e + 1 < g.ent_coef.len() {
            g.ent_coef[e + 1] as usize
        } else {
            g.coefs.len()
        };
        if c1 - c0 != nd {
            return Err(ChronoError::invalid(
                format!("rows.{name}[{i}].coefs.len()"),
                c1 - c0,
                format!("must equal the ndof ({nd}) of block {blk}"),
            ));
        }
        let c = &g.coefs[c0..c1];
        if let Some(j) = c.iter().position(|x| !x.is_finite()) {
            return Err(ChronoError::invalid(
                format!("rows.{name}[{i}].coefs[{j}]"),
                c[j],
                "must be finite",
            ));
        }
    }
    if !g.b[i].is_finite() {
        return Err(ChronoError::invalid(
            format!("rows.{name}[{i}].b"),
            g.b[i],
            "must be finite",
        ));
    }
    if !(g.eps[i].is_finite() && g.eps[i] >= 0.0) {
        return Err(ChronoError::invalid(
            format!("rows.{name}[{i}].eps"),
            g.eps[i],
            "must be finite and >= 0",
        ));
    }
    Ok(())
}

/// Every row of `g` passes [`check_row`] (`ndof`: each block's dof count): each entry's
/// block exists and has as many coefficients as dof, every coefficient and `b` is finite,
/// every `eps` finite and `>= 0`; in parallel over chunks, branch-free within one.
pub(super) fn rows_ok(g: &GroupRows, ndof: &[u32]) -> bool {
    const CHUNK: usize = 8192;
    let n_ent = g.row_ptr.get(g.n_rows()).map_or(0, |&p| p as usize);
    let entries_ok = (0..n_ent.div_ceil(CHUNK)).into_par_iter().all(|k| {
        (k * CHUNK..((k + 1) * CHUNK).min(n_ent)).fold(true, |ok, e| {
            let c1 = g.ent_coef.get(e + 1).map_or(g.coefs.len(), |&c| c as usize);
            let count = c1.wrapping_sub(g.ent_coef[e] as usize);
            let want = ndof
                .get(g.ent_block[e] as usize)
                .map_or(usize::MAX, |&d| d as usize);
            ok & (count == want)
        })
    });
    let n_coef = if n_ent == 0 { 0 } else { g.coefs.len() };
    let finite = |x: &[f64]| {
        x.par_chunks(CHUNK)
            .all(|c| c.iter().fold(true, |ok, v| ok & v.is_finite()))
    };
    let eps_ok = g.eps.par_chunks(CHUNK).all(|c| {
        c.iter()
            .fold(true, |ok, v| ok & (v.is_finite() & (*v >= 0.0)))
    });
    entries_ok && finite(&g.coefs[..n_coef]) && finite(&g.b) && eps_ok
}
