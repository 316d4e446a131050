//! Wong's general theory of skid steering with Coulomb contacts over given ground contacts
//! (J. Y. Wong, *Theory of Ground Vehicles*, 4th ed., Wiley 2008, sect. 7.3): the theory of
//! `m113-turn`'s steady turn and of its pivot turn.

/// Wong's general theory of skid steering with a rigid-plastic (Coulomb) shear law, over
/// given ground contacts `[x, y, N]` (vehicle frame from the centre of mass: `x` forward,
/// `y` left, m; normal load `N`, N; a contact with `y > 0` is on the left track): contact
/// `c` on track `j` slides at `s_c = (u_j, omega x_c + v_y)` and the ground pushes the
/// track with `-mu N_c s_c / |s_c|`. The unknowns `u_L`, `u_R` (m/s) and `v_y` (m/s) solve
///
/// ```text
/// sum_c F_x,c = 0,   sum_c F_y,c = m a_y,   sum_c (x_c F_y,c - y_c F_x,c) = 0
/// ```
///
/// (`m a_y` = `centripetal`, N: steady turn on flat ground, no other horizontal force) by
/// Newton's method with a finite-difference Jacobian; returns the lengthwise ground forces
/// on the left and right tracks `(F_L, F_R)`, N. `|s|` is regularized by 1e-9 m/s.
pub fn skid_steer(
    contacts: &[[f64; 3]],
    mu: f64,
    omega: f64,
    centripetal: f64,
) -> anyhow::Result<(f64, f64)> {
    skid_steer_solution(contacts, mu, omega, centripetal).map(|s| (s.left, s.right))
}

/// The solution of [`skid_steer`]: the lengthwise ground forces on the tracks and the
/// slip velocities that balance them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkidSteer {
    /// Lengthwise ground force on the left track, N.
    pub left: f64,
    /// Lengthwise ground force on the right track, N.
    pub right: f64,
    /// Lengthwise sliding velocity of the left track's ground contacts, `u_L`, m/s.
    pub u_left: f64,
    /// Lengthwise sliding velocity of the right track's ground contacts, `u_R`, m/s.
    pub u_right: f64,
    /// Lateral velocity of the centre of mass, `v_y`, m/s.
    pub v_y: f64,
}

/// [`skid_steer`] with the slip velocities (same arguments and errors).
pub fn skid_steer_solution(
    contacts: &[[f64; 3]],
    mu: f64,
    omega: f64,
    centripetal: f64,
) -> anyhow::Result<SkidSteer> {
    let forces = |z: [f64; 3]| -> ([f64; 3], f64, f64) {
        let (mut fx, mut fy, mut mz, mut fl, mut fr) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for &[x, y, n] in contacts {
            let u = if y > 0.0 { z[0] } else { z[1] };
            let w = omega * x + z[2];
            let norm = (u * u + w * w + 1e-18).sqrt();
            let (cx, cy) = (-mu * n * u / norm, -mu * n * w / norm);
            fx += cx;
            fy += cy;
            mz += x * cy - y * cx;
            if y > 0.0 {
                fl += cx;
            } else {
                fr += cx;
            }
        }
        ([fx, fy - centripetal, mz], fl, fr)
    };
    if omega == 0.0 && centripetal == 0.0 {
        // A straight run: no turning resistance, the tracks need no thrust difference.
        return Ok(SkidSteer {
            left: 0.0,
            right: 0.0,
            u_left: 0.0,
            u_right: 0.0,
            v_y: 0.0,
        });
    }
    anyhow::ensure!(
        contacts.iter().any(|c| c[1] > 0.0) && contacts.iter().any(|c| c[1] <= 0.0),
        "skid-steer theory: a track has no ground contact"
    );
    let scale: f64 = mu * contacts.iter().map(|c| c[2]).sum::<f64>();
    anyhow::ensure!(
        scale > 0.0 && scale.is_finite(),
        "no ground contact carries a load"
    );
    // The yaw moment's scale is a force times half the contact length (~1 m).
    let norm = |r: [f64; 3]| (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt() / scale;
    let v0 = (omega.abs() * 0.1).max(1e-4);
    let mut z = [v0, -v0, 0.0];
    let (mut r, _, _) = forces(z);
    for _ in 0..100 {
        if norm(r) < 1e-10 {
            break;
        }
        let mut jac = nalgebra::Matrix3::<f64>::zeros();
        for k in 0..3 {
            let mut zk = z;
            let dz = 1e-7 * (z[k].abs() + v0);
            zk[k] += dz;
            let (rk, _, _) = forces(zk);
            for i in 0..3 {
                jac[(i, k)] = (rk[i] - r[i]) / dz;
            }
        }
        let rhs = nalgebra::Vector3::new(-r[0], -r[1], -r[2]);
        // Gauss-Newton with a Levenberg damping where the Jacobian is (near) singular (a
        // track whose contacts all slide the same way has no lengthwise derivative).
        let step = match jac.lu().solve(&rhs) {
            Some(x) if x.iter().all(|v| v.is_finite()) => x,
            _ => {
                let jtj = jac.transpose() * jac;
                let damp = 1e-6 * jtj.trace().max(f64::MIN_POSITIVE);
                (jtj + nalgebra::Matrix3::identity() * damp)
                    .lu()
                    .solve(&(jac.transpose() * rhs))
                    .ok_or_else(|| anyhow::anyhow!("skid-steer theory: singular Jacobian"))?
            }
        };
        // Damped: halve the step until the residual falls.
        let mut t = 1.0;
        loop {
            let zt = [z[0] + t * step[0], z[1] + t * step[1], z[2] + t * step[2]];
            let (rt, _, _) = forces(zt);
            if norm(rt) < norm(r) || t < 1e-6 {
                z = zt;
                r = rt;
                break;
            }
            t *= 0.5;
        }
    }
    anyhow::ensure!(
        norm(r) < 1e-6,
        "skid-steer theory did not converge (residual {:.1e} of mu N; omega {omega} rad/s, \
         m a_y {centripetal} N, {} contacts, mu sum N {scale} N, slips {z:?})",
        norm(r),
        contacts.len()
    );
    let (_, left, right) = forces(z);
    Ok(SkidSteer {
        left,
        right,
        u_left: z[0],
        u_right: z[1],
        v_y: z[2],
    })
}

#[cfg(test)]
mod tests {
    use super::{skid_steer, skid_steer_solution};

    /// Contacts `[x, y, load]` of two tracks `l` long, `b` apart, carrying `w` N uniformly
    /// (40 points each).
    fn uniform_tracks(l: f64, b: f64, w: f64) -> Vec<[f64; 3]> {
        let k = 40;
        let mut c = Vec::new();
        for side in [1.0, -1.0] {
            for i in 0..k {
                let x = -0.5 * l + l * (i as f64 + 0.5) / k as f64;
                c.push([x, side * 0.5 * b, w / (2 * k) as f64]);
            }
        }
        c
    }

    /// A pivot turn (no lateral acceleration) on two tracks of uniform load: the thrusts are
    /// equal and opposite (`F_o = -F_i`), their difference below the simple form's `mu W L /
    /// (2 B)`, the tracks slip lengthwise equally and oppositely, and the slips scale with
    /// the yaw rate (Coulomb contacts are rate-independent: the pivot case's theory yaw
    /// rate rests on it).
    #[test]
    fn the_general_theory_of_a_pivot_is_antisymmetric_and_rate_independent() {
        let (l, b, mu, w) = (2.667, 2.159, 0.5, 109_441.0);
        let c = uniform_tracks(l, b, w);
        let s1 = skid_steer_solution(&c, mu, 0.3, 0.0).unwrap();
        let s2 = skid_steer_solution(&c, mu, 0.6, 0.0).unwrap();
        assert!(
            s1.right > 0.0 && (s1.right + s1.left).abs() < 1e-6 * s1.right,
            "{s1:?}"
        );
        assert!(
            s1.u_right < 0.0 && (s1.u_right + s1.u_left).abs() < 1e-6 * s1.u_left.abs(),
            "{s1:?}"
        );
        assert!(s1.v_y.abs() < 1e-9, "{s1:?}");
        let df = s1.right - s1.left;
        let simple = mu * w * l / (2.0 * b);
        assert!(df < simple && df > 0.5 * simple, "{df} against {simple}");
        assert!((s2.right / s1.right - 1.0).abs() < 1e-6, "{s1:?} {s2:?}");
        assert!(
            (s2.u_right / s1.u_right - 2.0).abs() < 1e-5,
            "{s1:?} {s2:?}"
        );
    }

    /// Two tracks of uniform load, 2.667 m long, 2.159 m apart, turning at 0.1 rad/s: the
    /// solution balances the forces and the moment, gives the outer (right) track a thrust
    /// and the inner a drag, a difference below the simple form's `mu W L / (2 B)` (the
    /// lengthwise slip takes part of the friction) and above half of it.
    #[test]
    fn the_general_theory_balances_and_stays_below_the_simple_form() {
        let (l, b, mu, w) = (2.667, 2.159, 0.3, 109_441.0);
        let c = uniform_tracks(l, b, w);
        let (fl, fr) = skid_steer(&c, mu, 0.1, 0.0).unwrap();
        assert!(
            fr > 0.0 && fl < 0.0 && (fr + fl).abs() < 1e-6 * fr,
            "{fl} {fr}"
        );
        let simple = mu * w * l / (2.0 * b);
        let df = fr - fl;
        assert!(df < simple && df > 0.5 * simple, "{df} against {simple}");
        // Without turning there is nothing to balance.
        let (fl, fr) = skid_steer(&c, mu, 0.0, 0.0).unwrap();
        assert!(fl.abs() < 1e-6 && fr.abs() < 1e-6, "{fl} {fr}");
    }
}
