//! Tests of the channel scene ([`crate::channel`]).

use chrono_core::math::Vector3;
use chrono_core::shape::ellipsoid_signed_distance;

use crate::cable::{cable_distance, node_uses};
use crate::channel::{ChannelParams, channel, placement_gap};
use crate::duct::{duct_mean_coefficient, duct_velocity};

fn solver() -> Box<chrono_ccp::Psor> {
    Box::new(chrono_ccp::Psor::new(Default::default()))
}

/// The default scene: bounding spheres [`placement_gap`] (at least a spacing) apart and clear of the beams (the
/// placement's contract), no marker of a body inside another body or a beam, no beam
/// marker inside a body, no fluid inside a solid, every body inside the channel.
#[test]
fn bodies_do_not_overlap_and_are_resolved() {
    let p = ChannelParams::default();
    let s = channel(&p, solver()).unwrap();
    assert_eq!(s.bodies.len(), p.ellipsoids);
    assert_eq!(s.roots.len(), p.beams);
    let e = Vector3::from(p.semi_axes);
    let r = e.max();
    let gap = placement_gap(&p);
    assert!(gap >= p.spacing);
    let poses: Vec<_> = (s.bodies.iter())
        .map(|&b| s.system.body(b).unwrap().pose())
        .collect();
    for (i, a) in poses.iter().enumerate() {
        for b in &poses[i + 1..] {
            let d = (a.translation.vector - b.translation.vector).norm();
            assert!(d >= 2.0 * r + gap - 1e-12, "{d}");
        }
        // inside the cross-section with a spacing to spare
        let c = a.translation.vector;
        assert!(c.y - r >= gap - 1e-12 && c.y + r <= p.width - gap + 1e-12);
        assert!(c.z - r >= gap - 1e-12 && c.z + r <= p.height - gap + 1e-12);
    }
    let f = s.fluid();
    let d = f.sph().data();
    let meshes: Vec<_> = (0..f.num_cables())
        .map(|k| f.cable(k).unwrap().mesh())
        .collect();
    let uses: Vec<_> = meshes.iter().map(|m| node_uses(m)).collect();
    let (mut body_markers, mut checked) = (0, 0);
    for i in 0..d.len() {
        if d.kind[i] == chrono_sph::data::FLUID {
            continue;
        }
        let x = Vector3::new(d.x[i], d.y[i], d.z[i]);
        // which solid the marker belongs to: the one it is inside of
        let inside_bodies = poses
            .iter()
            .filter(|q| {
                ellipsoid_signed_distance(&e, &q.inverse_transform_point(&x.into()).coords) < 0.0
            })
            .count();
        let inside_beams = (meshes.iter().zip(&uses))
            .filter(|(m, u)| cable_distance(m, u, &x) < 0.0)
            .count();
        assert!(
            inside_bodies + inside_beams <= 1,
            "marker {i} at {x:?} inside {inside_bodies} bodies and {inside_beams} beams"
        );
        body_markers += inside_bodies;
        checked += 1;
    }
    assert!(
        body_markers > 100 * p.ellipsoids,
        "{body_markers} of {checked}"
    );
    let inside = s.fluid_inside(0.0).unwrap();
    assert_eq!(inside.total(), 0, "{inside:?}");
    assert_eq!(s.bodies_outside().unwrap(), 0);
}

/// A spacing that does not resolve an ellipsoid (fewer than 4 across its 4.5 cm) or a
/// beam: the builder's error names the body or the beam.
#[test]
fn unresolved_bodies_name_the_body() {
    let p = ChannelParams {
        spacing: 0.0125,
        beams: 0,
        ..ChannelParams::default()
    };
    let e = channel(&p, solver()).err().unwrap().to_string();
    assert!(e.contains("ellipsoid 0"), "{e}");
    let p = ChannelParams {
        ellipsoids: 0,
        beam_diameter: 0.025,
        ..ChannelParams::default()
    };
    let e = channel(&p, solver()).err().unwrap().to_string();
    assert!(e.contains("beam 0"), "{e}");
}

#[test]
fn bad_input_names_the_field() {
    let check = |p: ChannelParams, field: &str| {
        let e = channel(&p, solver()).err().unwrap().to_string();
        assert!(e.contains(field), "{field}: {e}");
    };
    let d = ChannelParams::default;
    check(
        ChannelParams {
            width: f64::NAN,
            ..d()
        },
        "width",
    );
    check(
        ChannelParams {
            viscosity: -1.0,
            ..d()
        },
        "viscosity",
    );
    check(
        ChannelParams {
            semi_axes: [0.0225, 0.0, 0.03],
            ..d()
        },
        "semi_axes[1]",
    );
    check(
        ChannelParams {
            ellipsoids: 60,
            ..d()
        },
        "ellipsoids",
    );
    check(
        ChannelParams {
            coupling_step: 0.05,
            ..d()
        },
        "coupling_step",
    );
    check(
        ChannelParams {
            beam_length: 0.17,
            ..d()
        },
        "beam_length",
    );
    check(
        ChannelParams {
            height: 0.05,
            ..d()
        },
        "height",
    );
    check(
        ChannelParams {
            active_supports: Some(0.5),
            ..d()
        },
        "active_supports",
    );
}

/// The empty duct (`W = H = 0.09 m`), started on the laminar profile of the body force
/// the duct series gives for `U = 0.045 m/s`, driven by that force for 0.3 s (0.7 of
/// the slowest mode's viscous time `1 / (nu pi^2 (1/W^2 + 1/H^2))` = 0.41 s: a body force
/// off by `x` would move the mean by about `0.5 x`): the fluid's mean velocity converges
/// to `U` with the spacing. Measured (docs/validation-fsi.md): +3.4 % at 12 spacings
/// across, +1.5 % at 18 (the steady excess +4.7 %, +2.0 %, +1.2 % at 12, 18, 24: the
/// walls' no-slip at second order). Checked: the error positive and below 2 % at 18
/// spacings, and falling at least at order 1.5 between 12 and 18; the centre line
/// within 3 % of the series at 18.
#[test]
fn empty_duct_converges_to_the_laminar_mean() {
    let run = |dp: f64| {
        let p = ChannelParams {
            length: 0.06,
            width: 0.09,
            height: 0.09,
            spacing: dp,
            ellipsoids: 0,
            beams: 0,
            ..ChannelParams::default()
        };
        let mut s = channel(&p, solver()).unwrap();
        for _ in 0..30 {
            s.step(0.01).unwrap();
        }
        s
    };
    let u = 0.045;
    let e1 = run(0.0075).mean_fluid_velocity() / u - 1.0;
    let s = run(0.005);
    let p = &s.params;
    let e2 = s.mean_fluid_velocity() / u - 1.0;
    assert!(e2 > 0.0 && e2 < 0.02, "{e1} {e2}");
    assert!(e2 < e1 * (0.005f64 / 0.0075).powf(1.5), "{e1} {e2}");
    // the body force is the series' for U
    let k = duct_mean_coefficient(0.045, 0.045).unwrap();
    assert!((s.body_force * p.rho * k * 0.045 * 0.045 / p.viscosity - u).abs() < 1e-15);
    let g_over_mu = p.rho * s.body_force / p.viscosity;
    let d = s.fluid().sph().data();
    let (mut sum, mut n) = (0.0, 0);
    for i in 0..d.len() {
        if d.kind[i] == chrono_sph::data::FLUID
            && (d.y[i] - 0.045).abs() < 0.5 * p.spacing + 1e-9
            && (d.z[i] - 0.045).abs() < 0.5 * p.spacing + 1e-9
        {
            sum += d.vx[i];
            n += 1;
        }
    }
    assert!(n > 0);
    let uc = sum / n as f64;
    let exact = duct_velocity(g_over_mu, 0.045, 0.045, 0.5 * p.spacing, 0.5 * p.spacing).unwrap();
    assert!((uc / exact - 1.0).abs() < 0.03, "centre {uc} vs {exact}");
}
