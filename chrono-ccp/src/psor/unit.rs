//! One unit of a PSOR sweep: its relaxation from the current impulses and velocities
//! (`unit_update`, pure) and the velocity change it causes (`apply_update`), through the
//! explicit rows, a fused triplet's rows ([`CcpProblem::fused_triplet`]) or a matrix-free
//! sphere contact ([`CcpProblem::mf_contact`]); the triplet step sizes.

use chrono_core::descriptor::{
    CcpProblem, FusedTriplet, PER_BODY_ROWS, SphereContact, project_friction_cone,
    project_rolling_cone, project_rolling_per_body_cone, upper_index,
};

use super::Unit;
use crate::dense::{DenseLdl, MAX_BLOCK};

impl Unit {
    /// The first row and the number of rows.
    pub(super) fn rows(self) -> (usize, usize) {
        match self {
            Unit::Row(i) => (i, 1),
            Unit::Bilateral { start, len, .. } => (start, len),
            Unit::Triplet(t) => (t, 3),
            Unit::Rolling(t) => (t, 6),
            Unit::RollingPerBody(t) => (t, PER_BODY_ROWS),
        }
    }
}

/// `w += M^-1 D (new - cur)` over `unit`'s rows (`w` the window from dof `base`), row
/// by row in order, skipping rows that did not change; fused for a fused triplet.
#[inline]
pub(super) fn apply_update(
    d: &SweepData,
    unit: Unit,
    upd: &UnitUpdate,
    cur: &[f64; MAX_BLOCK],
    vel: &mut Vel,
) {
    let problem = d.problem;
    if let Unit::Triplet(t) = unit {
        let k = (t - problem.sections().friction.start) / 3;
        let dg = [
            upd.new[0] - cur[0],
            upd.new[1] - cur[1],
            upd.new[2] - cur[2],
        ];
        if let Some(c) = d.setup.mf_contact(k) {
            if dg != [0.0; 3] {
                c.add_in(&dg, vel.ws, vel.sbase);
            }
            return;
        }
        if let Some(f) = &d.setup.fused[k] {
            problem.fused_add_minv_in(f, &dg, vel.w, vel.base);
            return;
        }
    }
    for j in 0..upd.len {
        let dg = upd.new[j] - cur[j];
        if dg != 0.0 {
            problem.row_add_minv_in(upd.start + j, dg, vel.w, vel.base);
        }
    }
}

/// The velocities a unit writes: the window of the explicit `M^-1 D g` from dof `base`
/// and that of the pure spheres' world-frame velocities from sphere `sbase` (empty
/// without matrix-free sweeps).
pub(super) struct Vel<'a> {
    pub(super) w: &'a mut [f64],
    pub(super) base: usize,
    pub(super) ws: &'a mut [f64],
    pub(super) sbase: usize,
}

impl<'a> Vel<'a> {
    /// All of `w` and `ws`.
    pub(super) fn whole(w: &'a mut [f64], ws: &'a mut [f64]) -> Self {
        Self {
            w,
            base: 0,
            ws,
            sbase: 0,
        }
    }

    /// The same windows, read-only.
    pub(super) fn read(&self) -> ReadVel<'_> {
        ReadVel {
            w: self.w,
            base: self.base,
            ws: self.ws,
            sbase: self.sbase,
        }
    }
}

/// The velocities a unit reads (see [`Vel`]).
pub(super) struct ReadVel<'a> {
    w: &'a [f64],
    base: usize,
    ws: &'a [f64],
    sbase: usize,
}

impl<'a> ReadVel<'a> {
    /// The whole explicit `w`, no sphere velocities (the coloured sweep).
    pub(super) fn explicit(w: &'a [f64]) -> Self {
        Self {
            w,
            base: 0,
            ws: &[],
            sbase: 0,
        }
    }
}

/// The values of `g` on `unit`'s rows (the rest 0).
#[inline]
pub(super) fn current(unit: Unit, g: &[f64]) -> [f64; MAX_BLOCK] {
    let (start, len) = unit.rows();
    let mut cur = [0.0; MAX_BLOCK];
    cur[..len].copy_from_slice(&g[start..start + len]);
    cur
}

/// What the sweeps read besides `g` and the velocities, set up once per solve.
#[derive(Debug, Clone, Default)]
pub(super) struct Setup {
    /// Step per row (`omega / N_ii`; per cone block, one value on its rows, or per row
    /// for an exact triplet).
    pub(super) step: Vec<f64>,
    /// Per friction triplet, `k = sqrt(b / a)` of [`TripletStep::Exact`](super::TripletStep::Exact)
    /// (0: the block is not `diag(a, b, b)`, or another step).
    pub(super) cone_scale: Vec<f64>,
    /// Per friction triplet, its fused layout ([`CcpProblem::fused_triplet`]) if any.
    pub(super) fused: Vec<Option<FusedTriplet>>,
    /// Per friction triplet: swept matrix-free (empty: no matrix-free sweeps).
    pub(super) mf: Vec<bool>,
    /// Per friction triplet its matrix-free contact (a default where `mf` is false).
    pub(super) mf_contacts: Vec<SphereContact>,
    /// Factored dense blocks of the bilateral groups.
    pub(super) factors: Vec<f64>,
}

impl Setup {
    /// Friction triplet `k`'s matrix-free contact, if it is swept matrix-free.
    #[inline(always)]
    pub(super) fn mf_contact(&self, k: usize) -> Option<&SphereContact> {
        match self.mf.get(k) {
            Some(true) => Some(&self.mf_contacts[k]),
            _ => None,
        }
    }
}

/// What a unit update reads besides `g` and `w`.
pub(super) struct SweepData<'a> {
    pub(super) problem: &'a CcpProblem,
    pub(super) setup: &'a Setup,
    pub(super) omega: f64,
}

/// The new values of a unit's rows `start..start + len`.
#[derive(Debug, Clone, Copy)]
pub(super) struct UnitUpdate {
    pub(super) start: usize,
    pub(super) len: usize,
    pub(super) new: [f64; MAX_BLOCK],
}

/// The constraint velocity `c_i = D_i'w + eps_i g_i + r_i` of row `i` whose impulse is
/// `gi`, `w` the window of `M^-1 D g` from dof `base`.
#[inline]
fn velocity(problem: &CcpProblem, i: usize, gi: f64, w: &[f64], base: usize) -> f64 {
    problem.row_dot_in(i, w, base) + problem.eps()[i] * gi + problem.r()[i]
}

/// The relaxation of one unit whose rows hold `cur` (`cur[j]` = `g` of its row
/// `start + j`), from `w = M^-1 D g` given as the window from dof `base` (pure: the caller
/// writes the new values and updates `w`).
#[inline]
pub(super) fn unit_update(
    d: &SweepData,
    unit: Unit,
    cur: &[f64; MAX_BLOCK],
    vel: &ReadVel,
) -> UnitUpdate {
    let problem = d.problem;
    let (w, base) = (vel.w, vel.base);
    let s = problem.sections();
    let mut new = [0.0; MAX_BLOCK];
    let (start, len) = unit.rows();
    match unit {
        Unit::Row(i) => {
            let z = cur[0] - d.setup.step[i] * velocity(problem, i, cur[0], w, base);
            new[0] = if i < s.boxed.start {
                z
            } else if i < s.unilateral.start {
                let (lo, hi) = problem.box_bounds();
                let k = i - s.boxed.start;
                z.clamp(lo[k], hi[k])
            } else {
                z.max(0.0)
            };
        }
        Unit::Bilateral { start, len, factor } => {
            let mut c = [0.0; MAX_BLOCK];
            for j in 0..len {
                c[j] = velocity(problem, start + j, cur[j], w, base);
            }
            DenseLdl::solve(
                &d.setup.factors[factor..factor + len * len],
                len,
                &mut c[..len],
            );
            for j in 0..len {
                new[j] = cur[j] - d.omega * c[j];
            }
        }
        Unit::Triplet(t) | Unit::Rolling(t) | Unit::RollingPerBody(t) => {
            let k = (t - s.friction.start) / 3;
            let (fused, mf) = match unit {
                Unit::Triplet(_) => (d.setup.fused[k].as_ref(), d.setup.mf_contact(k)),
                _ => (None, None),
            };
            if fused.is_some() || mf.is_some() {
                let dots = match (mf, fused) {
                    (Some(c), _) => c.dots_in(vel.ws, vel.sbase),
                    (None, Some(f)) => problem.fused_dots_in(f, w, base),
                    (None, None) => unreachable!("one of the two"),
                };
                let (eps, r) = (problem.eps(), problem.r());
                for j in 0..3 {
                    let c = dots[j] + eps[t + j] * cur[j] + r[t + j];
                    new[j] = cur[j] - d.setup.step[t + j] * c;
                }
            } else {
                for j in 0..len {
                    new[j] =
                        cur[j] - d.setup.step[t + j] * velocity(problem, t + j, cur[j], w, base);
                }
            }
            match unit {
                Unit::Triplet(_) => {
                    let c = (t - s.friction.start) / 3;
                    let mu = problem.friction_mu()[c];
                    let k = d.setup.cone_scale[c];
                    if k > 0.0 {
                        // the cone in N_tt's metric: (n, k u, k w) against mu k
                        new[1] *= k;
                        new[2] *= k;
                        project_friction_cone(mu * k, &mut new[..3]);
                        new[1] /= k;
                        new[2] /= k;
                    } else {
                        project_friction_cone(mu, &mut new[..3]);
                    }
                }
                Unit::Rolling(_) => {
                    let mu = problem.rolling_mu()[(t - s.rolling.start) / 6];
                    project_rolling_cone(mu, &mut new[..6]);
                }
                _ => {
                    let c = (t - s.rolling_per_body.start) / PER_BODY_ROWS;
                    let mu = problem.rolling_per_body_mu()[c];
                    project_rolling_per_body_cone(mu, &mut new[..PER_BODY_ROWS]);
                }
            }
        }
    }
    UnitUpdate { start, len, new }
}

/// `k = sqrt(b / a)` if the triplet block (upper triangle `[nn, nu, nw, uu, uw, ww]`) is
/// `diag(a, b, b)` to round-off (off-diagonals and `uu - ww` below `1e-12` of the
/// diagonal), else 0.
pub(super) fn diagonal_cone_scale(b: &[f64]) -> f64 {
    let (a, t) = (b[0], b[3]);
    let tol = 1e-12 * (a + t);
    if a > 0.0
        && t > 0.0
        && b[1].abs() <= tol
        && b[2].abs() <= tol
        && b[4].abs() <= tol
        && (b[5] - t).abs() <= tol
    {
        (t / a).sqrt()
    } else {
        0.0
    }
}

/// Gershgorin's upper bound on the largest eigenvalue of a symmetric `n x n` matrix given
/// as its row-major upper triangle: `max_i sum_j |a_ij|`.
pub(super) fn gershgorin_bound(upper: &[f64], n: usize) -> f64 {
    (0..n)
        .map(|i| {
            (0..n)
                .map(|j| upper[upper_index(n, i.min(j), i.max(j))].abs())
                .sum::<f64>()
        })
        .fold(0.0, f64::max)
}

/// The largest eigenvalue of a symmetric 3x3 matrix, in closed form (trigonometric solution of
/// the characteristic cubic; Smith 1961, "Eigenvalues of a symmetric 3x3 matrix", CACM 4(4)).
pub(crate) fn sym3_max_eigen(a: &[[f64; 3]; 3]) -> f64 {
    let p1 = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    if p1 == 0.0 {
        return a[0][0].max(a[1][1]).max(a[2][2]);
    }
    let q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    let (b00, b11, b22) = (a[0][0] - q, a[1][1] - q, a[2][2] - q);
    let p2 = b00 * b00 + b11 * b11 + b22 * b22 + 2.0 * p1;
    let p = (p2 / 6.0).sqrt();
    let det = b00 * (b11 * b22 - a[1][2] * a[1][2]) - a[0][1] * (a[0][1] * b22 - a[1][2] * a[0][2])
        + a[0][2] * (a[0][1] * a[1][2] - b11 * a[0][2]);
    let half_det = (det / (p * p * p) / 2.0).clamp(-1.0, 1.0);
    let phi = half_det.acos() / 3.0;
    q + 2.0 * p * phi.cos()
}

/// The friction triplet at row `t` (triplet `k`) relaxed in registers: the same
/// operations as [`unit_update`] and [`apply_update`] on it (matrix-free, fused or row by
/// row), without the generic unit's 12-wide arrays, whose scalar stores and wide reloads
/// stalled the sweep. Returns the new impulses; the velocity change is applied.
#[inline(always)]
pub(super) fn triplet(d: &SweepData, t: usize, k: usize, cur: [f64; 3], vel: &mut Vel) -> [f64; 3] {
    let problem = d.problem;
    let contact = d.setup.mf_contact(k);
    // (a matrix-free contact has no fused rows: not read)
    let fused = match contact {
        Some(_) => None,
        None => d.setup.fused[k].as_ref(),
    };
    let dots = match (contact, fused) {
        (Some(c), _) => c.dots_in(vel.ws, vel.sbase),
        (None, Some(f)) => problem.fused_dots_in(f, vel.w, vel.base),
        (None, None) => [0, 1, 2].map(|j| problem.row_dot_in(t + j, vel.w, vel.base)),
    };
    let (eps, r) = (problem.eps(), problem.r());
    let mut new = [0.0; 3];
    for j in 0..3 {
        let c = dots[j] + eps[t + j] * cur[j] + r[t + j];
        new[j] = cur[j] - d.setup.step[t + j] * c;
    }
    let mu = problem.friction_mu()[k];
    let scale = d.setup.cone_scale[k];
    if scale > 0.0 {
        new[1] *= scale;
        new[2] *= scale;
        project_friction_cone(mu * scale, &mut new);
        new[1] /= scale;
        new[2] /= scale;
    } else {
        project_friction_cone(mu, &mut new);
    }
    let dg = [new[0] - cur[0], new[1] - cur[1], new[2] - cur[2]];
    match (contact, fused) {
        (Some(c), _) => {
            if dg != [0.0; 3] {
                c.add_in(&dg, vel.ws, vel.sbase);
            }
        }
        (None, Some(f)) => problem.fused_add_minv_in(f, &dg, vel.w, vel.base),
        (None, None) => {
            for j in 0..3 {
                if dg[j] != 0.0 {
                    problem.row_add_minv_in(t + j, dg[j], vel.w, vel.base);
                }
            }
        }
    }
    new
}

/// `(t, k)` of `unit` if it is a friction triplet (for [`triplet`]).
#[inline(always)]
pub(super) fn as_triplet(d: &SweepData, unit: Unit) -> Option<(usize, usize)> {
    let Unit::Triplet(t) = unit else {
        return None;
    };
    Some((t, (t - d.problem.sections().friction.start) / 3))
}
