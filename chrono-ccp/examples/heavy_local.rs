//! Heavy-on-light study: a CCP captured from a scene where heavy bodies rest on light ones
//! (e.g. `hmmwv-granular` with NSC grains), solved by APGD alone and by a block
//! Gauss-Seidel whose local block (every row touching a heavy body, the joints, and the
//! contacts of the light bodies within `hops` contacts of them) is solved by ADMM (direct
//! factorization, insensitive to the mass ratio) and whose far block (the rest) is
//! solved by a few APGD iterations with the local impulses held.
//!
//! Capture a step with `ProblemFile::save_problem(sys.last_problem(), "name", path)` (the
//! numbers in `docs/validation-rigid.md` are from `hmmwv-granular --quick --set method=nsc
//! --set h=0.001`, landing steps 200 and 250), then
//! run: `cargo run --release -p chrono-ccp --example heavy_local -- FILE.ccp [heavy_kg] [hops] [far_iters] [tol]`

use std::time::Instant;

use chrono_ccp::{Admm, Apgd, CcpSolver, LocalDirect, Schur, SolverSettings};
use chrono_core::descriptor::{CcpProblem, CcpWork, MassOperator, ProblemFile};

fn set(tol: f64, it: usize) -> SolverSettings {
    SolverSettings {
        tolerance: tol,
        max_iterations: it,
        record_history: false,
    }
}

fn residual(p: &CcpProblem, g: &[f64]) -> f64 {
    let mut work = CcpWork::default();
    let mut grad = vec![0.0; p.n_rows()];
    p.gradient(g, &mut grad, &mut work);
    p.residual(g, &grad, &mut work)
}

/// RMS residual of the rows `rows` alone (the full gradient restricted to them).
fn local_residual(p: &CcpProblem, rows: &[usize], g: &[f64]) -> f64 {
    let mut sub = CcpProblem::new();
    p.subproblem_rows(rows, g, &mut sub).unwrap();
    let gl: Vec<f64> = rows.iter().map(|&r| g[r]).collect();
    residual(&sub, &gl)
}

/// Largest velocity difference (m/s or rad/s) of the heavy blocks' dof between two impulses.
fn heavy_dv(p: &CcpProblem, heavy_dof: &[usize], a: &[f64], b: &[f64]) -> f64 {
    let e: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - y).collect();
    let mut dv = vec![0.0; p.ndof()];
    p.minv_d(&e, &mut dv);
    heavy_dof.iter().map(|&d| dv[d].abs()).fold(0.0, f64::max)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let Some(file) = args.get(1) else {
        return Err("usage: heavy_local FILE.ccp [heavy_kg] [hops] [far_iters] [tol]".into());
    };
    let heavy_kg: f64 = args.get(2).map_or(Ok(10.0), |s| s.parse())?;
    let hops: usize = args.get(3).map_or(Ok(2), |s| s.parse())?;
    let far_iters: usize = args.get(4).map_or(Ok(20), |s| s.parse())?;
    let tol: f64 = args.get(5).map_or(Ok(1e-4), |s| s.parse())?;
    let p = ProblemFile::load_problem(file)?;
    let vars = p.variables();
    let nb = vars.len();
    let mass: Vec<f64> = (0..nb)
        .map(
            |b| match vars.mass(chrono_core::descriptor::BlockId(b as u32)) {
                MassOperator::Particle { mass }
                | MassOperator::Scalar { mass }
                | MassOperator::RigidBody { mass, .. } => *mass,
                MassOperator::Coupled(_) => f64::INFINITY,
            },
        )
        .collect();
    let heavy: Vec<bool> = mass.iter().map(|&m| m > heavy_kg).collect();
    let s = p.sections();
    println!(
        "{} rows (bilateral {}, unilateral {}, friction {}, rolling {}), {nb} blocks, {} heavy (> {heavy_kg} kg)",
        p.n_rows(),
        s.bilateral.len(),
        s.unilateral.len(),
        s.friction.len(),
        s.rolling.len(),
        heavy.iter().filter(|&&h| h).count()
    );
    // Cone blocks and the variable blocks each touches.
    let mut blocks = Vec::new();
    let mut i = 0;
    while i < p.n_rows() {
        let (start, len) = s.block_of(i);
        let touched: Vec<usize> = (start..start + len)
            .flat_map(|r| p.row_blocks(r).map(|b| b.0 as usize).collect::<Vec<_>>())
            .collect();
        blocks.push((start, len, touched));
        i = start + len;
    }
    // Local set: joints and rows touching heavy bodies, grown by `hops` contact hops.
    let mut in_body = heavy.clone();
    let mut local = vec![false; blocks.len()];
    for (k, (start, _, t)) in blocks.iter().enumerate() {
        if s.bilateral.contains(start) || t.iter().any(|&b| heavy[b]) {
            local[k] = true;
        }
    }
    for _ in 0..hops {
        for (k, (_, _, t)) in blocks.iter().enumerate() {
            if local[k] {
                for &b in t {
                    in_body[b] = true;
                }
            }
        }
        for (k, (_, _, t)) in blocks.iter().enumerate() {
            if t.iter().any(|&b| in_body[b]) {
                local[k] = true;
            }
        }
    }
    let local_rows: Vec<usize> = blocks
        .iter()
        .zip(&local)
        .filter(|(_, l)| **l)
        .flat_map(|((st, len, _), _)| *st..*st + *len)
        .collect();
    let far_rows: Vec<usize> = blocks
        .iter()
        .zip(&local)
        .filter(|(_, l)| !**l)
        .flat_map(|((st, len, _), _)| *st..*st + *len)
        .collect();
    println!(
        "local block: {} rows, far block: {} rows (hops {hops})",
        local_rows.len(),
        far_rows.len()
    );

    let mut heavy_dof = Vec::new();
    let mut off = 0;
    for (b, &h) in heavy.iter().enumerate() {
        let n = vars.mass(chrono_core::descriptor::BlockId(b as u32)).ndof();
        if h {
            heavy_dof.extend(off..off + n);
        }
        off += n;
    }
    // Reference: APGD cold to 1e-7.
    let mut gref = vec![0.0; p.n_rows()];
    let t = Instant::now();
    let st = Apgd::new(set(1e-7, 200_000)).solve(&p, &mut gref);
    println!(
        "reference apgd cold to 1e-7: {} iterations, residual {:.2e}, local {:.2e}, {:.2} s",
        st.iterations,
        st.residual,
        local_residual(&p, &local_rows, &gref),
        t.elapsed().as_secs_f64()
    );
    for cap in [60, 200, 1000] {
        let mut g = vec![0.0; p.n_rows()];
        let st = Apgd::new(set(tol, cap)).solve(&p, &mut g);
        println!(
            "apgd cold cap {cap}: residual {:.2e} ({} it), local {:.2e}, heavy dv {:.2e}",
            st.residual,
            st.iterations,
            local_residual(&p, &local_rows, &g),
            heavy_dv(&p, &heavy_dof, &g, &gref)
        );
        let mut g = vec![0.0; p.n_rows()];
        let st = Schur::new(set(tol, cap)).solve(&p, &mut g);
        println!(
            "schur cold cap {cap}: residual {:.2e} ({} it), local {:.2e}, heavy dv {:.2e}",
            st.residual,
            st.iterations,
            local_residual(&p, &local_rows, &g),
            heavy_dv(&p, &heavy_dof, &g, &gref)
        );
    }

    for cap in [60, 200] {
        let mut g = vec![0.0; p.n_rows()];
        let mut ld = LocalDirect::new(set(tol, cap));
        let t = Instant::now();
        let st = ld.solve(&p, &mut g);
        println!(
            "local-direct cold cap {cap}: residual {:.2e} ({} sweeps, {} products), local {:.2e}, heavy dv {:.2e}, {} local rows, {:.2} s",
            st.residual,
            st.iterations,
            st.apply_n,
            local_residual(&p, &local_rows, &g),
            heavy_dv(&p, &heavy_dof, &g, &gref),
            ld.local_rows().len(),
            t.elapsed().as_secs_f64()
        );
    }
    // Block Gauss-Seidel, cold.
    let mut g = vec![0.0; p.n_rows()];
    let mut sub = CcpProblem::new();
    let mut admm = Admm::new(set(0.1 * tol, 2000));
    let mut apgd = Apgd::new(set(0.1 * tol, far_iters));
    let t = Instant::now();
    for sweep in 1..=30 {
        p.subproblem_rows(&local_rows, &g, &mut sub)?;
        let mut gl: Vec<f64> = local_rows.iter().map(|&r| g[r]).collect();
        let sl = admm.solve(&sub, &mut gl);
        for (&r, x) in local_rows.iter().zip(&gl) {
            g[r] = *x;
        }
        p.subproblem_rows(&far_rows, &g, &mut sub)?;
        let mut gf: Vec<f64> = far_rows.iter().map(|&r| g[r]).collect();
        let sf = apgd.solve(&sub, &mut gf);
        for (&r, x) in far_rows.iter().zip(&gf) {
            g[r] = *x;
        }
        let res = residual(&p, &g);
        println!(
            "bgs sweep {sweep}: local admm {} it (res {:.1e}), far apgd {} it (res {:.1e}); full residual {res:.2e}, local {:.2e}, heavy dv {:.2e} ({:.2} s)",
            sl.iterations,
            sl.residual,
            sf.iterations,
            sf.residual,
            local_residual(&p, &local_rows, &g),
            heavy_dv(&p, &heavy_dof, &g, &gref),
            t.elapsed().as_secs_f64()
        );
        if res < tol {
            break;
        }
    }
    Ok(())
}
