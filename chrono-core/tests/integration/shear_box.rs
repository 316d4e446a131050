//! The direct shear box's measurements through the public API (`granular::probe`,
//! `granular::shear_box`): the contact forces read from the last step (both methods)
//! against statics, and the peak / residual reduction.

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::granular::probe::{grain_forces_on, uniaxial_overlap_strain};
use chrono_core::granular::shear_box::{
    dilatancy_corrected_ratio, dilation_rate, peak_and_residual, peak_bin, residual_dilation_rate,
};
use chrono_core::granular::{Grain, add_grains};
use chrono_core::math::{GRAVITY, Isometry3, Vector3};
use chrono_core::system::ContactMethod;
use chrono_core::{ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};

#[test]
fn peak_and_residual_of_a_curve() {
    // Rises to 0.6 at s = 0.2, decays to 0.4.
    let bins: Vec<(f64, f64)> = (1..=40)
        .map(|k| {
            let s = k as f64 * 0.05;
            let y = if s <= 0.2 {
                3.0 * s
            } else {
                0.4 + 0.2 * (-(s - 0.2) / 0.2).exp()
            };
            (s, y)
        })
        .collect();
    let (peak, res) = peak_and_residual(&bins, 0.5, 0.3).unwrap();
    assert!(peak > 0.5 && peak <= 0.6, "{peak}");
    assert!((res - 0.4).abs() < 0.01, "{res}");
    assert!(peak_and_residual(&bins[..3], 0.5, 0.3).is_err());
    // The best 3-bin window is the corner (0.6 at s = 0.2) and the two bins after it,
    // whose decay is slower than the rise before it: centred at s = 0.25.
    let i = peak_bin(&bins, 0.5).unwrap();
    assert!((bins[i].0 - 0.25).abs() < 1e-12, "{}", bins[i].0);
    // Searched only up to peak_window: from s = 1.0 on, the last bins win.
    let rising: Vec<(f64, f64)> = bins.iter().map(|&(s, _)| (s, s)).collect();
    let i = peak_bin(&rising, 0.5).unwrap();
    assert!((rising[i].0 - 1.0).abs() < 1e-12, "{}", rising[i].0);
}

#[test]
fn dilation_rate_is_the_local_slope() {
    // Plate rise: y = 0.1 x up to x = 0.5, then flat (a dense sample reaching its
    // critical state); noise-free, so the fit is exact inside each part.
    let rise: Vec<(f64, f64)> = (0..=40)
        .map(|k| {
            let x = k as f64 * 0.05;
            (x, 0.1 * x.min(0.5))
        })
        .collect();
    let at = |x: f64| rise.iter().position(|p| (p.0 - x).abs() < 1e-9).unwrap();
    assert!((dilation_rate(&rise, at(0.25), 0.15) - 0.1).abs() < 1e-12);
    assert!(dilation_rate(&rise, at(1.5), 0.15).abs() < 1e-12);
    // Straddling the corner: between the two slopes.
    let r = dilation_rate(&rise, at(0.5), 0.15);
    assert!(r > 0.02 && r < 0.08, "{r}");
    // Outside the bins: no rate (NaN, not a panic).
    assert!(dilation_rate(&rise, 99, 0.15).is_nan());
}

#[test]
fn dilatancy_corrected_ratio_recovers_mu_cv() {
    // A sample that obeys Taylor's balance with mu_cv = 0.45: it contracts (y = -0.05 x^2,
    // dy/dx = -0.1 x) and its ratio is 0.45 + dy/dx; the correction over the bins from
    // x = 0.3 gives back 0.45 (the local fit of a parabola's slope is exact at interior bins;
    // near the end the one-sided window shifts it by O(h^2)).
    let xs: Vec<f64> = (1..=30).map(|k| k as f64 * 0.05).collect();
    let rise: Vec<(f64, f64)> = xs.iter().map(|&x| (x, -0.05 * x * x)).collect();
    let ratio: Vec<(f64, f64)> = xs.iter().map(|&x| (x, 0.45 - 0.1 * x)).collect();
    let mu = dilatancy_corrected_ratio(&ratio, &rise, 0.3, 0.15);
    assert!((mu - 0.45).abs() < 2e-3, "{mu}");
    // A ratio above the balance by 0.05 everywhere shows as 0.50.
    let high: Vec<(f64, f64)> = ratio.iter().map(|&(x, r)| (x, r + 0.05)).collect();
    let mu = dilatancy_corrected_ratio(&high, &rise, 0.3, 0.15);
    assert!((mu - 0.50).abs() < 2e-3, "{mu}");
    assert!(dilatancy_corrected_ratio(&ratio, &rise, 9.0, 0.15).is_nan());
}

#[test]
fn residual_dilation_rate_is_the_late_slope() {
    // Rise 0.1 x up to x = 1, then 0.02 x (a dense sample still dilating slowly at the end):
    // the slope over the last 30 % of x_max = 1.5 (x >= 1.05) is 0.02.
    let rise: Vec<(f64, f64)> = (1..=30)
        .map(|k| {
            let x = k as f64 * 0.05;
            (
                x,
                if x <= 1.0 {
                    0.1 * x
                } else {
                    0.1 + 0.02 * (x - 1.0)
                },
            )
        })
        .collect();
    assert!((residual_dilation_rate(&rise, 0.3) - 0.02).abs() < 1e-12);
    assert!(residual_dilation_rate(&rise[..1], 0.3).is_nan());
}

/// The material of every body in the contact tests below.
fn material() -> ContactMaterial {
    ContactMaterial::smc(1e7, 0.3, 0.5, 0.5)
}

/// A system of `method` with a 0.1 mm envelope and a tight solve (NSC).
fn small_system(method: ContactMethod, max_iterations: usize) -> System {
    let settings = SystemSettings {
        envelope: 1e-4,
        contact_method: method,
        ..SystemSettings::default()
    };
    let solver = Apgd::new(SolverSettings {
        tolerance: 1e-8,
        max_iterations,
        record_history: false,
    });
    System::new(settings, Box::new(solver)).unwrap()
}

/// A fixed square plate 1 cm thick, half side `half` (m), its top at height `top` (m).
fn fixed_plate(half: f64, top: f64) -> RigidBodyBuilder {
    RigidBodyBuilder::fixed().collider(
        Shape::Box {
            half_extents: Vector3::new(half, half, 0.005),
        },
        Isometry3::from_parts(
            Vector3::new(0.0, 0.0, top - 0.005).into(),
            Default::default(),
        ),
        material(),
    )
}

/// A sphere resting on a fixed plate and pushed sideways by a force below the
/// friction limit: the grain forces on the plate are its weight and the push, by both
/// methods.
#[test]
fn grain_forces_on_a_plate_balance_weight_and_push() {
    for method in [ContactMethod::Nsc, ContactMethod::Smc] {
        let mut sys = small_system(method, 500);
        let plate = sys.add_body(fixed_plate(0.05, 0.005)).unwrap();
        let r = 0.003;
        let g = [Grain {
            center: Vector3::new(0.0, 0.0, 0.005 + r),
            radius: r,
        }];
        let b = add_grains(&mut sys, &g, 2500.0, material()).unwrap()[0];
        let m = sys.body(b).unwrap().mass();
        let push = 0.2 * m * GRAVITY.norm();
        sys.body_mut(b)
            .unwrap()
            .set_applied_force(Vector3::new(push, 0.0, 0.0))
            .unwrap();
        let h = match method {
            ContactMethod::Nsc => 1e-3,
            ContactMethod::Smc => sys.smc_max_step().unwrap().0,
        };
        // 0.2 s: the sphere rolls 2.8 cm, still on the plate (half side 5 cm).
        let n = (0.2 / h) as usize;
        let mut f = Vector3::zeros();
        for i in 0..n {
            sys.step(h).unwrap();
            // Rolling is free: the sphere accelerates; average the late steps.
            if i >= n / 2 {
                f += grain_forces_on(&sys, h, &[plate], &[plate]);
            }
        }
        f /= (n - n / 2) as f64;
        let w = m * GRAVITY.norm();
        assert!(
            (f.z + w).abs() < 0.02 * w,
            "{method:?}: {f:?} vs weight {w}"
        );
        // A free sphere rolls: friction carries 2/7 of the push (I = 2/5 m r^2).
        let expect = 2.0 / 7.0 * push;
        assert!(
            (f.x - expect).abs() < 0.05 * push,
            "{method:?}: {f:?} vs {expect}"
        );
    }
}

/// Grains placed by an affine uniaxial compression `z -> (1 - eps) z` of touching
/// columns, plus an inclined pair closed by the same field and a fixed floor that overlaps
/// the bottom grains (structure: excluded): the overlap strain is `eps`, by both methods.
#[test]
fn uniaxial_overlap_strain_of_an_affine_compression() {
    let (r, eps) = (0.003, 0.01);
    let d = 2.0 * r;
    for method in [ContactMethod::Nsc, ContactMethod::Smc] {
        let mut sys = small_system(method, 50);
        let floor = sys.add_body(fixed_plate(0.1, 0.2 * r)).unwrap();
        let mut grains = Vec::new();
        // Two touching columns of four (side by side: horizontal contacts at zero overlap).
        for ix in 0..2 {
            for k in 0..4 {
                grains.push(Grain {
                    center: Vector3::new(ix as f64 * d, 0.0, r + k as f64 * d * (1.0 - eps)),
                    radius: r,
                });
            }
        }
        // A touching pair at 60 degrees from vertical, away from the columns, mapped by the
        // same compression.
        let (th, c0) = (60f64.to_radians(), Vector3::new(0.05, 0.05, 0.02));
        grains.push(Grain {
            center: c0,
            radius: r,
        });
        grains.push(Grain {
            center: c0 + d * Vector3::new(th.sin(), 0.0, th.cos() * (1.0 - eps)),
            radius: r,
        });
        add_grains(&mut sys, &grains, 2500.0, material()).unwrap();
        // A step short enough that the contacts are those of the placed configuration.
        sys.step(1e-7).unwrap();
        let e = uniaxial_overlap_strain(&sys, &[floor]).unwrap();
        // Exact for the columns; the inclined pair's normal turns by O(eps), which moves the
        // fit by O(eps^2).
        assert!(
            (e - eps).abs() < 2.0 * eps * eps,
            "{method:?}: {e} vs {eps}"
        );
        // With the floor counted as a grain its deep overlaps (0.8 r, n_z = 1) pull the
        // fit up: the exclusion is what makes it `eps`.
        let with_floor = uniaxial_overlap_strain(&sys, &[]).unwrap();
        assert!(with_floor > 2.0 * eps, "{method:?}: {with_floor}");
    }
}
