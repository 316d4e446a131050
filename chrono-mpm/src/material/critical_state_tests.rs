//! Tests of the critical-state sand: the steady simple shear of the rheology, the
//! dilatancy law's critical packing, Heyman et al.'s criterion, the return's surface.

use super::*;
use nalgebra::Rotation3;
use proptest::prelude::*;

fn sand(phi0: f64) -> CriticalStateSand {
    CriticalStateSand::glass_beads(2e6, 0.3, phi0).unwrap()
}

/// What a sheared marker ends at.
struct Sheared {
    /// `tau_xz / p` at the end.
    ratio: f64,
    /// The largest `tau_xz / p` on the way.
    ratio_max: f64,
    /// Pressure (Kirchhoff), Pa.
    p: f64,
    /// `I` of the imposed shear rate at the end pressure.
    i: f64,
    /// Packing fraction at the end.
    phi: f64,
}

/// Simple shear `v_x = gamma_dot z` of one marker at the imposed pressure `p0` (Pa): each
/// step the shear increment, then a stretch along `z` that brings the trial pressure back
/// to `p0` (the pressure-imposed shear cell), then the return; `strain` is the total shear.
fn shear(m: &CriticalStateSand, gamma_dot: f64, p0: f64, dt: f64, strain: f64) -> Sheared {
    let bulk = m.elastic.lambda + 2.0 * m.elastic.mu / 3.0;
    let mut fe = Matrix3::identity() * (-p0 / bulk / 3.0).exp();
    let mut fp = Matrix3::identity();
    let steps = (strain / (gamma_dot * dt)).ceil() as usize;
    let mut l = Matrix3::zeros();
    l[(0, 2)] = gamma_dot * dt;
    let mut ratio_max = f64::NEG_INFINITY;
    let mut ratio = 0.0;
    let mut p = 0.0;
    for _ in 0..steps {
        let mut tr = (Matrix3::identity() + l) * fe;
        let s = (-p0 / bulk).exp() / tr.determinant();
        tr = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, s)) * tr;
        (fe, fp) = m.project_step(&tr, &fp, dt).unwrap();
        let tau = hencky::kirchhoff(&m.elastic, &fe);
        p = -tau.trace() / 3.0;
        ratio = tau[(0, 2)] / p;
        ratio_max = ratio_max.max(ratio);
    }
    let i = gamma_dot * m.grain_diameter / (p / m.grain_density).sqrt();
    Sheared {
        ratio,
        ratio_max,
        p,
        i,
        phi: m.packing_of(&fe, &fp),
    }
}

#[test]
fn steady_simple_shear_is_the_rheology_and_the_critical_packing() {
    // Dense (phi0 0.62) and loose (0.52) glass beads sheared at imposed pressure 1 kPa at
    // I about 1e-3, 0.1 and 0.5: at steady state t/p = mu(I) and phi = phi_eq(I) of the
    // imposed rate, whatever the start; the dense start passes through a peak above
    // mu(I) (it dilates, tan(psi) > 0), the loose one stays below it (it compacts).
    let p0 = 1e3;
    let speed = (p0 / 2450.0f64).sqrt();
    for i_target in [1e-3, 0.1, 0.5] {
        let gamma_dot = i_target * speed / 0.53e-3;
        // about 1e-3 of shear per step; 6 strains (15 e-foldings of the dilatancy)
        let dt = 1e-3 / gamma_dot;
        for phi0 in [0.62, 0.52] {
            let m = sand(phi0);
            let r = shear(&m, gamma_dot, p0, dt, 6.0);
            assert!((r.p - p0).abs() < 1e-6 * p0, "p {}", r.p);
            let mu = m.mu(r.i);
            assert!(
                (r.ratio - mu).abs() < 5e-3 * mu,
                "I {:.4}, phi0 {phi0}: t/p {:.5} vs mu(I) {mu:.5}",
                r.i,
                r.ratio
            );
            let phi_eq = m.phi_eq(r.i);
            assert!(
                (r.phi - phi_eq).abs() < 1e-3,
                "I {:.4}, phi0 {phi0}: phi {:.5} vs phi_eq(I) {phi_eq:.5}",
                r.i,
                r.phi
            );
            if phi0 > phi_eq {
                // the peak: at least a quarter of the initial tan(psi) above mu(I)
                let peak = mu + 0.25 * m.dilatancy * (phi0 - phi_eq);
                assert!(r.ratio_max > peak, "dense peak {} < {peak}", r.ratio_max);
            } else {
                assert!(r.ratio_max < mu + 1e-3, "loose peak {}", r.ratio_max);
            }
        }
    }
    // Without dilatancy the packing does not move from its elastically compressed start
    // (the non-dilatant mu(I)).
    let m = CriticalStateSand {
        dilatancy: 0.0,
        ..sand(0.62)
    };
    let r = shear(&m, 100.0, p0, 1e-5, 2.0);
    let bulk = m.elastic.lambda + 2.0 * m.elastic.mu / 3.0;
    let start = 0.62 * (p0 / bulk).exp();
    assert!((r.phi - start).abs() < 1e-9, "{} vs {start}", r.phi);
}

#[test]
fn heyman_criterion_holds_for_the_glass_beads_and_can_fail() {
    // mu_b = 2 / (K_d delta_phi I) against 1 - 7 mu / 6 and 2 - 2 mu, for I from 1e-6 to
    // 2 (the dense regime and beyond).
    let m = sand(0.6);
    let mut i = 1e-6;
    while i <= 2.0 {
        assert!(m.well_posed_at(i), "I {i}: mu_b {}", m.bulk_friction(i));
        i *= 1.1;
    }
    // It fails for too little dissipation on volume change (a hundredfold K_d x delta_phi
    // at I = 1) and does not apply without dilatancy.
    let stiff = CriticalStateSand {
        dilatancy: 100.0,
        ..m
    };
    assert!(!stiff.well_posed_at(1.0));
    assert!(stiff.well_posed_at(1e-3));
    let none = CriticalStateSand {
        dilatancy: 0.0,
        ..m
    };
    assert!(!none.well_posed_at(0.1));
}

/// The rate-independent return (`dt` infinite) of a random state: on or inside
/// `q <= sqrt(2) mu_eff p`, on it after a plastic step (or stress-free at the apex),
/// `F_E F_P` kept, idempotent.
fn check(
    m: &CriticalStateSand,
    a: [f64; 6],
    e: [f64; 3],
    jp: f64,
) -> std::result::Result<(), TestCaseError> {
    let r1 = Rotation3::from_euler_angles(a[0], a[1], a[2]).into_inner();
    let r2 = Rotation3::from_euler_angles(a[3], a[4], a[5]).into_inner();
    let fe = r1 * Matrix3::from_diagonal(&Vector3::from(e).map(f64::exp)) * r2;
    let fp = Matrix3::identity() * jp.cbrt();
    let (fe1, fp1) = m.project(&fe, &fp).unwrap();
    let eps1 = strains_of(&fe1).unwrap();
    let (dev, tr) = split(&m.principal_stress(&eps1));
    let (q, p) = (dev.norm(), -tr / 3.0);
    let phi = m.packing_of(&fe, &fp);
    let mu_eff = (m.mu(0.0) + m.tan_psi(phi, 0.0)).max(0.0);
    let scale = m.elastic.young * (1e-3 + Vector3::from(e).norm());
    prop_assert!(p >= -1e-12 * scale, "tension p {p}");
    prop_assert!(
        q <= SQRT2 * mu_eff * p + 1e-9 * scale,
        "q {q} > {}",
        SQRT2 * mu_eff * p
    );
    let eps0 = Vector3::from(e);
    if fe1 != fe {
        let on = (q - SQRT2 * mu_eff * p).abs() <= 1e-9 * scale;
        let apex = q <= 1e-9 * scale;
        prop_assert!(on || apex, "plastic but q {q}, p {p}, mu_eff {mu_eff}");
    } else {
        prop_assert!(m.return_strain(&eps0, fe.determinant() * jp, f64::INFINITY) == eps0);
    }
    prop_assert!((fe1 * fp1 - fe * fp).norm() < 1e-9);
    prop_assert!((m.packing_of(&fe1, &fp1) - phi).abs() < 1e-12);
    let (fe2, fp2) = m.project(&fe1, &fp1).unwrap();
    prop_assert!((fe2 - fe1).norm() < 1e-9, "not idempotent");
    prop_assert!((fp2 - fp1).norm() < 1e-9);
    Ok(())
}

proptest! {
    #[test]
    fn return_lands_on_or_inside_and_is_idempotent(
        a in prop::array::uniform6(-3.0f64..3.0),
        e in prop::array::uniform3(-0.02f64..0.01),
        jp in 0.9f64..1.15,
        phi0 in 0.5f64..0.65,
    ) {
        check(&sand(phi0), a, e, jp)?;
    }
}

#[test]
fn rate_return_holds_mu_i_at_the_step_rate() {
    // At the critical packing (tan psi = 0 at the step's I is not assumed: the return's
    // own I and tan(psi)) the returned deviator is sqrt(2) mu_eff(I) p with I from the
    // plastic increment of the step and the trial pressure.
    let m = sand(0.6);
    let bulk = m.elastic.lambda + 2.0 * m.elastic.mu / 3.0;
    let g2 = 2.0 * m.elastic.mu;
    for (vol, shear, dt) in [
        (-1e-3, 5e-3, 1e-4),
        (-2e-4, 1e-3, 1e-5),
        (-1e-3, 2e-2, 1e-3),
    ] {
        let eps = Vector3::new(vol / 3.0 + shear, vol / 3.0, vol / 3.0 - shear);
        let out = m.return_strain(&eps, 1.0, dt);
        let (dev0, tr0) = split(&eps);
        let (dev1, tr1) = split(&out);
        let p_tr = -bulk * tr0;
        let delta = dev0.norm() - dev1.norm();
        assert!(delta > 0.0);
        let i = SQRT2 * delta / dt * m.grain_diameter / (p_tr / m.grain_density).sqrt();
        let tan_psi = m.tan_psi(0.6, i);
        let p = -bulk * tr1;
        assert!(
            (p - (p_tr + bulk * SQRT2 * tan_psi * delta)).abs() < 1e-9 * p_tr,
            "dilation: p {p}"
        );
        let q = g2 * dev1.norm();
        let target = SQRT2 * (m.mu(i) + tan_psi) * p;
        assert!((q - target).abs() < 1e-9 * q, "I {i}: q {q} vs {target}");
    }
    // tension: stress-free
    assert_eq!(
        m.return_strain(&Vector3::new(1e-3, 0.0, -5e-4), 1.0, 1e-4),
        Vector3::zeros()
    );
}

#[test]
fn bad_input_names_the_field() {
    let e = CriticalStateSand::glass_beads(2e6, 0.3, 1.2).unwrap_err();
    assert!(
        e.to_string().contains("material.critical_state.phi0"),
        "{e}"
    );
    let e = CriticalStateSand::glass_beads(-2e6, 0.3, 0.6).unwrap_err();
    assert!(e.to_string().contains("material.young"), "{e}");
    let m = sand(0.6);
    for (bad, field) in [
        (CriticalStateSand { i0: 0.0, ..m }, "i0"),
        (CriticalStateSand { mu_2: 0.1, ..m }, "mu_2"),
        (
            CriticalStateSand {
                dilatancy: f64::NAN,
                ..m
            },
            "dilatancy",
        ),
        (CriticalStateSand { phi_c: 1.0, ..m }, "phi_c"),
        (
            CriticalStateSand {
                delta_phi: -0.1,
                ..m
            },
            "delta_phi",
        ),
        (
            CriticalStateSand {
                grain_diameter: 0.0,
                ..m
            },
            "grain_diameter",
        ),
    ] {
        let e = bad.validated().unwrap_err().to_string();
        assert!(
            e.contains(&format!("material.critical_state.{field}")),
            "{e}"
        );
    }
    // a degenerate state is refused, not returned
    assert!(
        m.project_step(&Matrix3::zeros(), &Matrix3::identity(), 1e-4)
            .is_none()
    );
}
