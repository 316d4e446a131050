//! Tests of the fully parameterized ANCF beam element ([`AncfBeam`]): finite-difference
//! checks of force and tangent, rigid motions, rank, mass, bad input.

use super::*;
use chrono_core::math::GRAVITY_MAGNITUDE;
use nalgebra::{Rotation3, Unit};

fn section() -> BeamSection {
    BeamSection::rectangle(2e11, 0.3, 7850.0, 0.02, 0.01).unwrap()
}

/// A curved element: a 20 degree arc of radius 1 in a tilted plane, unit frames.
fn curved_reference() -> [Vector3<f64>; 8] {
    let rot = Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::new(0.3, -0.5, 1.0)), 0.7);
    let node = |phi: f64| {
        let p = Vector3::new(phi.sin(), 1.0 - phi.cos(), 0.0);
        let t = Vector3::new(phi.cos(), phi.sin(), 0.0);
        let a = Vector3::new(-phi.sin(), phi.cos(), 0.0);
        [rot * p, rot * t, rot * a, rot * Vector3::z()]
    };
    let (na, nb) = (node(0.1), node(0.1 + 20f64.to_radians()));
    [na[0], na[1], na[2], na[3], nb[0], nb[1], nb[2], nb[3]]
}

fn element(reference: &[Vector3<f64>; 8], quad: BeamQuadrature) -> AncfBeam {
    let l = AncfBeam::reference_length(reference);
    AncfBeam::new([0, 1], reference, l, section(), quad).unwrap()
}

fn coords(v: &[Vector3<f64>; 8]) -> BeamVector {
    BeamVector::from_fn(|r, _| v[r / 3][r % 3])
}

/// A deterministic, well spread perturbation of the element coordinates.
fn perturbed(e0: &BeamVector, amp: f64) -> BeamVector {
    BeamVector::from_fn(|r, _| e0[r] + amp * ((r as f64 * 1.7 + 0.3).sin()))
}

#[test]
fn reference_length_of_an_arc_is_its_arc_length() {
    // The Hermite cubic through the end points and unit tangents of a 20 degree arc
    // is 2e-5 shorter than the arc (an interpolation error, ~ phi^4).
    let l = AncfBeam::reference_length(&curved_reference());
    let exact = 20f64.to_radians();
    assert!((l / exact - 1.0).abs() < 3e-5, "{l} vs {exact}");
    let straight = [
        Vector3::zeros(),
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        0.5 * Vector3::x(),
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
    ];
    assert!((AncfBeam::reference_length(&straight) - 0.5).abs() < 1e-15);
}

#[test]
fn reference_is_stress_free_and_rigid_motions_give_no_force() {
    let r0 = curved_reference();
    let el = element(&r0, BeamQuadrature::default());
    let e0 = coords(&r0);
    let scale = section().young * section().area;
    assert_eq!(el.strain_energy(&e0), 0.0);
    assert!(el.internal_force(&e0).amax() < 1e-9 * scale);
    // A large rotation and a translation of the whole element.
    let rot = Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::new(-1.0, 2.0, 0.5)), 2.1);
    let shift = Vector3::new(3.0, -1.0, 7.0);
    let moved: [Vector3<f64>; 8] = std::array::from_fn(|i| {
        if i % 4 == 0 {
            rot * r0[i] + shift
        } else {
            rot * r0[i]
        }
    });
    let f = el.internal_force(&coords(&moved));
    assert!(
        f.amax() < 1e-6 * scale * 1e-3,
        "rigid motion force {}",
        f.amax()
    );
    assert!(el.strain_energy(&coords(&moved)) < 1e-9);
    // ... while a deformation does produce one (the test can fail).
    assert!(el.internal_force(&perturbed(&e0, 1e-3)).amax() > 1e-3 * scale * 1e-3);
}

#[test]
fn force_is_the_gradient_of_the_energy() {
    let r0 = curved_reference();
    for quad in [
        BeamQuadrature::default(),
        BeamQuadrature {
            bending: 5,
            twist: 3,
            shear: 2,
        },
    ] {
        let el = element(&r0, quad);
        let e = perturbed(&coords(&r0), 0.02);
        let f = el.internal_force(&e);
        let h = 1e-6;
        for i in 0..24 {
            let (mut ep, mut em) = (e, e);
            ep[i] += h;
            em[i] -= h;
            let fd = (el.strain_energy(&ep) - el.strain_energy(&em)) / (2.0 * h);
            assert!(
                (fd - f[i]).abs() <= 1e-6 * f.amax(),
                "coordinate {i}: fd {fd} vs {}",
                f[i]
            );
        }
    }
}

#[test]
fn tangent_is_the_derivative_of_the_force() {
    let r0 = curved_reference();
    let el = element(&r0, BeamQuadrature::default());
    let e = perturbed(&coords(&r0), 0.05);
    let k = el.tangent_stiffness(&e);
    let h = 1e-6;
    for j in 0..24 {
        let (mut ep, mut em) = (e, e);
        ep[j] += h;
        em[j] -= h;
        let fd = (el.internal_force(&ep) - el.internal_force(&em)) / (2.0 * h);
        for i in 0..24 {
            assert!(
                (fd[i] - k[(i, j)]).abs() <= 1e-6 * k.amax(),
                "K[{i},{j}] = {} vs fd {}",
                k[(i, j)],
                fd[i]
            );
        }
    }
    assert!((k - k.transpose()).amax() <= 1e-12 * k.amax());
}

#[test]
fn stiffness_has_exactly_six_rigid_body_modes() {
    for r0 in [curved_reference(), {
        let x = Vector3::x();
        [
            Vector3::zeros(),
            x,
            Vector3::y(),
            Vector3::z(),
            0.5 * x,
            x,
            Vector3::y(),
            Vector3::z(),
        ]
    }] {
        let el = element(&r0, BeamQuadrature::default());
        let k = el.tangent_stiffness(&coords(&r0));
        let eig = k.symmetric_eigen().eigenvalues;
        let max = eig.amax();
        let zero = eig.iter().filter(|&&v| v.abs() < 1e-10 * max).count();
        assert_eq!(zero, 6, "eigenvalues {eig:?}");
        assert!(eig.iter().all(|&v| v > -1e-10 * max));
    }
}

#[test]
fn mass_of_a_rigid_translation_and_gravity() {
    let r0 = curved_reference();
    let el = element(&r0, BeamQuadrature::default());
    let s = section();
    let m = el.mass_matrix();
    let v = Vector3::new(0.3, -1.2, 2.0);
    let vt = BeamVector::from_fn(|r, _| if (r / 3) % 4 == 0 { v[r % 3] } else { 0.0 });
    // The mass of the reference centre line: rho A times its length, which is the
    // parameter length L by construction.
    let mass = s.density * s.area * el.length();
    let ke = 0.5 * vt.dot(&(m * vt));
    assert!((ke / (0.5 * mass * v.norm_squared()) - 1.0).abs() < 1e-5);
    let g = Vector3::new(0.0, 0.0, -GRAVITY_MAGNITUDE);
    let qg = el.gravity_force(&g);
    let total: Vector3<f64> = (0..8)
        .step_by(4)
        .map(|i| Vector3::new(qg[3 * i], qg[3 * i + 1], qg[3 * i + 2]))
        .sum();
    assert!((total - mass * g).norm() < 1e-5 * mass * GRAVITY_MAGNITUDE);
    assert!((el.mass() / mass - 1.0).abs() < 1e-5);
}

#[test]
fn bad_input_is_rejected_with_the_field() {
    let r0 = curved_reference();
    let err = AncfBeam::new([0, 1], &r0, -1.0, section(), BeamQuadrature::default()).unwrap_err();
    assert!(err.to_string().contains("element.length"), "{err}");
    let err = AncfBeam::new(
        [0, 1],
        &r0,
        0.3,
        section(),
        BeamQuadrature {
            bending: 0,
            ..Default::default()
        },
    )
    .unwrap_err();
    assert!(err.to_string().contains("quadrature.bending"), "{err}");
    let mut bad = r0;
    bad[2] = Vector3::zeros();
    bad[6] = Vector3::zeros();
    let err = AncfBeam::new([0, 1], &bad, 0.3, section(), BeamQuadrature::default()).unwrap_err();
    assert!(err.to_string().contains("element.reference"), "{err}");
}
