//! Tests of the BCE markers on ANCF cables: consistent virtual work, rigid motions,
//! momentum of fluid plus cable in a periodic box, bad input.

use chrono_core::item::{ItemHandle, PhysicsItem};
use chrono_core::math::{Unit, UnitQuaternion, Vector3};
use chrono_core::{System, SystemSettings};
use chrono_fea::{BeamMaterial, CableItem, CableMesh, CableQuadrature, NodeId};
use chrono_sph::SphSettings;

use crate::cable::CableMarkers;
use crate::{FsiBuilder, FsiError, SphFluid};

/// A small deterministic generator (xorshift) of numbers in `[-1, 1)`.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    fn vec(&mut self) -> Vector3<f64> {
        Vector3::new(self.next(), self.next(), self.next())
    }
}

/// A round beam of diameter `d` (m) along `dir` from `start`, `n` elements of `length`
/// (m) in total, soft (E = 1e5 Pa) and light (500 kg/m^3).
fn round_beam(start: Vector3<f64>, dir: Vector3<f64>, length: f64, n: usize, d: f64) -> CableMesh {
    let a = 0.25 * std::f64::consts::PI * d * d;
    let i = a * d * d / 16.0;
    let mat = BeamMaterial::new(1e5, 500.0, a, i, 0.0).unwrap();
    CableMesh::straight(
        start,
        start + dir * length,
        n,
        mat,
        CableQuadrature::default(),
    )
    .unwrap()
}

/// Markers, positions and velocities of `mesh` with nodal velocities `vel`.
fn place(
    m: &mut CableMarkers,
    mesh: &CableMesh,
    vel: &[(Vector3<f64>, Vector3<f64>)],
) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let mut x = vec![[0.0; 3]; m.len()];
    let mut v = vec![[0.0; 3]; m.len()];
    m.place("beam", mesh, |n: NodeId| vel[n.0], &mut x, &mut v)
        .unwrap();
    (x, v)
}

fn v3(p: [f64; 3]) -> Vector3<f64> {
    Vector3::new(p[0], p[1], p[2])
}

/// A deformed beam: every coordinate perturbed by up to `amp` (positions m, slopes -).
fn deformed(rng: &mut Rng, amp: f64) -> CableMesh {
    let mut mesh = round_beam(
        Vector3::new(0.1, 0.2, 0.0),
        Vector3::new(0.0, 0.6, 0.8),
        0.5,
        4,
        0.1,
    );
    let q: Vec<f64> = mesh
        .coordinates()
        .iter()
        .map(|x| x + amp * rng.next())
        .collect();
    mesh.set_coordinates(&q).unwrap();
    mesh
}

/// (a) The marker forces and the nodal loads they are mapped to do the same virtual
/// work for every virtual nodal velocity: `sum_m F_m . v_m = Q . e_dot` (round-off); and
/// the marker velocity is the rate of the marker position but for the twist the cable
/// cannot represent (finite differences, along the offset and the tangent).
#[test]
fn marker_forces_and_nodal_loads_do_the_same_virtual_work() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mesh = deformed(&mut rng, 0.02);
    let mut m = CableMarkers::new("beam", &mesh, 0.02, 0.06).unwrap();
    assert!(m.len() > 100, "{} markers", m.len());
    let nn = mesh.nodes().len();
    for trial in 0..5 {
        let vel: Vec<_> = (0..nn).map(|_| (rng.vec(), rng.vec())).collect();
        let (_, v) = place(&mut m, &mesh, &vel);
        let f: Vec<[f64; 3]> = (0..m.len()).map(|_| rng.vec().into()).collect();
        let mut q = vec![0.0; mesh.ndof()];
        m.nodal_loads(&mesh, &f, &mut q);
        let w_markers: f64 = f.iter().zip(&v).map(|(a, b)| v3(*a).dot(&v3(*b))).sum();
        let w_nodes: f64 = (0..nn)
            .map(|n| {
                v3([q[6 * n], q[6 * n + 1], q[6 * n + 2]]).dot(&vel[n].0)
                    + v3([q[6 * n + 3], q[6 * n + 4], q[6 * n + 5]]).dot(&vel[n].1)
            })
            .sum();
        let scale: f64 = f
            .iter()
            .zip(&v)
            .map(|(a, b)| v3(*a).norm() * v3(*b).norm())
            .sum();
        let err = (w_markers - w_nodes).abs() / scale;
        eprintln!("trial {trial}: virtual work {w_markers:.6e} vs {w_nodes:.6e}, rel. {err:e}");
        assert!(
            err < 1e-13,
            "virtual work of markers {w_markers} and nodes {w_nodes}: {err:e}"
        );
    }
    // finite differences of the placement along the nodal velocity
    let vel: Vec<_> = (0..nn).map(|_| (rng.vec(), 0.3 * rng.vec())).collect();
    let (x0, v) = place(&mut m, &mesh, &vel);
    let d = m.clone();
    let eps = 1e-6;
    let shifted = |s: f64| {
        let mut mm = mesh.clone();
        let q: Vec<f64> = (0..nn)
            .flat_map(|n| {
                let node = &mesh.nodes()[n];
                let (r, g) = (node.position + s * vel[n].0, node.slope + s * vel[n].1);
                [r.x, r.y, r.z, g.x, g.y, g.z]
            })
            .collect();
        mm.set_coordinates(&q).unwrap();
        let mut mk = d.clone();
        place(&mut mk, &mm, &vel).0
    };
    let (xp, xm) = (shifted(eps), shifted(-eps));
    let mut worst: f64 = 0.0;
    let mut twist: f64 = 0.0;
    for i in 0..m.len() {
        let fd = (v3(xp[i]) - v3(xm[i])) / (2.0 * eps);
        let diff = fd - v3(v[i]);
        // the offset and tangent directions at the marker, from the placement
        let (off, tan) = m.frame(i);
        let along = diff.dot(&off).abs().max(diff.dot(&tan).abs());
        worst = worst.max(along / (1.0 + v3(v[i]).norm()));
        twist = twist.max(diff.norm() / (1.0 + v3(v[i]).norm()));
        let _ = x0[i];
    }
    // the rest is along t x d: the twist rate of the smallest-rotation frame, which the
    // cable's coordinates do not carry
    eprintln!("finite differences: along offset/tangent {worst:e}, twist part {twist:e}");
    assert!(
        worst < 1e-7,
        "marker velocity differs from the rate of its position: {worst:e}"
    );
}

/// (c) A rigid motion of the cable moves its markers rigidly: a rotation about an axis
/// normal to the straight beam and a translation map every marker as they map the nodes
/// (positions to 1e-12 m), and a rigid velocity field `v_c + w x r` of the nodes gives
/// the markers `v_c + w x x_m`. A rotation with a component along the beam (the twist the
/// cable cannot see) still keeps every distance between markers.
#[test]
fn a_rigid_motion_moves_the_markers_rigidly() {
    let dir = Vector3::new(1.0, 0.0, 0.0);
    let mesh = round_beam(Vector3::zeros(), dir, 0.4, 3, 0.1);
    let mut m = CableMarkers::new("beam", &mesh, 0.02, 0.06).unwrap();
    let nn = mesh.nodes().len();
    let rest = vec![(Vector3::zeros(), Vector3::zeros()); nn];
    let (x0, _) = place(&mut m, &mesh, &rest);
    let c = Vector3::new(0.3, -0.2, 0.5);
    for (axis, normal) in [
        (Vector3::new(0.0, 0.6, 0.8), true),
        (Vector3::new(0.5, 0.5, 0.7), false),
    ] {
        let rot = UnitQuaternion::from_axis_angle(&Unit::new_normalize(axis), 0.9);
        let mut moved = mesh.clone();
        let q: Vec<f64> = (0..nn)
            .flat_map(|n| {
                let node = &mesh.nodes()[n];
                let (r, g) = (rot * node.position + c, rot * node.slope);
                [r.x, r.y, r.z, g.x, g.y, g.z]
            })
            .collect();
        moved.set_coordinates(&q).unwrap();
        let (x1, _) = place(&mut m, &moved, &rest);
        if normal {
            let err = (0..m.len())
                .map(|i| (v3(x1[i]) - (rot * v3(x0[i]) + c)).norm())
                .fold(0.0, f64::max);
            assert!(err < 1e-12, "markers off the rigid image by {err:e} m");
        }
        let mut err: f64 = 0.0;
        for i in (0..m.len()).step_by(7) {
            for j in (0..m.len()).step_by(11) {
                let d0 = (v3(x0[i]) - v3(x0[j])).norm();
                let d1 = (v3(x1[i]) - v3(x1[j])).norm();
                err = err.max((d1 - d0).abs());
            }
        }
        assert!(err < 1e-12, "distance between markers changed by {err:e} m");
    }
    // a rigid velocity field, rotation normal to the beam
    let (vc, w) = (Vector3::new(0.1, -0.4, 0.2), Vector3::new(0.0, 1.5, -2.0));
    let vel: Vec<_> = (0..nn)
        .map(|n| {
            let node = &mesh.nodes()[n];
            (vc + w.cross(&node.position), w.cross(&node.slope))
        })
        .collect();
    let (x, v) = place(&mut m, &mesh, &vel);
    let err = (0..m.len())
        .map(|i| (v3(v[i]) - (vc + w.cross(&v3(x[i])))).norm())
        .fold(0.0, f64::max);
    assert!(
        err < 1e-12,
        "marker velocities off the rigid field by {err:e} m/s"
    );
}

/// Bad input: a section thinner than the kernel support or not resolved by the spacing
/// is an error naming the cable, the element and the value.
#[test]
fn a_thin_or_unresolved_cable_is_an_error_naming_the_element() {
    // the last element thinner: d = 0.05 m < support 0.06 m
    let mut mesh = round_beam(Vector3::zeros(), Vector3::x(), 0.4, 2, 0.1);
    let thin = {
        let d: f64 = 0.05;
        let a = 0.25 * std::f64::consts::PI * d * d;
        BeamMaterial::new(1e5, 500.0, a, a * d * d / 16.0, 0.0).unwrap()
    };
    let n = mesh
        .add_node(Vector3::new(0.6, 0.0, 0.0), Vector3::x())
        .unwrap();
    mesh.add_cable(NodeId(2), n, thin, CableQuadrature::default())
        .unwrap();
    let e = CableMarkers::new("flag", &mesh, 0.02, 0.06).unwrap_err();
    let msg = e.to_string();
    assert!(
        matches!(e, FsiError::BodyThinnerThanSupport { .. })
            && msg.contains("element 2")
            && msg.contains("flag")
            && msg.contains("0.05"),
        "{msg}"
    );
    // d = 0.07 m: thicker than the support, but 3.5 spacings across
    let mesh = round_beam(Vector3::zeros(), Vector3::x(), 0.4, 2, 0.07);
    let e = CableMarkers::new("flag", &mesh, 0.02, 0.06).unwrap_err();
    let msg = e.to_string();
    assert!(
        matches!(e, FsiError::Unresolved { .. })
            && msg.contains("element 0")
            && msg.contains("0.07"),
        "{msg}"
    );
}

fn cable_momentum(item: &CableItem) -> Vector3<f64> {
    // P = sum_e rho A l [r_A/2 + l r_x,A/12 + r_B/2 - l r_x,B/12]_dot (exact integral of
    // the Hermite shape functions)
    let mesh = item.mesh();
    let mut p = Vector3::zeros();
    for el in mesh.elements() {
        let l = el.length();
        let (a, b) = (
            item.node_velocity(NodeId(el.nodes[0])).unwrap(),
            item.node_velocity(NodeId(el.nodes[1])).unwrap(),
        );
        p += el.material().mass_per_length()
            * l
            * (0.5 * a.0 + l / 12.0 * a.1 + 0.5 * b.0 - l / 12.0 * b.1);
    }
    p
}

fn momentum(sys: &System, item: ItemHandle) -> Vector3<f64> {
    let f = sys.item::<SphFluid>(item).unwrap();
    f.sph().fluid_momentum() + cable_momentum(f.cable(0).unwrap())
}

/// (b) A free cable moving through fluid at rest in a triply periodic box without
/// gravity: fluid plus cable linear momentum is constant to round-off over more than
/// 500 fluid sub-steps, while the cable gives a good part of its momentum to the fluid.
#[test]
fn momentum_of_fluid_and_cable_is_conserved_in_a_periodic_box() {
    let (dp, l) = (0.02, 0.32);
    let settings = SphSettings {
        spacing: dp,
        sound_speed: 10.0,
        viscosity: 1e-2,
        domain_lower: [0.0; 3],
        domain_upper: [l; 3],
        periodic: [true; 3],
        gravity: [0.0; 3],
        ..SphSettings::default()
    };
    let s = SystemSettings {
        gravity: Vector3::zeros(),
        ..SystemSettings::default()
    };
    let mut sys = System::new(s, Box::new(chrono_ccp::Psor::new(Default::default()))).unwrap();
    let mesh = round_beam(
        Vector3::new(0.06, 0.16, 0.1),
        Vector3::new(1.0, 0.0, 0.5).normalize(),
        0.22,
        3,
        0.09,
    );
    let mut cable = CableItem::new("fibre", mesh).unwrap();
    cable.set_contact_enabled(false);
    let v0 = Vector3::new(0.2, 0.3, -0.1);
    for n in 0..4 {
        // translating and bending
        let bend = Vector3::new(0.0, 0.0, if n % 2 == 0 { 0.4 } else { -0.4 });
        cable
            .set_node_velocity(NodeId(n), v0 + bend * 0.1, bend)
            .unwrap();
    }
    let mut fsi = FsiBuilder::new(settings).unwrap();
    fsi.add_fluid_box([0.0; 3], [l; 3], None).unwrap();
    fsi.add_cable(cable).unwrap();
    let fluid = fsi.build("water", 1).unwrap();
    let markers = fluid.cable_markers(0).unwrap().len();
    let item = sys.add_item(Box::new(fluid));
    let p0 = momentum(&sys, item);
    let c0 = cable_momentum(sys.item::<SphFluid>(item).unwrap().cable(0).unwrap());
    let scale = c0.norm();
    let mut max_err: f64 = 0.0;
    while sys.item::<SphFluid>(item).unwrap().substeps() < 500 {
        sys.step(2e-3).unwrap();
        max_err = max_err.max((momentum(&sys, item) - p0).norm() / scale);
        if std::env::var("FSI_DEBUG").is_ok() {
            let f = sys.item::<SphFluid>(item).unwrap();
            eprintln!(
                "t {:.4} fluid {:?} cable {:?} J/h {:?}",
                sys.time(),
                f.sph().fluid_momentum(),
                cable_momentum(f.cable(0).unwrap()),
                f.cable_force(0).unwrap()
            );
        }
    }
    let f = sys.item::<SphFluid>(item).unwrap();
    let c1 = cable_momentum(f.cable(0).unwrap());
    let lost = (c1 - c0).norm() / scale;
    eprintln!(
        "{markers} markers, {} sub-steps: momentum drift {max_err:e}, cable momentum change {lost}",
        f.substeps()
    );
    assert!(
        lost > 0.05,
        "the cable exchanged only {lost} of its momentum"
    );
    assert!(max_err < 1e-12, "momentum drift {max_err:e} (relative)");
    assert_eq!(f.cable(0).unwrap().name(), "fibre");
}
