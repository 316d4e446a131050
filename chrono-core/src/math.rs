//! Math types and small helpers shared by every crate.
//!
//! Conventions: SI units, `f64`, Z up, gravity `(0, 0, -9.81)` m/s^2. Our public math is
//! nalgebra; parry's glam types are converted only at the collision boundary
//! (`crate::collision::convert`).

pub use nalgebra::{Isometry3, Matrix3, Point3, Translation3, Unit, UnitQuaternion, Vector3};

/// The floating-point type of the engine.
pub type Real = f64;

/// The magnitude of gravity used throughout, `g = 9.81` m/s^2 (the value of the
/// validation references; standard gravity is 9.80665).
pub const GRAVITY_MAGNITUDE: f64 = 9.81;

/// Gravity vector `(0, 0, -g)`, m/s^2 (Z up), `g` = [`GRAVITY_MAGNITUDE`].
pub const GRAVITY: Vector3<f64> = Vector3::new(0.0, 0.0, -GRAVITY_MAGNITUDE);

/// The skew-symmetric (cross-product) matrix `[a]x`, so that `[a]x b = a x b`.
#[inline]
pub fn skew(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// Advance an orientation by a body-frame angular velocity over a step:
/// `q+ = q * exp(h w / 2)` (the exponential map), renormalized.
///
/// `omega_body` is in rad/s in the body frame, `h` in s. Exact for constant `omega_body`
/// over the step, so the quaternion stays unit length to round-off.
#[inline]
pub fn integrate_rotation(
    q: &UnitQuaternion<f64>,
    omega_body: &Vector3<f64>,
    h: f64,
) -> UnitQuaternion<f64> {
    let dq = UnitQuaternion::from_scaled_axis(omega_body * h);
    UnitQuaternion::new_normalize((q * dq).into_inner())
}

/// A right-handed orthonormal frame `(n, u, w)` with `n` the given unit normal.
///
/// Branch-free construction of Duff et al., "Building an orthonormal basis, revisited"
/// (JCGT 6(1), 2017): continuous except on the plane `n.z = 0` sign flip, deterministic.
#[inline]
pub fn tangent_frame(n: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let sign = 1.0f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let u = Vector3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let w = Vector3::new(b, sign + n.y * n.y * a, -n.y);
    (u, w)
}

/// True if every component of the vector is finite.
#[inline]
pub fn is_finite3(v: &Vector3<f64>) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skew_is_cross_product() {
        let a = Vector3::new(1.0, -2.0, 0.5);
        let b = Vector3::new(0.3, 4.0, -1.0);
        assert!((skew(&a) * b - a.cross(&b)).norm() < 1e-14);
    }

    #[test]
    fn tangent_frame_is_orthonormal_and_right_handed() {
        for n in [
            Vector3::new(0.0, 0.0, 1.0),
            Vector3::new(0.0, 0.0, -1.0),
            Vector3::new(1.0, 2.0, 3.0).normalize(),
            Vector3::new(-0.3, 0.1, -0.9).normalize(),
            Vector3::new(1.0, 0.0, 0.0),
        ] {
            let (u, w) = tangent_frame(&n);
            assert!((u.norm() - 1.0).abs() < 1e-12);
            assert!((w.norm() - 1.0).abs() < 1e-12);
            assert!(u.dot(&n).abs() < 1e-12 && w.dot(&n).abs() < 1e-12 && u.dot(&w).abs() < 1e-12);
            assert!((n.cross(&u) - w).norm() < 1e-12, "w = n x u for {n:?}");
        }
    }

    #[test]
    fn rotation_integration_matches_constant_spin() {
        let q0 = UnitQuaternion::identity();
        let w = Vector3::new(0.0, 0.0, 2.0);
        let mut q = q0;
        for _ in 0..1000 {
            q = integrate_rotation(&q, &w, 1e-3);
        }
        let expect = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 2.0);
        assert!(q.angle_to(&expect) < 1e-10);
    }
}
