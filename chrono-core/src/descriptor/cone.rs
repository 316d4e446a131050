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
    let gt = gu.hypot(gw);
    if gt <= mu * gn {
        return; // inside the cone (this includes the apex)
    }
    if mu * gt <= -gn {
        g[0] = 0.0;
        g[1] = 0.0;
        g[2] = 0.0;
        return; // inside the polar cone
    }
    let gn_new = (mu * gt + gn) / (mu * mu + 1.0);
    let scale = mu * gn_new / gt; // gt > 0 here, else one of the branches above was taken
    g[0] = gn_new;
    g[1] = gu * scale;
    g[2] = gw * scale;
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
