//! Cable nodes as contact spheres in the system's CCP: a cable dropped on the ground comes
//! to rest on it carrying its weight, a cable on an inclined plane sticks or slides as
//! Coulomb's law says, and a bad contact radius is an error naming the field.

use chrono_ccp::{Apgd, SolverSettings};
use chrono_core::math::GRAVITY_MAGNITUDE;
use chrono_core::math::Isometry3;
use chrono_core::{ContactMaterial, RigidBodyBuilder, Shape, System, SystemSettings};
use chrono_fea::{BeamMaterial, CableItem, CableMesh, CableQuadrature, FeaError};
use nalgebra::Vector3;

const G: f64 = GRAVITY_MAGNITUDE;

fn system() -> System {
    let settings = SystemSettings {
        gravity: Vector3::new(0.0, 0.0, -G),
        ..SystemSettings::default()
    };
    let solver = Apgd::new(SolverSettings {
        tolerance: 1e-12,
        max_iterations: 3000,
        record_history: false,
    });
    System::new(settings, Box::new(solver)).unwrap()
}

/// A fixed half-space through the origin with unit normal `normal` and friction `mu`.
fn ground(sys: &mut System, normal: Vector3<f64>, mu: f64) {
    sys.add_body(RigidBodyBuilder::fixed().collider(
        Shape::HalfSpace { normal },
        Isometry3::identity(),
        ContactMaterial::with_friction(mu),
    ))
    .unwrap();
}

/// 1 m, 8 elements, 2 cm square section (contact radius 1 cm), `E = 1e8` Pa,
/// `rho = 1000` kg/m^3, a little stiffness damping so the landing's bending waves die out.
fn cable(start: Vector3<f64>, end: Vector3<f64>, mu: f64) -> CableItem {
    let mat = BeamMaterial::rectangle(1e8, 1000.0, 0.02, 0.02, 1e-3).unwrap();
    let mesh = CableMesh::straight(start, end, 8, mat, CableQuadrature::default()).unwrap();
    let mut item = CableItem::new("cable", mesh).unwrap();
    item.set_contact_material(ContactMaterial::with_friction(mu))
        .unwrap();
    item
}

/// Sum of the normal impulses of the proxy contacts of the last step, N s.
fn normal_impulse(sys: &System) -> f64 {
    let (p, g) = (sys.last_problem(), sys.last_gamma());
    sys.proxy_contacts()
        .iter()
        .map(|c| g[p.row_index(c.row)])
        .sum()
}

fn max_node_speed(item: &CableItem) -> f64 {
    (0..item.mesh().nodes().len())
        .map(|n| item.node_velocity(chrono_fea::NodeId(n)).unwrap().0.norm())
        .fold(0.0, f64::max)
}

#[test]
fn dropped_cable_comes_to_rest_on_the_ground() {
    let mut sys = system();
    ground(&mut sys, Vector3::z(), 0.5);
    let z0 = 0.05;
    let item = cable(Vector3::new(0.0, 0.0, z0), Vector3::new(1.0, 0.0, z0), 0.5);
    let r = item.contact_radius();
    assert!((r - 0.01).abs() < 1e-12, "default radius {r}");
    let weight = item.mesh().total_mass() * G;
    let idx = sys.add_item(Box::new(item));
    let h = 1e-3;
    let mut touched = false;
    for _ in 0..600 {
        sys.step(h).unwrap();
        touched |= !sys.proxy_contacts().is_empty();
    }
    assert!(touched, "the cable never reached the ground");
    let item = sys.item::<CableItem>(idx).unwrap();
    let speed = max_node_speed(item);
    let pen = (item.mesh().nodes().iter())
        .map(|n| r - n.position.z)
        .fold(f64::NEG_INFINITY, f64::max);
    let force = normal_impulse(&sys) / h;
    let err = force / weight - 1.0;
    eprintln!(
        "drop: max speed {speed:.3e} m/s, max penetration {pen:.3e} m (radius {r}), \
         contact force {force:.6} N, weight {weight:.6} N, error {err:.3e}"
    );
    assert!(speed < 1e-4, "still moving at {speed} m/s");
    assert!(pen < 0.01 * r, "penetration {pen} m");
    assert!(
        err.abs() < 0.01,
        "contact force {force} N, weight {weight} N"
    );
}

/// The cable across an incline of `angle` (rad) with friction `mu`, resting on it at the
/// start; returns the mean downslope displacement and velocity of the nodes at `t1` and `t2`.
fn incline(angle: f64, mu: f64, t1: f64, t2: f64) -> [(f64, f64); 2] {
    let mut sys = system();
    // The plane z = x tan(angle): normal (-sin, 0, cos), downslope -(cos, 0, sin).
    let n = Vector3::new(-angle.sin(), 0.0, angle.cos());
    let down = -Vector3::new(angle.cos(), 0.0, angle.sin());
    ground(&mut sys, n, mu);
    let r = 0.01;
    let item = cable(
        Vector3::new(0.0, -0.5, 0.0) + r * n,
        Vector3::new(0.0, 0.5, 0.0) + r * n,
        mu,
    );
    let idx = sys.add_item(Box::new(item));
    let h = 1e-3;
    let mean = |sys: &System| {
        let item = sys.item::<CableItem>(idx).unwrap();
        let nodes = item.mesh().nodes();
        let k = nodes.len() as f64;
        let x: f64 = nodes.iter().map(|nd| nd.displacement().dot(&down)).sum();
        let v: f64 = (0..nodes.len())
            .map(|i| {
                item.node_velocity(chrono_fea::NodeId(i))
                    .unwrap()
                    .0
                    .dot(&down)
            })
            .sum();
        (x / k, v / k)
    };
    let mut out = [(0.0, 0.0); 2];
    let mut t = 0.0;
    for (slot, t_end) in [t1, t2].into_iter().enumerate() {
        while t < t_end - 0.5 * h {
            sys.step(h).unwrap();
            t += h;
        }
        out[slot] = mean(&sys);
    }
    out
}

#[test]
fn cable_on_an_incline_sticks_below_the_friction_angle() {
    let mu = 0.5;
    let angle = 20f64.to_radians(); // tan = 0.364 < mu
    let [_, (x, v)] = incline(angle, mu, 0.1, 0.5);
    eprintln!("incline stick: downslope displacement {x:.3e} m, velocity {v:.3e} m/s");
    assert!(x.abs() < 1e-5, "crept {x} m");
    assert!(v.abs() < 1e-4, "moving at {v} m/s");
}

#[test]
fn cable_on_an_incline_slides_above_the_friction_angle() {
    let mu = 0.3;
    let angle = 30f64.to_radians(); // tan = 0.577 > mu
    let (t1, t2) = (0.1, 0.5);
    let [(_, v1), (_, v2)] = incline(angle, mu, t1, t2);
    let a = (v2 - v1) / (t2 - t1);
    let exact = G * (angle.sin() - mu * angle.cos());
    let err = a / exact - 1.0;
    eprintln!("incline slide: a = {a:.6} m/s^2, g (sin - mu cos) = {exact:.6}, error {err:.3e}");
    assert!(err.abs() < 0.03, "a = {a}, exact {exact}");
}

#[test]
fn bad_contact_radius_names_the_field() {
    let mut item = cable(Vector3::zeros(), Vector3::x(), 0.5);
    for r in [0.0, -1.0, f64::NAN] {
        let e = item.set_contact_radius(r).unwrap_err();
        assert!(matches!(e, FeaError::InvalidParameter { .. }), "{e}");
        assert!(e.to_string().contains("contact.radius"), "{e}");
    }
    let bad = ContactMaterial::with_friction(-0.1);
    let e = item.set_contact_material(bad).unwrap_err();
    assert!(e.to_string().contains("friction"), "{e}");
}

/// One 1 m element dropped across a narrow fixed ridge (a box 10 cm wide under its middle):
/// the node spheres miss the ridge and the element falls through it, while with midpoint
/// spheres it comes to rest with `r(1/2)` one radius above the ridge's top.
#[test]
fn midpoint_spheres_hold_a_coarse_element_on_a_ridge() {
    let top = 0.0;
    let rest_height = |midpoints: bool| {
        let mut sys = system();
        sys.add_body(
            RigidBodyBuilder::fixed()
                .position(Vector3::new(0.5, 0.0, top - 0.05))
                .collider(
                    Shape::Box {
                        half_extents: Vector3::new(0.05, 0.5, 0.05),
                    },
                    Isometry3::identity(),
                    ContactMaterial::with_friction(0.5),
                ),
        )
        .unwrap();
        let mat = BeamMaterial::rectangle(1e8, 1000.0, 0.02, 0.02, 1e-3).unwrap();
        let z0 = top + 0.03;
        let mesh = CableMesh::straight(
            Vector3::new(0.0, 0.0, z0),
            Vector3::new(1.0, 0.0, z0),
            1,
            mat,
            CableQuadrature::default(),
        )
        .unwrap();
        let mut item = CableItem::new("coarse", mesh).unwrap();
        item.set_midpoint_contacts(midpoints);
        let idx = sys.add_item(Box::new(item));
        for _ in 0..300 {
            sys.step(1e-3).unwrap();
        }
        let mesh = sys.item::<CableItem>(idx).unwrap().mesh();
        let el = &mesh.elements()[0];
        el.position_at(&mesh.element_coordinates(el, &mesh.coordinates()), 0.5)
            .z
    };
    let r = 0.01;
    let (with, without) = (rest_height(true), rest_height(false));
    eprintln!("ridge: midpoint at z = {with:.6e} m with midpoint spheres, {without:.4} m without");
    assert!((with - (top + r)).abs() < 0.01 * r, "midpoint at {with} m");
    assert!(
        without < top,
        "without midpoint spheres the element stays at {without} m"
    );
}
