//! APGD with a coarse (aggregate) correction of the contact impulses: a two-level method
//! for granular beds, whose slow modes are smooth pressure fields (the load path through
//! many layers) that a first-order method resolves one layer per few iterations.
//!
//! Cycle: `inner` APGD iterations (warm-started from the current impulses), then a coarse
//! step. The bodies are grouped into aggregates on the contact graph (a seed body and its
//! neighbours, Vaněk, Mandel and Brezina 1996); each loaded contact (`g_n > 0`) belongs to
//! the aggregate of its first body. The coarse space adds one normal impulse per aggregate
//! to all its loaded contacts, `g + P d`, and `d` minimizes the objective restricted to it,
//!
//! ```text
//! (P'N P) d = -P'(N g + r),     P'N P = (D P)' M^-1 (D P)
//! ```
//!
//! (the Galerkin operator, built from the rows' Jacobians aggregate by aggregate and solved by
//! conjugate gradients), followed by the projection onto the cones and a backtracking test
//! on the objective `f(g) = 1/2 g'N g + r'g` (the step is kept only if `f` falls).
//! A study (issue 23), not a library solver: docs/performance.md, "A coarse space for the
//! pour".

use chrono_core::descriptor::{CcpProblem, CcpSolver, CcpWork, SolveStats, SolverSettings};

use chrono_ccp::Apgd;

/// APGD cycles with an aggregate correction of the normal impulses; see the module docs.
#[derive(Debug, Clone, Default)]
pub struct TwoLevel {
    settings: SolverSettings,
    apgd: Apgd,
    /// APGD iterations per cycle.
    pub inner: usize,
    /// Print the effect of every coarse step (`TWO_LEVEL_DEBUG`).
    debug: bool,
    work: CcpWork,
    grad: Vec<f64>,
    g_try: Vec<f64>,
    agg_of_body: Vec<u32>,
    n_agg: usize,
}

impl TwoLevel {
    /// A solver with the common settings and `inner` APGD iterations per cycle.
    pub fn new(settings: SolverSettings, inner: usize) -> Self {
        Self {
            apgd: Apgd::new(settings.clone()),
            settings,
            inner: inner.max(1),
            debug: std::env::var("TWO_LEVEL_DEBUG").is_ok(),
            ..Self::default()
        }
    }

    /// Aggregates of the bodies touched by the friction triplets' normal rows (indexed by
    /// the block's first dof; `u32::MAX` for an untouched dof).
    fn aggregate(&mut self, problem: &CcpProblem) {
        let ndof = problem.ndof();
        let fr = problem.sections().friction.clone();
        // Compact body ids by first dof.
        let mut id_of = vec![u32::MAX; ndof];
        let mut n_b = 0u32;
        let mut edges: Vec<(u32, u32)> = Vec::new();
        for t in fr.clone().step_by(3) {
            let mut ids = [u32::MAX; 2];
            for (k, (_, off, _, _)) in problem.row_entries(t).enumerate().take(2) {
                if id_of[off] == u32::MAX {
                    id_of[off] = n_b;
                    n_b += 1;
                }
                ids[k] = id_of[off];
            }
            if ids[1] != u32::MAX {
                edges.push((ids[0], ids[1]));
                edges.push((ids[1], ids[0]));
            }
        }
        let nb = n_b as usize;
        edges.sort_unstable();
        edges.dedup();
        let mut ptr = vec![0usize; nb + 1];
        for &(a, _) in &edges {
            ptr[a as usize + 1] += 1;
        }
        for i in 0..nb {
            ptr[i + 1] += ptr[i];
        }
        let nbr = |b: usize| edges[ptr[b]..ptr[b + 1]].iter().map(|e| e.1 as usize);
        let mut agg = vec![u32::MAX; nb];
        let mut n_agg = 0u32;
        for b in 0..nb {
            if agg[b] == u32::MAX && nbr(b).all(|c| agg[c] == u32::MAX) {
                agg[b] = n_agg;
                for c in nbr(b) {
                    agg[c] = n_agg;
                }
                n_agg += 1;
            }
        }
        for b in 0..nb {
            if agg[b] == u32::MAX {
                agg[b] = nbr(b)
                    .map(|c| agg[c])
                    .find(|&a| a != u32::MAX)
                    .unwrap_or_else(|| {
                        n_agg += 1;
                        n_agg - 1
                    });
            }
        }
        self.agg_of_body.clear();
        self.agg_of_body.resize(ndof, u32::MAX);
        for (off, &id) in id_of.iter().enumerate() {
            if id != u32::MAX {
                self.agg_of_body[off] = agg[id as usize];
            }
        }
        self.n_agg = n_agg as usize;
    }

    /// One coarse step on `gamma` (feasible); returns the number of `apply_n` spent.
    fn coarse_step(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> usize {
        let m = problem.n_rows();
        self.grad.resize(m, 0.0);
        self.g_try.resize(m, 0.0);
        let f0 = problem.objective(gamma, &mut self.grad, &mut self.work);
        let fr = problem.sections().friction.clone();
        let g: &[f64] = gamma;
        let Some(coarse) = Coarse::build(
            problem,
            &self.agg_of_body,
            self.n_agg,
            |t| g[t] > 0.0,
            |j| g[j],
        ) else {
            return 1;
        };
        let mut rhs = coarse.restrict(problem, &self.grad);
        rhs.iter_mut().for_each(|x| *x = -*x);
        let (d, cg_it) = coarse.solve(&rhs);
        let mut n_apply = 1;
        let mut alpha = 1.0;
        for _ in 0..4 {
            self.g_try.copy_from_slice(gamma);
            for (c, t) in fr.clone().step_by(3).enumerate() {
                let a = coarse.contact_agg[c];
                if a != u32::MAX {
                    // Scale by at most 10x down (a factor stays positive).
                    let f = 1.0 + (alpha * d[a as usize]).max(-0.9);
                    for j in t..t + 3 {
                        self.g_try[j] *= f;
                    }
                }
            }
            problem.project(&mut self.g_try);
            let f = problem.objective(&self.g_try, &mut self.grad, &mut self.work);
            n_apply += 1;
            if self.debug {
                eprintln!(
                    "coarse: agg {} cg {cg_it} alpha {alpha} f0 {f0:.6e} f {f:.6e} |d|max {:.3e}",
                    coarse.na,
                    d.iter().fold(0.0f64, |m, x| m.max(x.abs()))
                );
            }
            if f < f0 {
                gamma.copy_from_slice(&self.g_try);
                break;
            }
            alpha *= 0.5;
        }
        n_apply
    }

    /// The share of the error's energy `e'N e` that the coarse spaces can remove: for the
    /// additive normal space and the scaling space (shaped by `g`) on the aggregates of
    /// `problem`. For studies (`pour_stats`).
    pub fn capture(&mut self, problem: &CcpProblem, g: &[f64], e: &[f64]) -> [f64; 2] {
        self.work.resize(problem);
        self.aggregate(problem);
        let mut ne = vec![0.0; problem.n_rows()];
        problem.apply_n(e, &mut ne, &mut self.work);
        let ene: f64 = e.iter().zip(&ne).map(|(a, b)| a * b).sum();
        let mut out = [0.0; 2];
        for (k, o) in out.iter_mut().enumerate() {
            let fr_start = problem.sections().friction.start;
            let coarse = if k == 0 {
                Coarse::build(
                    problem,
                    &self.agg_of_body,
                    self.n_agg,
                    |t| g[t] > 0.0,
                    |j| {
                        if (j - fr_start).is_multiple_of(3) {
                            1.0
                        } else {
                            0.0
                        }
                    },
                )
            } else {
                Coarse::build(
                    problem,
                    &self.agg_of_body,
                    self.n_agg,
                    |t| g[t] > 0.0,
                    |j| g[j],
                )
            };
            let Some(coarse) = coarse else { continue };
            let b = coarse.restrict(problem, &ne);
            let (d, _) = coarse.solve(&b);
            let cap: f64 = d.iter().zip(&b).map(|(a, b)| a * b).sum();
            *o = cap / ene;
        }
        out
    }
}

/// The Galerkin operator `P'N P` of a coarse space: aggregate `a(c)` per contact (or none),
/// prolongation `P e_a = sum over rows j of a's contacts of w_j e_j`.
struct Coarse {
    na: usize,
    contact_agg: Vec<u32>,
    weights: Vec<f64>,
    rows: Vec<usize>,
    cols: Vec<u32>,
    vals: Vec<f64>,
    diag: Vec<f64>,
}

impl Coarse {
    fn build(
        problem: &CcpProblem,
        agg_of_body: &[u32],
        na: usize,
        include: impl Fn(usize) -> bool,
        weight: impl Fn(usize) -> f64,
    ) -> Option<Self> {
        let fr = problem.sections().friction.clone();
        let mut parts: Vec<(usize, u32, [f64; 6], [f64; 6])> = Vec::new();
        let mut contact_agg: Vec<u32> = vec![u32::MAX; fr.len() / 3];
        let mut weights = vec![0.0; fr.len()];
        for (c, t) in fr.clone().step_by(3).enumerate() {
            if !include(t) {
                continue;
            }
            let off = problem.row_entries(t).next()?.1;
            let a = agg_of_body[off];
            if a == u32::MAX {
                continue;
            }
            contact_agg[c] = a;
            for j in t..t + 3 {
                let w = weight(j);
                weights[j - fr.start] = w;
                for (_, off, d, md) in problem.row_entries(j) {
                    if d.len() != 6 {
                        return None;
                    }
                    let mut dd = [0.0; 6];
                    let mut mm = [0.0; 6];
                    for k in 0..6 {
                        dd[k] = w * d[k];
                        mm[k] = w * md[k];
                    }
                    parts.push((off, a, dd, mm));
                }
            }
        }
        parts.sort_unstable_by_key(|p| (p.0, p.1));
        let mut merged: Vec<(usize, u32, [f64; 6], [f64; 6])> = Vec::with_capacity(parts.len());
        for p in parts {
            if let Some(q) = merged.last_mut()
                && q.0 == p.0
                && q.1 == p.1
            {
                for k in 0..6 {
                    q.2[k] += p.2[k];
                    q.3[k] += p.3[k];
                }
                continue;
            }
            merged.push(p);
        }
        let mut trip: Vec<(u32, u32, f64)> = Vec::new();
        let mut s = 0;
        while s < merged.len() {
            let mut e = s;
            while e < merged.len() && merged[e].0 == merged[s].0 {
                e += 1;
            }
            for x in &merged[s..e] {
                for y in &merged[s..e] {
                    let v: f64 = (0..6).map(|k| x.2[k] * y.3[k]).sum();
                    trip.push((x.1, y.1, v));
                }
            }
            s = e;
        }
        trip.sort_unstable_by_key(|t| (t.0, t.1));
        let mut rows = vec![0usize; na + 1];
        let mut cols: Vec<u32> = Vec::new();
        let mut vals: Vec<f64> = Vec::new();
        let mut prev = (u32::MAX, u32::MAX);
        for (i, j, v) in trip {
            if (i, j) == prev {
                *vals.last_mut().expect("an entry") += v;
                continue;
            }
            prev = (i, j);
            rows[i as usize + 1] += 1;
            cols.push(j);
            vals.push(v);
        }
        for r in 0..na {
            rows[r + 1] += rows[r];
        }
        let diag = (0..na)
            .map(|i| {
                (rows[i]..rows[i + 1])
                    .find(|&k| cols[k] as usize == i)
                    .map_or(0.0, |k| vals[k])
            })
            .collect();
        Some(Self {
            na,
            contact_agg,
            weights,
            rows,
            cols,
            vals,
            diag,
        })
    }

    /// `P'v` (v over all rows).
    fn restrict(&self, problem: &CcpProblem, v: &[f64]) -> Vec<f64> {
        let fr = problem.sections().friction.clone();
        let mut out = vec![0.0; self.na];
        for (c, t) in fr.clone().step_by(3).enumerate() {
            let a = self.contact_agg[c];
            if a != u32::MAX {
                for j in t..t + 3 {
                    out[a as usize] += self.weights[j - fr.start] * v[j];
                }
            }
        }
        out
    }

    fn matvec(&self, x: &[f64], y: &mut [f64]) {
        for i in 0..self.na {
            let mut acc = 0.0;
            for k in self.rows[i]..self.rows[i + 1] {
                acc += self.vals[k] * x[self.cols[k] as usize];
            }
            y[i] = acc;
        }
    }

    /// Jacobi-preconditioned CG on `P'N P d = rhs`; returns `d` and the iterations.
    fn solve(&self, rhs: &[f64]) -> (Vec<f64>, usize) {
        let na = self.na;
        let mut d = vec![0.0; na];
        let mut res = rhs.to_vec();
        let pre = |r: &[f64], z: &mut [f64]| {
            for i in 0..na {
                z[i] = if self.diag[i] > 0.0 {
                    r[i] / self.diag[i]
                } else {
                    0.0
                };
            }
        };
        let mut z = vec![0.0; na];
        pre(&res, &mut z);
        let mut p = z.clone();
        let mut rz: f64 = res.iter().zip(&z).map(|(a, b)| a * b).sum();
        let rz0 = rz;
        let mut ap = vec![0.0; na];
        let mut it = 0;
        while it < 500 && rz > 1e-12 * rz0 {
            self.matvec(&p, &mut ap);
            let pap: f64 = p.iter().zip(&ap).map(|(a, b)| a * b).sum();
            if pap <= 0.0 {
                break;
            }
            let alpha = rz / pap;
            for i in 0..na {
                d[i] += alpha * p[i];
                res[i] -= alpha * ap[i];
            }
            pre(&res, &mut z);
            let rz_new: f64 = res.iter().zip(&z).map(|(a, b)| a * b).sum();
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..na {
                p[i] = z[i] + beta * p[i];
            }
            it += 1;
        }
        (d, it)
    }
}

impl CcpSolver for TwoLevel {
    fn name(&self) -> &'static str {
        "two-level"
    }
    fn settings(&self) -> &SolverSettings {
        &self.settings
    }
    fn settings_mut(&mut self) -> &mut SolverSettings {
        &mut self.settings
    }

    fn solve(&mut self, problem: &CcpProblem, gamma: &mut [f64]) -> SolveStats {
        if problem.n_rows() == 0 || !problem.is_friction_only() {
            *self.apgd.settings_mut() = self.settings.clone();
            return self.apgd.solve(problem, gamma);
        }
        self.work.resize(problem);
        self.aggregate(problem);
        let max_it = self.settings.max_iterations;
        let (mut it, mut n_apply) = (0, 0);
        let mut last;
        loop {
            let mut s = self.settings.clone();
            s.max_iterations = self.inner.min(max_it - it);
            *self.apgd.settings_mut() = s;
            last = self.apgd.solve(problem, gamma);
            it += last.iterations;
            n_apply += last.apply_n;
            if last.converged || it >= max_it || !last.residual.is_finite() {
                break;
            }
            n_apply += self.coarse_step(problem, gamma);
        }
        self.grad.resize(problem.n_rows(), 0.0);
        let objective = problem.objective(gamma, &mut self.grad, &mut self.work);
        let residual = problem.residual(gamma, &self.grad, &mut self.work);
        SolveStats {
            iterations: it,
            residual,
            objective,
            converged: residual <= self.settings.tolerance,
            apply_n: n_apply + 1,
            history: Vec::new(),
        }
    }
}
