//! Problems captured from scenes built with the public API (`System::last_problem`), the
//! ones of the solver benchmarks, plus a synthetic bilateral net.
//!
//! - a settled granular pile: a square pyramid of spheres in body-centred stacking (each
//!   sphere of a layer rests in the pocket of four below, the layer is touching in-plane),
//!   radii jittered by 1 %, on a fixed ground box, settled for a few steps with APGD, then
//!   the problem of the last step (about 6 contacts per sphere);
//! - the heavy stack: 5 unit boxes, each 3 times heavier than the one below (top 81x bottom),
//!   on a half-space, captured after a few steps;
//! - a particle net with distance rows (bilateral only) for CG/MINRES.

use chrono_core::descriptor::{CcpProblem, ConstraintRows, MassOperator, RowEntry, Variables};
use chrono_core::math::{GRAVITY, Isometry3, Vector3};
use chrono_core::rng::Rng;
use chrono_core::{ChronoError, ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};

use crate::{SolverSettings, by_name};

/// Sphere radius of the pile, m.
pub const PILE_RADIUS: f64 = 0.05;

/// Number of contacts of a pyramid with a base of `n x n` spheres (ground contacts, four
/// pocket contacts per upper sphere, in-plane neighbours).
pub fn pyramid_contacts(n: usize) -> usize {
    (0..n)
        .map(|k| {
            let m = n - k;
            let down = if k == 0 { m * m } else { 4 * m * m };
            down + 2 * m * m.saturating_sub(1)
        })
        .sum()
}

/// The base size whose pyramid has the number of contacts nearest `target`.
pub fn pyramid_base_for(target: usize) -> usize {
    (1..400)
        .min_by_key(|&n| pyramid_contacts(n).abs_diff(target))
        .unwrap_or(1)
}

/// Build the pile with about `n_contacts` contacts, settle it `settle_steps` steps of
/// `h` s, and return the problem of the last step, its solution by the scene's solver and
/// the number of spheres.
pub fn granular_pile(
    n_contacts: usize,
    settle_steps: usize,
    h: f64,
) -> chrono_core::Result<(CcpProblem, Vec<f64>, usize)> {
    if n_contacts < 1 {
        return Err(ChronoError::invalid(
            "n_contacts",
            n_contacts,
            "must be >= 1",
        ));
    }
    if settle_steps < 1 {
        return Err(ChronoError::invalid(
            "settle_steps",
            settle_steps,
            "must be >= 1",
        ));
    }
    let n = pyramid_base_for(n_contacts);
    let settings = SolverSettings {
        tolerance: 1e-5,
        max_iterations: 30,
        record_history: false,
    };
    let solver = by_name("apgd", settings)?;
    let mut sys = System::new(SystemSettings::default(), solver)?;
    let mat = ContactMaterial::with_friction(0.5);
    let r = PILE_RADIUS;
    let half = (n as f64 + 2.0) * r * 2.0;
    sys.add_body(RigidBodyBuilder::fixed().name("ground").collider(
        Shape::Box {
            half_extents: Vector3::new(half, half, 0.5),
        },
        Isometry3::translation(0.0, 0.0, -0.5),
        mat,
    ))?;
    let mut rng = Rng::splitmix64(12345);
    let dz = r * 2f64.sqrt();
    let mut count = 0;
    for k in 0..n {
        let m = n - k;
        let offset = k as f64 * r;
        for i in 0..m {
            for j in 0..m {
                let radius = r * (1.0 - 0.01 * rng.range(0.0, 1.0));
                let ball = Shape::Sphere { radius };
                let p = Vector3::new(
                    offset + 2.0 * r * i as f64,
                    offset + 2.0 * r * j as f64,
                    r + dz * k as f64,
                );
                sys.add_body(
                    RigidBodyBuilder::dynamic()
                        .mass_from_shape(&ball, 2500.0)?
                        .position(p)
                        .collider(ball, Isometry3::identity(), mat),
                )?;
                count += 1;
            }
        }
    }
    for _ in 0..settle_steps {
        sys.step(h)?;
    }
    Ok((sys.last_problem().clone(), sys.last_gamma().to_vec(), count))
}

/// The 5-box heavy stack (mass ratio 3 between levels, mu 0.5, h 10 ms) after `steps`
/// steps: its problem and the scene solver's answer.
pub fn heavy_stack(steps: usize) -> chrono_core::Result<(CcpProblem, Vec<f64>)> {
    let settings = SolverSettings {
        tolerance: 1e-7,
        max_iterations: 500,
        record_history: false,
    };
    let mut sys = System::new(SystemSettings::default(), by_name("apgd", settings)?)?;
    let mat = ContactMaterial::with_friction(0.5);
    sys.add_body(RigidBodyBuilder::fixed().collider(
        Shape::HalfSpace {
            normal: Vector3::z(),
        },
        Isometry3::identity(),
        mat,
    ))?;
    let shape = Shape::Box {
        half_extents: Vector3::repeat(0.5),
    };
    let mut density = 100.0;
    for i in 0..5 {
        let x = if i % 2 == 1 { 0.005 } else { -0.005 };
        sys.add_body(
            RigidBodyBuilder::dynamic()
                .mass_from_shape(&shape, density)?
                .position(Vector3::new(x, 0.0, 0.5 + i as f64))
                .collider(shape.clone(), Isometry3::identity(), mat),
        )?;
        density *= 3.0;
    }
    for _ in 0..steps.max(1) {
        sys.step(0.01)?;
    }
    Ok((sys.last_problem().clone(), sys.last_gamma().to_vec()))
}

/// A particle net of about `rows` bilateral rows: `n x n` particles (mass 0.5–2 kg),
/// distance rows between neighbours, the corners pinned in z and one corner in x and y,
/// small stabilization terms, gravity over one step of 10 ms. Symmetric positive definite,
/// condition number growing like `n^2`.
pub fn bilateral_net(rows: usize) -> chrono_core::Result<CcpProblem> {
    let n = ((rows as f64 / 2.0).sqrt().round() as usize).max(2);
    let mut rng = Rng::splitmix64(99);
    let mut vars = Variables::new();
    let ids: Vec<_> = (0..n * n)
        .map(|_| MassOperator::particle(rng.range(0.5, 2.0)).map(|m| vars.add(m)))
        .collect::<Result<_, _>>()?;
    let mut cr = ConstraintRows::new();
    let ex = [1.0, 0.0, 0.0];
    let ey = [0.0, 1.0, 0.0];
    let ez = [0.0, 0.0, 1.0];
    for y in 0..n {
        for x in 0..n {
            let i = ids[y * n + x];
            for (dx, dy, d) in [(1, 0, ex), (0, 1, ey)] {
                if x + dx < n && y + dy < n {
                    let j = ids[(y + dy) * n + x + dx];
                    let nd = [-d[0], -d[1], -d[2]];
                    let e = [
                        RowEntry {
                            block: j,
                            coefs: &d,
                        },
                        RowEntry {
                            block: i,
                            coefs: &nd,
                        },
                    ];
                    cr.push_bilateral(&e, rng.range(-1e-3, 1e-3), 0.0);
                }
            }
            if (x == 0 || x == n - 1) && (y == 0 || y == n - 1) {
                cr.push_bilateral(
                    &[RowEntry {
                        block: i,
                        coefs: &ez,
                    }],
                    0.0,
                    0.0,
                );
                if x == 0 && y == 0 {
                    cr.push_bilateral(
                        &[RowEntry {
                            block: i,
                            coefs: &ex,
                        }],
                        0.0,
                        0.0,
                    );
                    cr.push_bilateral(
                        &[RowEntry {
                            block: i,
                            coefs: &ey,
                        }],
                        0.0,
                        0.0,
                    );
                }
            }
        }
    }
    let mut k = vec![0.0; vars.ndof()];
    for (p, kp) in k.chunks_mut(3).enumerate() {
        let m = match vars.mass(ids[p]) {
            MassOperator::Particle { mass } => *mass,
            _ => 1.0,
        };
        kp[0] = m * rng.range(-0.05, 0.05);
        kp[2] = m * GRAVITY.z * 0.01;
    }
    let mut p = CcpProblem::new();
    p.assemble(&vars, &cr, &k)?;
    Ok(p)
}
