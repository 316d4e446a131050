//! Projections onto the admissible sets of the constraint groups.

/// Project a friction triplet `(g_n, g_u, g_w)` onto the Coulomb cone
/// `Y = { |(g_u, g_w)| <= mu g_n }` (Euclidean projection).
///
/// Three cases (Anitescu and Tasora 2010; seed slide "Cone Complementarity Problem"):
/// inside `Y` the point is kept; inside the polar cone `Y° = { mu |g_t| <= -g_n }` it goes to
/// zero; otherwise onto the cone surface:
/// `g_n* = (mu |g_t| + g_n) / (mu^2 + 1)`, `|g_t*| = mu g_n*`, same tangential direction.
/// `mu = 0` reduces to `g_n* = max(g_n, 0)`, `g_t* = 0`.
#[inline]
pub fn project_friction_cone(mu: f64, g: &mut [f64]) {
    debug_assert!(g.len() >= 3);
    let (gn, gu, gw) = (g[0], g[1], g[2]);
    if mu <= 0.0 {
        g[0] = gn.max(0.0);
        g[1] = 0.0;
        g[2] = 0.0;
        return;
    }
    // The inside test on squares, `u^2 + w^2 <= (mu g_n)^2` with `g_n >= 0`: no square
    // root for the common case (a sticking contact). The surface case shrinks its result
    // until it passes this same test, so the projection is idempotent exactly.
    let t2 = gu * gu + gw * gw;
    let radius = mu * gn;
    if gn >= 0.0 && t2 <= radius * radius {
        return; // inside the cone (this includes the apex)
    }
    // sqrt(u^2 + w^2), not hypot: impulses are far from overflow, and hypot's care costs
    // several times more in this hot loop.
    let gt = t2.sqrt();
    if mu * gt <= -gn {
        g[0] = 0.0;
        g[1] = 0.0;
        g[2] = 0.0;
        return; // inside the polar cone
    }
    let gn_new = (mu * gt + gn) / (mu * mu + 1.0);
    let scale = mu * gn_new / gt; // gt > 0 here, else one of the branches above was taken
    let radius = mu * gn_new;
    let (mut u, mut w) = (gu * scale, gw * scale);
    // Round-off can leave the scaled point an ulp outside; shrink by ulps until the inside
    // test above holds for it.
    for _ in 0..4 {
        if u * u + w * w <= radius * radius {
            break;
        }
        u *= 1.0 - f64::EPSILON;
        w *= 1.0 - f64::EPSILON;
    }
    g[0] = gn_new;
    g[1] = u;
    g[2] = w;
}

/// After a radial scaling onto the ball of `radius`, round-off can leave the norm an ulp
/// outside it; shrink by ulps until the inside test `|x| <= radius` holds, so that the
/// projection is idempotent exactly (a projected warm start is not moved again).
#[inline]
fn shrink_into_ball(x: &mut [f64], radius: f64) {
    for _ in 0..4 {
        if x.iter().map(|v| v * v).sum::<f64>().sqrt() <= radius {
            return;
        }
        for v in x.iter_mut() {
            *v *= 1.0 - f64::EPSILON;
        }
    }
}

/// Project a contact block `g = (g_n, g_u, g_w, g_s, g_ru, g_rw)` (sliding, spinning and
/// rolling friction; Tasora and Anitescu 2013, Meccanica 48) onto the convex cone
///
/// ```text
/// K = { |(g_u, g_w)| <= mu[0] g_n,  |g_s| <= mu[1] g_n,  |(g_ru, g_rw)| <= mu[2] g_n }
/// ```
///
/// exactly (the Euclidean projection, not Chrono's sequence of three cone projections,
/// which is not a projection onto `K`). For a fixed normal value `n` the nearest point
/// clamps each tangential part radially to the ball of radius `mu_k n`, so the projection
/// minimizes the convex piecewise quadratic
/// `phi(n) = (n - g_n)^2 + sum_k (|x_k| - mu_k n)_+^2` over `n >= 0`. Its stationary point
/// in the interval where the set `A` of clamped parts is fixed is
/// `n = (g_n + sum_A mu_k |x_k|) / (1 + sum_A mu_k^2)`; the intervals are bounded by the
/// breakpoints `|x_k| / mu_k` and are scanned in order. With one part (`mu[1] = mu[2] = 0`
/// and zero torques) this is [`project_friction_cone`]. Coefficients `mu_k = 0` force the
/// part to zero.
pub fn project_rolling_cone(mu: [f64; 3], g: &mut [f64]) {
    debug_assert!(g.len() >= 6);
    project_parts(&[(1, 2, mu[0]), (3, 1, mu[1]), (4, 2, mu[2])], &mut g[..6]);
}

/// Project a per-body rolling contact block
/// `g = (g_n, g_u, g_w, g_s, g_a (3), g_b (3))` ([`RowGroup::RollingPerBody`](super::RowGroup))
/// onto the convex cone
///
/// ```text
/// K = { |(g_u, g_w)| <= mu[0] g_n,  |g_s| <= mu[1] g_n,  |g_a| <= mu[2] g_n,  |g_b| <= mu[2] g_n }
/// ```
///
/// exactly, by the scan of [`project_rolling_cone`] over the four parts.
pub fn project_rolling_per_body_cone(mu: [f64; 3], g: &mut [f64]) {
    debug_assert!(g.len() >= 10);
    project_parts(
        &[(1, 2, mu[0]), (3, 1, mu[1]), (4, 3, mu[2]), (7, 3, mu[2])],
        &mut g[..10],
    );
}

/// The Euclidean projection of `g` onto `{ |g[s..s + len]| <= mu g[0] for each part }`
/// (parts `(s, len, mu)`, at most four, disjoint, after `g[0]`): see
/// [`project_rolling_cone`] for the scan over the breakpoints `|x_k| / mu_k`.
fn project_parts(parts: &[(usize, usize, f64)], g: &mut [f64]) {
    const MAX: usize = 4;
    debug_assert!(parts.len() <= MAX);
    let mut norms = [0.0; MAX];
    for (k, &(s, len, _)) in parts.iter().enumerate() {
        norms[k] = if len == 1 {
            g[s].abs()
        } else {
            g[s..s + len].iter().map(|v| v * v).sum::<f64>().sqrt()
        };
    }
    let gn = g[0];
    // Inside K: keep.
    if gn >= 0.0 && parts.iter().enumerate().all(|(k, p)| norms[k] <= p.2 * gn) {
        return;
    }
    // Breakpoints of the parts that can be clamped against a positive n.
    let mut bp = [(f64::INFINITY, 0usize); MAX];
    let mut nb = 0;
    for (k, p) in parts.iter().enumerate() {
        if p.2 > 0.0 && norms[k] > 0.0 {
            bp[nb] = (norms[k] / p.2, k);
            nb += 1;
        }
    }
    bp[..nb].sort_by(|a, b| a.0.total_cmp(&b.0));
    // Scan the intervals [0, b1], [b1, b2], ..., [b_nb, inf): in interval j the parts
    // j.. (in breakpoint order) are clamped (|x_k| > mu_k n).
    let mut n = 0.0;
    for j in 0..=nb {
        let (mut num, mut den) = (gn, 1.0);
        for &(_, k) in &bp[j..nb] {
            num += parts[k].2 * norms[k];
            den += parts[k].2 * parts[k].2;
        }
        let cand = num / den;
        let lo = if j == 0 { 0.0 } else { bp[j - 1].0 };
        let hi = if j < nb { bp[j].0 } else { f64::INFINITY };
        if cand <= hi {
            // phi' is increasing: the first interval whose stationary point is not beyond
            // its upper end holds the minimizer (clamped to the interval's lower end).
            n = cand.max(lo);
            break;
        }
    }
    g[0] = n;
    for (k, &(s, len, mu)) in parts.iter().enumerate() {
        let radius = mu * n;
        let x = &mut g[s..s + len];
        if norms[k] > radius {
            let sc = if norms[k] > 0.0 {
                radius / norms[k]
            } else {
                0.0
            };
            for v in x.iter_mut() {
                *v *= sc;
            }
            shrink_into_ball(x, radius);
        }
    }
}

/// Project a unilateral multiplier onto `g >= 0`.
#[inline]
pub fn project_unilateral(g: f64) -> f64 {
    g.max(0.0)
}

/// Project a box-bounded multiplier onto `[lo, hi]`.
#[inline]
pub fn project_box(g: f64, lo: f64, hi: f64) -> f64 {
    g.clamp(lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn in_cone(mu: f64, g: &[f64; 3], tol: f64) -> bool {
        g[1].hypot(g[2]) <= mu * g[0] + tol && g[0] >= -tol
    }

    #[test]
    fn the_three_cases() {
        // inside
        let mut g = [1.0, 0.1, -0.2];
        project_friction_cone(0.5, &mut g);
        assert_eq!(g, [1.0, 0.1, -0.2]);
        // polar cone -> 0
        let mut g = [-1.0, 0.1, 0.1];
        project_friction_cone(0.5, &mut g);
        assert_eq!(g, [0.0, 0.0, 0.0]);
        // surface: (n, t) = (0, 1), mu = 1 -> (0.5, 0.5)
        let mut g = [0.0, 1.0, 0.0];
        project_friction_cone(1.0, &mut g);
        assert!((g[0] - 0.5).abs() < 1e-15 && (g[1] - 0.5).abs() < 1e-15 && g[2] == 0.0);
        // frictionless
        let mut g = [2.0, 1.0, 1.0];
        project_friction_cone(0.0, &mut g);
        assert_eq!(g, [2.0, 0.0, 0.0]);
    }

    proptest! {
        #[test]
        fn projection_lands_in_cone_and_is_idempotent(
            mu in 0.0f64..2.0, n in -10.0f64..10.0, u in -10.0f64..10.0, w in -10.0f64..10.0
        ) {
            let mut g = [n, u, w];
            project_friction_cone(mu, &mut g);
            prop_assert!(in_cone(mu, &g, 1e-12));
            let once = g;
            project_friction_cone(mu, &mut g);
            for k in 0..3 { prop_assert!((g[k] - once[k]).abs() <= 1e-12 * (1.0 + once[k].abs())); }
        }

        #[test]
        fn projection_is_the_nearest_point(
            mu in 0.05f64..2.0, n in -5.0f64..5.0, u in -5.0f64..5.0, w in -5.0f64..5.0,
            pn in 0.0f64..5.0, pa in 0.0f64..std::f64::consts::TAU, pr in 0.0f64..1.0
        ) {
            // any cone point q is no closer to x than the projection p,
            // and (x - p) is orthogonal to p (projection onto a cone).
            let x = [n, u, w];
            let mut p = x;
            project_friction_cone(mu, &mut p);
            let q = [pn, mu * pn * pr * pa.cos(), mu * pn * pr * pa.sin()];
            let d = |a: &[f64; 3], b: &[f64; 3]| ((a[0]-b[0]).powi(2) + (a[1]-b[1]).powi(2) + (a[2]-b[2]).powi(2)).sqrt();
            prop_assert!(d(&x, &p) <= d(&x, &q) + 1e-9);
            let dot = (x[0]-p[0])*p[0] + (x[1]-p[1])*p[1] + (x[2]-p[2])*p[2];
            prop_assert!(dot.abs() < 1e-9 * (1.0 + d(&x, &[0.0; 3]).powi(2)));
        }
    }
}
