//! SMC (penalty) contact: the force of one contact from its overlap, relative velocity and
//! tangential displacement history.
//!
//! # Normal force
//!
//! With overlap `delta > 0` (m), normal approach speed `delta_dot` (m/s, positive while the
//! bodies approach), effective radius `R = 1/(1/R_a + 1/R_b)` and effective mass
//! `m = 1/(1/m_a + 1/m_b)`:
//!
//! - **Hertz** (K. L. Johnson, *Contact Mechanics*, 1985, §4.2; damping of the form of
//!   Y. Tsuji, T. Tanaka, T. Ishida, Powder Technol. 71, 1992):
//!   `F_n = K delta^(3/2) + alpha sqrt(m K) delta^(1/4) delta_dot`, `K = 4/3 E* sqrt(R)`.
//! - **Hooke** (linear spring-dashpot, P. A. Cundall and O. D. L. Strack, Géotechnique 29,
//!   1979): `F_n = k delta + alpha sqrt(m k) delta_dot`, with `k` chosen so that an impact at
//!   the characteristic speed `v_c` reaches the same maximum overlap as a Hertz contact,
//!   `k = m v_c^2 / delta_max^2`, `delta_max = (15 m v_c^2 / (16 E* sqrt(R)))^(2/5)`.
//!
//! `F_n` is clamped at 0 (no adhesion): the bodies separate when the damping would pull.
//! In both forms the coefficient of restitution depends only on the dimensionless damping
//! `alpha` (scale `delta` and `t` by the impact's maximum overlap and speed), not on the
//! impact speed. [`damping_for_restitution`] maps the material's restitution `e` to
//! `alpha` by solving the dimensionless contact ODE `X'' = -max(X^p + alpha X^q X', 0)`
//! (`p, q = 3/2, 1/4` or `1, 0`) with RK4 and bisecting on `alpha`, so the mapping is exact
//! to the integrator's accuracy, clamp included. (The closed forms in common use, e.g.
//! `beta = ln e / sqrt(ln^2 e + pi^2)`, hold for the linear model without the clamp only.)
//!
//! # Tangential force
//!
//! A spring with history (Mindlin's no-slip stiffness for Hertz, R. D. Mindlin, J. Appl.
//! Mech. 16, 1949; S. Luding, Granular Matter 10, 2008 for the projection and reset):
//! the tangential displacement `xi` is stored per persistent contact
//! ([`ContactKey`]), rotated into the current tangent plane
//! (magnitude kept), and advanced by `v_t h`. `F_t = -k_t xi - c_t v_t`, capped by Coulomb
//! `|F_t| <= mu F_n`; when capped, `xi = -F_t / k_t` (no spring wind-up).
//! `k_t = 8 G* sqrt(R delta)` (Hertz–Mindlin) or `k_t = 2/7 k` (Hooke; equal normal and
//! tangential periods for a solid sphere). `c_t = c_n sqrt(k_t / S_n)` where `c_n` is the
//! normal damping coefficient and `S_n = dF_n/d delta` the normal contact stiffness.
//!
//! # Rolling and spinning resistance
//!
//! Three models, chosen by [`SystemSettings::rolling_model`](crate::SystemSettings)
//! ([`RollingModel`], shared with NSC contact); the first two are a constant-magnitude
//! torque `mu_r R F_n` while the bodies roll, the third a spring capped at it (`R` the
//! contact's effective radius, so the rolling-friction length of the literature is
//! `mu_r R`):
//!
//! - [`RollingModel::Relative`] (default): opposes the *relative* rolling velocity
//!   `w_r = (omega_B - omega_A)` minus its normal part (J. Ai, J.-F. Chen, J. M. Rotter and
//!   J. Y. Ooi, Powder Technol. 206, 2011, "model type A"); a pure couple, B gets `M_r`,
//!   A gets `-M_r`; two grains turning together feel none. Limited so that it cannot reverse
//!   `w_r` within one step (`|M_r| <= I |w_r| / h`, `I` the contact's effective rotational
//!   inertia).
//! - [`RollingModel::PerBody`]: each body gets `M_i = -mu_r R F_n omega_i / |omega_i|`
//!   opposing its *own* angular velocity (Y. C. Zhou, B. D. Wright, R. Y. Yang, B. H. Xu and
//!   A. B. Yu, "Rolling friction in the dynamic simulation of sandpile formation", Physica A
//!   269, 1999, 536–553; used by Zhou et al., Powder Technol. 125, 2002 for the angle of
//!   repose, with the length `mr = mu_r R`). Not a couple (angular momentum is not
//!   conserved, as for a grain on a fixed plane), and it also resists a rigid rotation of
//!   two grains together. [`contact_force`] returns the magnitudes ([`SmcForce::rolling`]);
//!   the torques of all contacts of a body are parallel, so the caller sums them and limits
//!   the sum once per body ([`per_body_rolling_torque`]: it cannot reverse `omega_i`
//!   within one step). Limiting each contact separately lets `k` contacts reverse the
//!   rotation `k - 1` times over, a per-step sign flip that grows until the caps bind: a
//!   heap of 400 grains at `mu_r = 0.02` then collapsed to 7 degrees at the SMC step limit
//!   and stood at 16 degrees at `h = 1e-5` s (measured while this was written).
//!
//! - [`RollingModel::Spring`]: an elastic-plastic rolling spring with a dashpot on the
//!   relative rolling rotation (Ai et al. 2011, "model type C"). The contact stores its
//!   rolling angle `theta_r` (rad, world, in the tangent plane; rotated into the current
//!   tangent plane like `xi`, magnitude kept) and advances it by `w_r h`; the spring moment
//!   `M_k = -k_r theta_r`, `k_r = 2.25 S_n mu_r^2 R^2` (`S_n` the normal contact
//!   stiffness), is capped at `mu_r R F_n` (then `theta_r = -M_k / k_r`, no wind-up, and
//!   the dashpot is off, Ai's `f = 0`); below the cap the dashpot adds `-C_r w_r`,
//!   `C_r = 2 eta_r sqrt(I_r k_r)` with `eta_r` = [`SmcSettings::rolling_damping_ratio`]
//!   and `I_r` the pair's effective inertia about the contact point
//!   ([`SmcPair::rolling_inertia`]). Unlike the two models above it holds a static moment
//!   below the cap: a sphere on a slope steeper than its rolling resistance angle rolls, on
//!   a gentler one it stops (a couple: angular momentum is conserved). The relative model's
//!   limiter instead leaves a steady creep `w_r = tau h / I` under a held moment `tau`,
//!   which grows as `1/d^2` for grains of diameter `d`. The explicit step bounds both
//!   coefficients: `k_r <= I (0.5 / h)^2` and `C_r <= 0.25 I / h` with `I` the centroidal
//!   effective inertia ([`MAX_ROLLING_OMEGA_H`], [`MAX_ROLLING_DAMPING_H`]). They bind only
//!   where the contact radius is large against the body (a flat contact of a small box,
//!   `R` = `flat_contact_radius`), not for spheres (`k_r h^2 / I` is at most
//!   `5.6 mu_r^2 (omega_n h)^2`, a sphere on a plane, with `omega_n h` ~ 0.3 at the step
//!   limit).
//!
//! For NSC contact `Spring` acts as `Relative`: the rolling rows are rigid-plastic, the
//! spring's limit of infinite stiffness.
//!
//! The spinning torque `mu_s R F_n` about the normal opposes the relative spin in all
//! three, with the limiter.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::collision::ContactKey;
use crate::error::{ChronoError, Result, check_positive};

/// The normal force law of SMC contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SmcModel {
    /// Linear spring-dashpot, stiffness from the material at the characteristic speed.
    Hooke,
    /// Hertz (`F ~ delta^(3/2)`) with Tsuji damping and Mindlin's tangential stiffness.
    Hertz,
}

impl SmcModel {
    /// Exponents `(p, q)` of the dimensionless normal law `X^p + alpha X^q X'`.
    fn exponents(self) -> (f64, f64) {
        match self {
            SmcModel::Hooke => (1.0, 0.0),
            SmcModel::Hertz => (1.5, 0.25),
        }
    }
}

/// Which rotation the rolling resistance opposes, for both contact methods (see the module
/// docs here for SMC and [`crate::contact::nsc`] for NSC).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RollingModel {
    /// The relative rolling velocity of the two bodies (Ai et al. 2011, model type A): a
    /// couple.
    #[default]
    Relative,
    /// Each body's own angular velocity (Zhou et al. 1999, 2002).
    PerBody,
    /// An elastic-plastic spring-dashpot on the relative rolling rotation (Ai et al. 2011,
    /// model type C; SMC only, NSC treats it as [`RollingModel::Relative`]).
    Spring,
}

/// Settings of SMC contact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct SmcSettings {
    /// The normal force law.
    pub model: SmcModel,
    /// Characteristic impact speed `v_c` (m/s): sets the Hooke stiffness and the contact
    /// duration used by the time-step check.
    pub characteristic_velocity: f64,
    /// The step must resolve a contact with at least this many steps: `h <= t_c / N`
    /// (checked by [`System::step`](crate::system::System::step) in SMC mode, the error
    /// names the body). 10 is the stability margin usually quoted for explicit DEM
    /// (O'Sullivan and Bray, Eng. Comput. 21, 2004); accurate restitution needs ~50.
    pub min_steps_per_contact: f64,
    /// Effective radius (m) of a contact between two shapes without a curvature radius
    /// (boxes against half-spaces, meshes ...).
    pub flat_contact_radius: f64,
    /// Verlet skin of the sphere grid in SMC steps, as a fraction of the largest sphere
    /// radius ([`CollisionWorld::set_sphere_skin`](crate::collision::CollisionWorld::set_sphere_skin)):
    /// the sphere pairs are searched again only after a sphere moved more than half of
    /// it. The contacts do not depend on it (only the cost does); 0 searches every step.
    pub grid_skin: f64,
    /// Damping ratio `eta_r` of the rolling spring's dashpot ([`RollingModel::Spring`]):
    /// `C_r = 2 eta_r sqrt(I_r k_r)`. 0.3 is the value Ai et al. (Powder Technol. 206,
    /// 2011) use in their tests of model type C.
    pub rolling_damping_ratio: f64,
}

impl Default for SmcSettings {
    fn default() -> Self {
        Self {
            model: SmcModel::Hertz,
            characteristic_velocity: 1.0,
            min_steps_per_contact: 10.0,
            flat_contact_radius: 1.0,
            grid_skin: 0.25,
            rolling_damping_ratio: 0.3,
        }
    }
}

impl SmcSettings {
    /// Check every field.
    pub fn validate(&self) -> Result<()> {
        check_positive("smc.characteristic_velocity", self.characteristic_velocity)?;
        check_positive("smc.min_steps_per_contact", self.min_steps_per_contact)?;
        check_positive("smc.flat_contact_radius", self.flat_contact_radius)?;
        crate::error::check_non_negative("smc.grid_skin", self.grid_skin)?;
        crate::error::check_non_negative("smc.rolling_damping_ratio", self.rolling_damping_ratio)?;
        Ok(())
    }
}

/// The constant parameters of one contact pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SmcPair {
    /// Effective radius `R` (m).
    pub radius: f64,
    /// Effective mass `m` (kg).
    pub mass: f64,
    /// Effective rotational inertia for the rolling and spinning limiters (kg m^2).
    pub inertia: f64,
    /// Effective rolling inertia about the contact point for the rolling spring's dashpot
    /// (kg m^2): `1 / sum_i 1/(I_i + m_i d_i^2)`, `d_i` the distance of body `i`'s centre of
    /// mass from the contact point (Ai et al. 2011; [`RollingModel::Spring`] only).
    pub rolling_inertia: f64,
    /// Effective Young's modulus `E*` (Pa).
    pub young: f64,
    /// Effective shear modulus `G*` (Pa).
    pub shear: f64,
    /// Dimensionless damping `alpha` ([`damping_for_restitution`]).
    pub alpha: f64,
    /// Coulomb friction coefficient.
    pub friction: f64,
    /// Rolling friction coefficient (dimensionless).
    pub rolling_friction: f64,
    /// Spinning friction coefficient (dimensionless).
    pub spinning_friction: f64,
    /// The rolling resistance model.
    pub rolling_model: RollingModel,
    /// The rolling spring's damping ratio `eta_r` ([`SmcSettings::rolling_damping_ratio`]).
    pub rolling_damping: f64,
}

/// The history of one persistent SMC contact, carried from step to step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SmcHistory {
    /// Tangential displacement `xi` (m, world).
    pub tangential: Vector3<f64>,
    /// Rolling angle `theta_r` of [`RollingModel::Spring`] (rad, world; 0 for the other
    /// models).
    pub rolling: Vector3<f64>,
}

/// The kinematics of one contact at the current step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SmcKinematics {
    /// Unit normal from A to B.
    pub normal: Vector3<f64>,
    /// Overlap `delta = -distance` (m); no force unless > 0.
    pub overlap: f64,
    /// Velocity of B's material point at the contact minus A's (m/s, world).
    pub relative_velocity: Vector3<f64>,
    /// Angular velocity of A (rad/s, world).
    pub angular_velocity_a: Vector3<f64>,
    /// Angular velocity of B (rad/s, world).
    pub angular_velocity_b: Vector3<f64>,
}

/// The result of [`contact_force`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SmcForce {
    /// Normal force magnitude `F_n >= 0` (N).
    pub normal: f64,
    /// Total force on B at the contact point (N, world); A gets the opposite.
    pub force: Vector3<f64>,
    /// Pure couple on B from rolling and spinning resistance (N m, world); A gets the
    /// opposite.
    pub torque: Vector3<f64>,
    /// [`RollingModel::PerBody`]: the magnitudes `mu_r R F_n` (N m) of the rolling torques
    /// on A and B, each against that body's own angular velocity (0 for a body that does
    /// not turn, and for the relative model); sum per body and apply with
    /// [`per_body_rolling_torque`].
    pub rolling: [f64; 2],
    /// The updated history to store for the next step.
    pub history: SmcHistory,
}

/// One SMC contact of the last step (for output and measurements).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SmcContact {
    /// Persistence key (also the key of its tangential history).
    pub key: ContactKey,
    /// The owner (body index) of collider A.
    pub owner_a: u32,
    /// The owner of collider B.
    pub owner_b: u32,
    /// The contact point, midway between the two surfaces (m, world).
    pub point: Vector3<f64>,
    /// Unit normal from A to B (world).
    pub normal: Vector3<f64>,
    /// Overlap (m); <= 0 for a contact inside the envelope that does not touch.
    pub overlap: f64,
    /// Normal force magnitude (N).
    pub normal_force: f64,
    /// Total force on B at `point` (N, world); A gets `-force`.
    pub force: Vector3<f64>,
    /// Couple on B from rolling and spinning resistance (N m, world); A gets `-torque`.
    pub torque: Vector3<f64>,
    /// Per-body rolling torque magnitudes on A and B ([`SmcForce::rolling`]).
    pub rolling: [f64; 2],
}

/// Normal stiffness law of a pair: `(F_elastic, S_n = dF/d delta, c_n)` for overlap
/// `delta`, where the normal force is `F_elastic + c_n delta_dot`.
#[inline]
fn normal_law(model: SmcModel, pair: &SmcPair, v_c: f64, delta: f64) -> (f64, f64, f64) {
    match model {
        SmcModel::Hertz => {
            let k = 4.0 / 3.0 * pair.young * pair.radius.sqrt();
            let sd = delta.sqrt();
            let c = pair.alpha * (pair.mass * k).sqrt() * sd.sqrt();
            (k * delta * sd, 1.5 * k * sd, c)
        }
        SmcModel::Hooke => {
            let k = hooke_stiffness(pair, v_c);
            (k * delta, k, pair.alpha * (pair.mass * k).sqrt())
        }
    }
}

/// Maximum overlap of an undamped Hertz impact at speed `v` (m):
/// `delta_max = (15 m v^2 / (16 E* sqrt(R)))^(2/5)` (Johnson 1985, §11.4).
pub fn hertz_max_overlap(young: f64, radius: f64, mass: f64, v: f64) -> f64 {
    (15.0 * mass * v * v / (16.0 * young * radius.sqrt())).powf(0.4)
}

/// The Hooke stiffness `k = m v_c^2 / delta_max^2` (N/m): the linear spring with the Hertz
/// contact's maximum overlap at the characteristic speed `v_c`.
pub fn hooke_stiffness(pair: &SmcPair, v_c: f64) -> f64 {
    let d = hertz_max_overlap(pair.young, pair.radius, pair.mass, v_c);
    pair.mass * v_c * v_c / (d * d)
}

/// Duration of an undamped contact (s): Hertz `t_c = 2.9432 delta_max / v` (Johnson 1985,
/// eq. 11.24, at the impact speed `v`), Hooke `t_c = pi sqrt(m / k)`.
pub fn contact_duration(model: SmcModel, pair: &SmcPair, v: f64) -> f64 {
    match model {
        SmcModel::Hertz => 2.9432 * hertz_max_overlap(pair.young, pair.radius, pair.mass, v) / v,
        SmcModel::Hooke => std::f64::consts::PI * (pair.mass / hooke_stiffness(pair, v)).sqrt(),
    }
}

/// The rolling spring's stiffness is capped at `I (w h / h)^2` with this `w h` (`I` the
/// pair's centroidal effective inertia, [`SmcPair::inertia`]): the explicit step needs
/// `omega h < 2` for the sum of a body's contacts, so 0.5 holds for up to 16 binding ones.
pub const MAX_ROLLING_OMEGA_H: f64 = 0.5;

/// The rolling dashpot's coefficient is capped at this fraction of `I / h`: the explicit
/// step needs `C h / I < 2` for the sum of a body's contacts.
pub const MAX_ROLLING_DAMPING_H: f64 = 0.25;

/// Rotate a stored history vector into the tangent plane of `n`, keeping its length.
#[inline]
fn into_tangent_plane(v: &Vector3<f64>, n: &Vector3<f64>) -> Vector3<f64> {
    let mut t = v - n * v.dot(n);
    let (len0, len1) = (v.norm(), t.norm());
    if len1 > 0.0 {
        t *= len0 / len1;
    }
    t
}

/// The force of one contact, updating its history (tangential displacement `xi`, rolling
/// angle; see the module docs). `v_c` is the characteristic speed (Hooke stiffness), `h` the
/// step (s). Pure function.
#[inline]
pub fn contact_force(
    model: SmcModel,
    pair: &SmcPair,
    v_c: f64,
    kin: &SmcKinematics,
    history: &SmcHistory,
    h: f64,
) -> SmcForce {
    let n = kin.normal;
    let delta = kin.overlap;
    if delta <= 0.0 {
        return SmcForce {
            normal: 0.0,
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
            rolling: [0.0; 2],
            history: SmcHistory::default(),
        };
    }
    let vr = kin.relative_velocity;
    let vn = vr.dot(&n);
    let vt = vr - n * vn;
    let (elastic, s_n, c_n) = normal_law(model, pair, v_c, delta);
    // delta_dot = -vn (approach positive).
    let f_n = (elastic - c_n * vn).max(0.0);

    // Tangential spring: rotate the history into the tangent plane keeping its length.
    let k_t = match model {
        SmcModel::Hertz => 8.0 * pair.shear * (pair.radius * delta).sqrt(),
        SmcModel::Hooke => 2.0 / 7.0 * s_n,
    };
    let c_t = c_n * (k_t / s_n).sqrt();
    let mut xi = into_tangent_plane(&history.tangential, &n);
    xi += vt * h;
    let mut f_t = -k_t * xi - c_t * vt;
    let cap = pair.friction * f_n;
    let ft_len = f_t.norm();
    if ft_len > cap {
        f_t *= if ft_len > 0.0 { cap / ft_len } else { 0.0 };
        xi = -f_t / k_t;
    }

    // Rolling and spinning resistance: a couple (torque on B, -torque on A) and, for the
    // per-body rolling model, the magnitudes of each body's own torque.
    let mut torque = Vector3::zeros();
    let mut rolling = [0.0; 2];
    let mut theta = Vector3::zeros();
    if (pair.rolling_friction > 0.0 || pair.spinning_friction > 0.0) && f_n > 0.0 {
        let w = kin.angular_velocity_b - kin.angular_velocity_a;
        let ws = n * w.dot(&n);
        let full = pair.rolling_friction * pair.radius * f_n;
        let couples = match pair.rolling_model {
            RollingModel::Relative => [(full, w - ws), (pair.spinning_friction, ws)],
            RollingModel::Spring
                if pair.rolling_friction > 0.0 && pair.rolling_inertia.is_finite() =>
            {
                let wr = w - ws;
                theta = into_tangent_plane(&history.rolling, &n) + wr * h;
                // Only as stiff and damped as the step resolves: a flat contact (`R` =
                // `flat_contact_radius`) of a small body would exceed both at the normal
                // law's step. Against the centroidal inertia: a body's contacts add up
                // about its centre.
                let k_r = (2.25 * s_n * (pair.rolling_friction * pair.radius).powi(2))
                    .min((MAX_ROLLING_OMEGA_H / h).powi(2) * pair.inertia);
                let mut m_k = -k_r * theta;
                let len = m_k.norm();
                if len > full {
                    m_k *= full / len;
                    theta = -m_k / k_r;
                    torque += m_k;
                } else {
                    let c_r = (2.0 * pair.rolling_damping * (pair.rolling_inertia * k_r).sqrt())
                        .min(MAX_ROLLING_DAMPING_H * pair.inertia / h);
                    torque += m_k - c_r * wr;
                }
                [(0.0, Vector3::zeros()), (pair.spinning_friction, ws)]
            }
            RollingModel::Spring => [(0.0, Vector3::zeros()), (pair.spinning_friction, ws)],
            RollingModel::PerBody => {
                for (k, omega) in [kin.angular_velocity_a, kin.angular_velocity_b]
                    .iter()
                    .enumerate()
                {
                    if omega.norm() > 0.0 {
                        rolling[k] = full;
                    }
                }
                [(0.0, Vector3::zeros()), (pair.spinning_friction, ws)]
            }
        };
        for (k, (m, omega)) in couples.into_iter().enumerate() {
            // The spinning coefficient still needs its `R F_n`.
            let m = if k == 1 { m * pair.radius * f_n } else { m };
            let len = omega.norm();
            if m > 0.0 && len > 0.0 {
                torque -= omega * (m.min(pair.inertia * len / h) / len);
            }
        }
    }
    SmcForce {
        normal: f_n,
        force: n * f_n + f_t,
        torque,
        rolling,
        history: SmcHistory {
            tangential: xi,
            rolling: theta,
        },
    }
}

/// The per-body rolling torque (N m, world) on a body turning at `omega` (rad/s, world)
/// from the summed magnitudes `total` (N m) of its contacts' [`SmcForce::rolling`]: against
/// `omega`, limited so that it cannot reverse `omega` within the step `h` (`inertia` the
/// body's rotational inertia, kg m^2).
pub fn per_body_rolling_torque(
    omega: &Vector3<f64>,
    total: f64,
    inertia: f64,
    h: f64,
) -> Vector3<f64> {
    let len = omega.norm();
    if total > 0.0 && len > 0.0 {
        -omega * (total.min(inertia * len / h) / len)
    } else {
        Vector3::zeros()
    }
}

/// The coefficient of restitution of the dimensionless contact
/// `X'' = -max(X^p + alpha X^q X', 0)`, `X(0) = 0`, `X'(0) = 1` (RK4): the separation
/// speed, i.e. `-X'` when the force first vanishes after the turning point (the motion is
/// free afterwards).
pub fn restitution_of_damping(model: SmcModel, alpha: f64) -> f64 {
    let (p, q) = model.exponents();
    let acc = |x: f64, v: f64| {
        if x <= 0.0 {
            0.0
        } else {
            -(x.powf(p) + alpha * x.powf(q) * v).max(0.0)
        }
    };
    let dt = 2e-4;
    let (mut x, mut v) = (0.0_f64, 1.0_f64);
    for _ in 0..2_000_000 {
        let (k1x, k1v) = (v, acc(x, v));
        let (k2x, k2v) = (
            v + 0.5 * dt * k1v,
            acc(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v),
        );
        let (k3x, k3v) = (
            v + 0.5 * dt * k2v,
            acc(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v),
        );
        let (k4x, k4v) = (v + dt * k3v, acc(x + dt * k3x, v + dt * k3v));
        x += dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        v += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        if v < 0.0 && (x <= 0.0 || acc(x, v) == 0.0) {
            return -v;
        }
        if v >= 0.0 && x <= 0.0 {
            // Over-damped to rest at the surface.
            return 0.0;
        }
    }
    0.0
}

/// The smallest restitution [`damping_for_restitution`] resolves; lower values map to it.
pub const MIN_RESTITUTION: f64 = 1e-3;

/// The dimensionless damping `alpha` that gives the restitution `e` in `[0, 1]` for
/// `model` (bisection on [`restitution_of_damping`] to 1e-10; `e < MIN_RESTITUTION` is
/// treated as `MIN_RESTITUTION`). Costs a few milliseconds: cache the result per material.
pub fn damping_for_restitution(model: SmcModel, e: f64) -> Result<f64> {
    if !(e.is_finite() && (0.0..=1.0).contains(&e)) {
        return Err(ChronoError::invalid(
            "material.restitution",
            e,
            "must be in [0, 1]",
        ));
    }
    if e >= 1.0 {
        return Ok(0.0);
    }
    let e = e.max(MIN_RESTITUTION);
    // A pure function of (model, e): memoized for the process (few distinct values).
    static MEMO: std::sync::Mutex<Vec<(SmcModel, u64, f64)>> = std::sync::Mutex::new(Vec::new());
    let key = (model, e.to_bits());
    if let Ok(memo) = MEMO.lock()
        && let Some(&(_, _, a)) = memo.iter().find(|m| (m.0, m.1) == key)
    {
        return Ok(a);
    }
    let a = bisect_damping(model, e);
    if let Ok(mut memo) = MEMO.lock() {
        memo.push((model, key.1, a));
    }
    Ok(a)
}

fn bisect_damping(model: SmcModel, e: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0);
    while restitution_of_damping(model, hi) > e {
        hi *= 2.0;
        if hi > 1e6 {
            return hi;
        }
    }
    while hi - lo > 1e-10 * hi {
        let mid = 0.5 * (lo + hi);
        if restitution_of_damping(model, mid) > e {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}
