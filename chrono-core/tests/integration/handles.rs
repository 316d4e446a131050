//! Generational body and item handles: removal, stale handles, and the caches that must
//! follow a removal (collision world, warm start, SMC history).

use chrono_ccp::{Psor, SolverSettings};
use chrono_core::descriptor::{CcpProblem, Variables};
use chrono_core::item::{PhysicsItem, StepContext};
use chrono_core::math::{GRAVITY, Isometry3, Vector3};
use chrono_core::system::{ContactMethod, SmcSettings};
use chrono_core::{
    BodyHandle, ChronoError, ContactMaterial, JointBuilder, JointKind, RigidBodyBuilder, Shape,
    System, SystemSettings,
};
use proptest::prelude::*;

fn system(method: ContactMethod) -> System {
    let settings = SystemSettings {
        contact_method: method,
        smc: SmcSettings::default(),
        ..SystemSettings::default()
    };
    System::new(settings, Box::new(Psor::new(SolverSettings::default()))).unwrap()
}

fn mat() -> ContactMaterial {
    ContactMaterial::with_friction(0.4)
}

fn ground(sys: &mut System) -> BodyHandle {
    sys.add_body(RigidBodyBuilder::fixed().name("ground").collider(
        Shape::HalfSpace {
            normal: Vector3::z(),
        },
        Isometry3::identity(),
        mat(),
    ))
    .unwrap()
}

fn ball(sys: &mut System, name: &str, p: Vector3<f64>) -> BodyHandle {
    let s = Shape::Sphere { radius: 0.05 };
    sys.add_body(
        RigidBodyBuilder::dynamic()
            .name(name)
            .mass_from_shape(&s, 2500.0)
            .unwrap()
            .position(p)
            .collider(s, Isometry3::identity(), mat()),
    )
    .unwrap()
}

/// Position of ball `i` of the test scenes: a loose pile, touching neighbours.
fn spot(i: usize) -> Vector3<f64> {
    let (x, y, z) = (i % 3, (i / 3) % 3, i / 9);
    Vector3::new(0.099 * x as f64, 0.099 * y as f64, 0.05 + 0.099 * z as f64)
}

/// Every collider is owned by the dense index of its body and the colliders are sorted by
/// owner (as in a freshly built world).
fn check_collision_owners(sys: &System) {
    let owners: Vec<u32> = sys
        .collision()
        .colliders()
        .iter()
        .map(|c| c.owner())
        .collect();
    assert!(owners.windows(2).all(|w| w[0] <= w[1]), "{owners:?}");
    for (i, b) in sys.bodies().iter().enumerate() {
        let n = owners.iter().filter(|&&o| o as usize == i).count();
        assert_eq!(n, b.colliders().len(), "body {i}");
    }
    assert_eq!(
        owners.len(),
        sys.bodies()
            .iter()
            .map(|b| b.colliders().len())
            .sum::<usize>()
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    /// Random adds and removals: live handles keep naming their body, stale ones are errors.
    #[test]
    fn random_add_remove_keeps_handles_right(ops in prop::collection::vec((any::<bool>(), any::<u16>()), 1..80)) {
        let mut sys = system(ContactMethod::Nsc);
        let mut live: Vec<(BodyHandle, String, Vector3<f64>)> = Vec::new();
        let mut stale: Vec<BodyHandle> = Vec::new();
        for (k, (add, pick)) in ops.into_iter().enumerate() {
            if add || live.is_empty() {
                let name = format!("b{k}");
                let p = Vector3::new(k as f64, 0.0, 1.0);
                live.push((ball(&mut sys, &name, p), name, p));
            } else {
                let (h, name, _) = live.swap_remove(pick as usize % live.len());
                let body = sys.remove_body(h).unwrap();
                prop_assert_eq!(body.name(), name.as_str());
                stale.push(h);
            }
            prop_assert_eq!(sys.bodies().len(), live.len());
            for (h, name, p) in &live {
                let b = sys.body(*h).unwrap();
                prop_assert_eq!(b.name(), name.as_str());
                prop_assert_eq!(b.position(), *p);
            }
            for h in &stale {
                prop_assert_eq!(sys.body(*h).unwrap_err(), ChronoError::StaleBody { handle: *h });
                prop_assert!(sys.remove_body(*h).is_err());
            }
            let handles: Vec<BodyHandle> = sys.body_handles().collect();
            for (i, h) in handles.iter().enumerate() {
                prop_assert_eq!(sys.body_set().dense_index(*h), Some(i));
            }
            check_collision_owners(&sys);
        }
    }
}

/// Build a pile of `n` balls on the ground, named by their spot.
fn pile(method: ContactMethod, spots: &[usize]) -> (System, Vec<BodyHandle>) {
    let mut sys = system(method);
    ground(&mut sys);
    let hs = spots
        .iter()
        .map(|&i| ball(&mut sys, &format!("s{i}"), spot(i)))
        .collect();
    (sys, hs)
}

fn state_bits(sys: &System) -> Vec<u64> {
    sys.bodies()
        .iter()
        .flat_map(|b| {
            let (p, v) = (b.position(), b.linear_velocity());
            [p.x, p.y, p.z, v.x, v.y, v.z]
        })
        .map(f64::to_bits)
        .collect()
}

/// After removals, the system steps exactly like one built without the removed bodies in
/// the same dense order.
#[test]
fn removal_steps_like_a_system_built_without() {
    for method in [ContactMethod::Nsc, ContactMethod::Smc] {
        let h = if method == ContactMethod::Smc {
            2e-5
        } else {
            1e-3
        };
        let all: Vec<usize> = (0..14).collect();
        let (mut a, hs) = pile(method, &all);
        for i in [3, 13, 0, 7] {
            a.remove_body(hs[i]).unwrap();
        }
        // The dense order left by the swap-removes, by name.
        let order: Vec<usize> = (a.bodies()[1..].iter())
            .map(|b| b.name()[1..].parse().unwrap())
            .collect();
        let (mut b, _) = pile(method, &order);
        for _ in 0..40 {
            a.step(h).unwrap();
            b.step(h).unwrap();
        }
        assert!(!a.contacts().is_empty() || method == ContactMethod::Smc);
        assert_eq!(state_bits(&a), state_bits(&b), "{method:?}");
    }
}

/// Grains are taken from the bottom of a pile and put back on top while stepping: no
/// panic, contacts name existing bodies, energy stays bounded.
#[test]
fn remove_and_reinsert_while_stepping() {
    for method in [ContactMethod::Nsc, ContactMethod::Smc] {
        let h = if method == ContactMethod::Smc {
            2e-5
        } else {
            1e-3
        };
        let steps_between = if method == ContactMethod::Smc { 100 } else { 5 };
        let all: Vec<usize> = (0..18).collect();
        let (mut sys, mut hs) = pile(method, &all);
        let mass = sys.body(hs[0]).unwrap().mass();
        for round in 0..12 {
            for _ in 0..steps_between {
                sys.step(h).unwrap();
            }
            // The lowest grain leaves and comes back above the pile.
            let (k, _) = (hs.iter().enumerate())
                .map(|(k, h)| (k, sys.body(*h).unwrap().position().z))
                .fold(
                    (0, f64::INFINITY),
                    |m, (k, z)| if z < m.1 { (k, z) } else { m },
                );
            let old = hs.swap_remove(k);
            let body = sys.remove_body(old).unwrap();
            assert!(sys.body(old).is_err());
            let p = Vector3::new(body.position().x, body.position().y, 0.5);
            hs.push(ball(&mut sys, &format!("r{round}"), p));
            assert_eq!(sys.bodies().len(), 19);
            let n = sys.bodies().len() as u32;
            for c in sys.contacts() {
                assert!(c.point.owner_a < n && c.point.owner_b < n);
            }
        }
        sys.step(h).unwrap();
        let n = sys.bodies().len() as u32;
        assert!(
            sys.contacts()
                .iter()
                .all(|c| c.point.owner_a < n && c.point.owner_b < n)
        );
        // Nothing gained energy from a removal: the kinetic energy stays below the potential
        // energy of every grain falling from the re-insertion height.
        let bound = 19.0 * mass * GRAVITY.norm() * 0.5;
        assert!(
            sys.kinetic_energy() < bound,
            "{method:?}: {}",
            sys.kinetic_energy()
        );
        check_collision_owners(&sys);
    }
}

#[test]
fn stale_handles_are_errors_naming_them() {
    let (mut sys, hs) = pile(ContactMethod::Nsc, &[0, 1, 2]);
    let body = sys.remove_body(hs[0]).unwrap();
    assert_eq!(body.name(), "s0");
    let err = sys.remove_body(hs[0]).unwrap_err();
    assert_eq!(err, ChronoError::StaleBody { handle: hs[0] });
    assert!(err.to_string().contains(&hs[0].to_string()), "{err}");
    assert!(sys.body_mut(hs[0]).is_err());
    assert!(sys.set_contact_friction(hs[0], None).is_err());
    // The slot is reused with a new generation: the old handle stays stale.
    let new = ball(&mut sys, "new", spot(5));
    assert_eq!(new.index(), hs[0].index());
    assert_ne!(new, hs[0]);
    assert!(sys.body(hs[0]).is_err());
    assert_eq!(sys.body(new).unwrap().name(), "new");
    // The moved body (last) keeps its handle.
    assert_eq!(sys.body(hs[2]).unwrap().name(), "s2");
}

#[test]
fn a_jointed_body_is_not_removed() {
    let (mut sys, hs) = pile(ContactMethod::Nsc, &[0, 1]);
    sys.add_joint(
        JointBuilder::new(
            JointKind::Spherical,
            hs[0],
            hs[1],
            Isometry3::translation(0.05, 0.0, 0.05),
        )
        .name("link"),
    )
    .unwrap();
    let err = sys.remove_body(hs[1]).unwrap_err();
    match &err {
        ChronoError::BodyInUse { handle, users, .. } => {
            assert_eq!(*handle, hs[1]);
            assert!(users[0].contains("link"), "{users:?}");
        }
        e => panic!("{e}"),
    }
    assert_eq!(sys.bodies().len(), 3);
    sys.step(1e-3).unwrap();
}

/// A removed body's contact friction override goes with it; the moved body keeps its own.
#[test]
fn contact_friction_follows_the_moved_body() {
    let (mut sys, hs) = pile(ContactMethod::Nsc, &[0, 1, 2]);
    let f = chrono_core::ContactFriction {
        friction: 0.9,
        rolling_friction: 0.0,
        spinning_friction: 0.0,
    };
    sys.set_contact_friction(hs[2], Some(f)).unwrap();
    sys.remove_body(hs[0]).unwrap();
    assert_eq!(sys.contact_friction(hs[2]), Some(f));
    assert_eq!(sys.contact_friction(hs[1]), None);
}

struct Dummy;

impl PhysicsItem for Dummy {
    fn name(&self) -> &str {
        "dummy"
    }
    fn add_variables(&mut self, _vars: &mut Variables) {}
    fn load_momentum(&self, _ctx: &StepContext, _vars: &Variables, _k: &mut [f64]) {}
    fn update(
        &mut self,
        _ctx: &StepContext,
        _vars: &Variables,
        _v: &[f64],
        _problem: &CcpProblem,
        _gamma: &[f64],
    ) -> chrono_core::Result<()> {
        Ok(())
    }
}

#[test]
fn items_are_removed_by_handle() {
    let mut sys = system(ContactMethod::Nsc);
    let a = sys.add_item(Box::new(Dummy));
    let b = sys.add_item(Box::new(Dummy));
    assert!(sys.item::<Dummy>(a).is_some());
    sys.remove_item(a).unwrap();
    assert!(sys.item::<Dummy>(a).is_none());
    assert_eq!(
        sys.remove_item(a).err(),
        Some(ChronoError::StaleItem { handle: a })
    );
    assert!(sys.item_mut::<Dummy>(b).is_some());
    assert_eq!(sys.items().len(), 1);
    assert_eq!(sys.item_handles().collect::<Vec<_>>(), vec![b]);
    sys.step(1e-3).unwrap();
}

fn cube(sys: &mut System, name: &str, p: Vector3<f64>, halves: &[f64]) -> BodyHandle {
    // One box collider per entry of `halves`, side by side along x (a compound for 2+).
    let mut b = RigidBodyBuilder::dynamic()
        .name(name)
        .mass(1.0)
        .inertia_diagonal(Vector3::repeat(1e-3))
        .position(p);
    for (i, &h) in halves.iter().enumerate() {
        let shape = Shape::Box {
            half_extents: Vector3::repeat(h),
        };
        b = b.collider(
            shape,
            Isometry3::translation(0.2 * i as f64, 0.0, 0.0),
            mat(),
        );
    }
    sys.add_body(b).unwrap()
}

/// A stack of boxes and a pile of balls on the ground (parry manifolds and analytic
/// contacts), in the same order in every system that calls it.
fn stack(sys: &mut System) {
    ground(sys);
    for i in 0..3 {
        cube(
            sys,
            &format!("box{i}"),
            Vector3::new(0.5, 0.0, 0.05 + 0.1 * i as f64),
            &[0.05],
        );
    }
    for i in 0..8 {
        ball(sys, &format!("s{i}"), spot(i));
    }
}

/// A body that touches nothing is removed between steps: the other bodies step
/// bit-identically to a system built without it, warm start, SMC history and narrow-phase
/// state included. Three layouts: the removed body is the last one (nothing moves); or the
/// last body (a ball of the pile) takes its place, with as many colliders (the collider
/// blocks swap) or fewer (the colliders between them shift).
#[test]
fn removing_an_untouched_body_keeps_the_others_bit_identical() {
    for method in [ContactMethod::Nsc, ContactMethod::Smc] {
        let (h, before, after) = if method == ContactMethod::Smc {
            (2e-5, 300, 300)
        } else {
            (1e-3, 30, 30)
        };
        for (layout, far_halves) in [
            ("last", &[0.05][..]),
            ("swap", &[0.05]),
            ("shift", &[0.05, 0.05]),
        ] {
            let mut a = system(method);
            stack(&mut a);
            // Far above the scene: falls freely, touches nothing.
            let far = cube(&mut a, "far", Vector3::new(-5.0, 0.0, 50.0), far_halves);
            if layout != "last" {
                ball(&mut a, "s8", spot(8));
            }
            let mut b = system(method);
            stack(&mut b);
            if layout != "last" {
                ball(&mut b, "s8", spot(8));
            }
            for _ in 0..before {
                a.step(h).unwrap();
                b.step(h).unwrap();
            }
            assert_eq!(state_bits(&a)[..6 * 12], state_bits(&b)[..6 * 12]);
            a.remove_body(far).unwrap();
            check_collision_owners(&a);
            for _ in 0..after {
                a.step(h).unwrap();
                b.step(h).unwrap();
            }
            assert!(!b.contacts().is_empty() || method == ContactMethod::Smc);
            assert_eq!(
                a.contacts().len(),
                b.contacts().len(),
                "{method:?} {layout}"
            );
            assert_eq!(
                state_bits(&a),
                state_bits(&b),
                "{method:?} {layout}: the removal changed the others' steps"
            );
        }
    }
}

/// Removing a body in the middle reorders the others (the last takes its place), so the
/// steps are no longer bit-identical to a system built without it; the contacts are
/// those of that system, and the motion agrees to the solver's tolerance.
#[test]
fn removing_from_the_middle_keeps_the_contacts() {
    let mut a = system(ContactMethod::Nsc);
    stack(&mut a);
    let far = cube(&mut a, "far", Vector3::new(-5.0, 0.0, 50.0), &[0.05]);
    for i in 8..11 {
        ball(&mut a, &format!("s{i}"), spot(i));
    }
    let mut b = system(ContactMethod::Nsc);
    stack(&mut b);
    for i in 8..11 {
        ball(&mut b, &format!("s{i}"), spot(i));
    }
    for _ in 0..30 {
        a.step(1e-3).unwrap();
        b.step(1e-3).unwrap();
    }
    a.remove_body(far).unwrap();
    check_collision_owners(&a);
    a.step(1e-3).unwrap();
    b.step(1e-3).unwrap();
    let names = |s: &System| {
        let mut v: Vec<(String, String)> = (s.contacts().iter())
            .map(|c| {
                let n = |o: u32| s.bodies()[o as usize].name().to_string();
                (n(c.point.owner_a), n(c.point.owner_b))
            })
            .map(|(x, y)| if x < y { (x, y) } else { (y, x) })
            .collect();
        v.sort();
        v
    };
    assert_eq!(names(&a), names(&b));
    for _ in 0..20 {
        a.step(1e-3).unwrap();
        b.step(1e-3).unwrap();
    }
    for bb in b.bodies() {
        let ba = a.bodies().iter().find(|x| x.name() == bb.name()).unwrap();
        assert!(
            (ba.position() - bb.position()).norm() < 1e-4,
            "{}: {} vs {}",
            bb.name(),
            ba.position(),
            bb.position()
        );
    }
}

/// A batch removal with a bad handle (stale, twice, or jointed) changes nothing: the system
/// steps on bit-identically to an untouched copy.
#[test]
fn a_failed_batch_removal_leaves_the_system_unchanged() {
    let all: Vec<usize> = (0..10).collect();
    let (mut a, hs) = pile(ContactMethod::Nsc, &all);
    let (mut b, _) = pile(ContactMethod::Nsc, &all);
    let gone = ball(&mut a, "gone", Vector3::new(3.0, 0.0, 1.0));
    ball(&mut b, "gone", Vector3::new(3.0, 0.0, 1.0));
    for _ in 0..10 {
        a.step(1e-3).unwrap();
        b.step(1e-3).unwrap();
    }
    a.remove_body(gone).unwrap();
    b.remove_body(b.body_handles().last().unwrap()).unwrap();
    a.add_joint(JointBuilder::new(
        JointKind::Spherical,
        hs[8],
        hs[9],
        Isometry3::translation(0.05, 0.2, 0.15),
    ))
    .unwrap();
    let (b8, b9) = (
        b.body_handles().nth(9).unwrap(),
        b.body_handles().nth(10).unwrap(),
    );
    b.add_joint(JointBuilder::new(
        JointKind::Spherical,
        b8,
        b9,
        Isometry3::translation(0.05, 0.2, 0.15),
    ))
    .unwrap();
    let n = a.bodies().len();
    let stale = a.remove_bodies(&[hs[0], gone, hs[1]]).unwrap_err();
    assert_eq!(stale, ChronoError::StaleBody { handle: gone });
    let twice = a.remove_bodies(&[hs[2], hs[3], hs[2]]).unwrap_err();
    assert!(twice.to_string().contains("handles[2]"), "{twice}");
    let jointed = a.remove_bodies(&[hs[4], hs[9]]).unwrap_err();
    assert!(
        matches!(&jointed, ChronoError::BodyInUse { handle, .. } if *handle == hs[9]),
        "{jointed}"
    );
    assert_eq!(a.bodies().len(), n);
    assert!(hs.iter().all(|h| a.body(*h).is_ok()));
    check_collision_owners(&a);
    for _ in 0..10 {
        a.step(1e-3).unwrap();
        b.step(1e-3).unwrap();
    }
    assert_eq!(state_bits(&a), state_bits(&b));
    // A good batch removes them all; the handles are stale.
    let removed = a.remove_bodies(&[hs[0], hs[5], hs[3]]).unwrap();
    let names: Vec<&str> = removed.iter().map(|b| b.name()).collect();
    assert_eq!(names, ["s0", "s5", "s3"]);
    assert_eq!(a.bodies().len(), n - 3);
    for h in [hs[0], hs[5], hs[3]] {
        assert_eq!(a.body(h).unwrap_err(), ChronoError::StaleBody { handle: h });
    }
    check_collision_owners(&a);
    a.step(1e-3).unwrap();
}

/// Joints and force elements are removed by handle; stale handles are errors naming them;
/// removing the last joint between two bodies lets them touch again.
#[test]
fn joint_and_force_removal() {
    use chrono_core::{Curve, SpringDamper};
    let (mut sys, hs) = pile(ContactMethod::Nsc, &[0, 1, 2]);
    let (g, a, b) = (sys.body_handles().next().unwrap(), hs[0], hs[1]);
    // Balls 0 and 1 overlap by 1 mm: a contact, unless jointed.
    let ij = sys.body_set().dense_index(a).unwrap() as u32;
    let jb = sys.body_set().dense_index(b).unwrap() as u32;
    let joined = |sys: &System| {
        sys.contacts().iter().any(|c| {
            let (x, y) = (c.point.owner_a, c.point.owner_b);
            (x.min(y), x.max(y)) == (ij.min(jb), ij.max(jb))
        })
    };
    sys.step(1e-3).unwrap();
    assert!(joined(&sys));
    let at = Isometry3::translation(0.0495, 0.0, 0.05);
    let j1 = sys
        .add_joint(JointBuilder::new(JointKind::Spherical, a, b, at).name("j1"))
        .unwrap();
    let j2 = sys
        .add_joint(JointBuilder::new(JointKind::Spherical, b, a, at).name("j2"))
        .unwrap();
    let j3 = sys
        .add_joint(JointBuilder::new(JointKind::Spherical, g, hs[2], at).name("j3"))
        .unwrap();
    let spring = sys
        .add_force_element(Box::new(SpringDamper::new(
            "spring",
            a,
            spot(0),
            hs[2],
            spot(2),
            0.1,
            Curve::linear(10.0),
            Curve::linear(0.0),
        )))
        .unwrap();
    sys.step(1e-3).unwrap();
    assert!(!joined(&sys));
    assert!(sys.collision().is_pair_excluded(ij, jb));

    // The last joint (j3) takes j1's place and keeps its handle.
    assert_eq!(sys.remove_joint(j1).unwrap().name(), "j1");
    assert_eq!(sys.joint(j3).unwrap().name(), "j3");
    assert_eq!(
        sys.joint(j1).unwrap_err(),
        ChronoError::StaleJoint { handle: j1 }
    );
    assert!(sys.joint_mut(j1).is_err());
    let err = sys.remove_joint(j1).unwrap_err();
    assert!(err.to_string().contains(&j1.to_string()), "{err}");
    // j2 still joins the two balls.
    assert!(sys.collision().is_pair_excluded(ij, jb));
    sys.step(1e-3).unwrap();
    assert!(!joined(&sys));
    // A jointed body is not removed; once its joints are gone it is.
    assert!(matches!(
        sys.remove_body(b),
        Err(ChronoError::BodyInUse { .. })
    ));
    sys.remove_joint(j2).unwrap();
    assert!(!sys.collision().is_pair_excluded(ij, jb));
    sys.step(1e-3).unwrap();
    assert!(joined(&sys), "contact between the unjointed balls");
    assert_eq!(sys.joint_handles().collect::<Vec<_>>(), vec![j3]);
    // A new joint reuses a slot with a new generation.
    let j4 = sys
        .add_joint(JointBuilder::new(JointKind::Spherical, a, b, at))
        .unwrap();
    assert!(j4 != j1 && j4 != j2);
    assert!(sys.joint(j1).is_err() && sys.joint(j2).is_err());

    // Force elements.
    let err = sys.remove_body(hs[2]).unwrap_err();
    assert!(format!("{err}").contains("spring"), "{err}");
    assert!(sys.force_element::<SpringDamper>(spring).is_some());
    sys.remove_force_element(spring).unwrap();
    assert!(sys.force_element::<SpringDamper>(spring).is_none());
    assert!(sys.force_element_mut::<SpringDamper>(spring).is_none());
    assert_eq!(
        sys.remove_force_element(spring)
            .err()
            .map(|e| e.to_string()),
        Some(ChronoError::StaleForce { handle: spring }.to_string())
    );
    assert_eq!(sys.force_handles().count(), 0);
    sys.remove_joint(j3).unwrap();
    sys.remove_body(hs[2]).unwrap();
    sys.step(1e-3).unwrap();
}

/// The silo's recycler removes the discharged grains and adds new ones: the grain count
/// stays, the old handles are stale, the new grains are at rest above the pile.
#[test]
fn recycler_removes_and_reinserts() {
    use chrono_core::granular::{GrainBed, Recycler, Silo};
    let mut sys = system(ContactMethod::Nsc);
    let d = 0.004;
    let silo = Silo::new(0.024, 0.012, 2.0 * d, mat());
    silo.add(&mut sys).unwrap();
    let bed = GrainBed::new(
        silo.region(0.25 * d, 0.02),
        0.45 * d,
        0.5 * d,
        2500.0,
        mat(),
    )
    .pour(&mut sys)
    .unwrap();
    let mut recycler = Recycler::new(&sys, &bed, &silo, d, 0.03).unwrap();
    let n = sys.bodies().len();
    for _ in 0..5 {
        sys.step(1e-3).unwrap();
        assert_eq!(recycler.recycle(&mut sys).unwrap(), 0);
    }
    // Two grains "fall out" (moved below the floor).
    let out = [bed.handles[3], bed.handles[7]];
    for h in out {
        sys.body_mut(h)
            .unwrap()
            .set_pose(Vector3::new(0.0, 0.0, -1.0), Default::default())
            .unwrap();
    }
    let mass: f64 = recycler.masses()[3] + recycler.masses()[7];
    assert_eq!(recycler.recycle(&mut sys).unwrap(), 2);
    assert_eq!(recycler.discharged(), mass);
    assert_eq!(sys.bodies().len(), n);
    assert_eq!(recycler.handles().len(), bed.len());
    for h in out {
        assert_eq!(
            sys.body(h).unwrap_err(),
            ChronoError::StaleBody { handle: h }
        );
    }
    for k in [3, 7] {
        let g = sys.body(recycler.handles()[k]).unwrap();
        assert!(g.position().z >= 0.03 && g.linear_velocity() == Vector3::zeros());
        assert_eq!(g.mass(), recycler.masses()[k]);
    }
    assert!(recycler.handles().iter().all(|h| sys.body(*h).is_ok()));
    check_collision_owners(&sys);
    for _ in 0..5 {
        sys.step(1e-3).unwrap();
        recycler.recycle(&mut sys).unwrap();
    }
    assert_eq!(sys.bodies().len(), n);
}

/// The contacts the system's collision world finds after removals (pair states and sphere
/// grid kept and renumbered) are those of a world built afresh from its colliders.
fn check_contacts_fresh(sys: &System, poses: &[Isometry3<f64>]) {
    let mut fresh = chrono_core::collision::CollisionWorld::new(sys.settings().envelope).unwrap();
    for c in sys.collision().colliders() {
        fresh
            .add_collider(c.owner(), c.shape(), *c.local_pose(), c.material())
            .unwrap();
    }
    let active: Vec<bool> = sys.bodies().iter().map(|b| b.is_dynamic()).collect();
    let mut out = Vec::new();
    fresh.detect(poses, &active, &mut out).unwrap();
    let mine: Vec<_> = sys.contacts().iter().map(|c| c.point).collect();
    assert_eq!(mine, out);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]
    /// Random adds and batch removals of bodies with 0, 1 or 2 colliders, stepping in
    /// between: the body count, the handles, the collider owners, and the contacts (those
    /// of a world built afresh) stay right.
    #[test]
    fn random_batches_keep_the_collision_world_consistent(
        ops in prop::collection::vec((0..4u8, any::<u16>(), 1..4usize), 1..40)
    ) {
        let mut sys = system(ContactMethod::Nsc);
        let g = ground(&mut sys);
        let mut live: Vec<(BodyHandle, String)> = Vec::new();
        let mut stale: Vec<BodyHandle> = Vec::new();
        for (k, (op, pick, count)) in ops.into_iter().enumerate() {
            if op < 2 || live.is_empty() {
                let name = format!("b{k}");
                let p = spot(k % 27);
                let s = Shape::Sphere { radius: 0.05 };
                let mut b = RigidBodyBuilder::dynamic().name(&name).mass(1.0)
                    .inertia_diagonal(Vector3::repeat(1e-3)).position(p);
                // 0, 1 or 2 spheres.
                for i in 0..(pick % 3) {
                    b = b.collider(s.clone(), Isometry3::translation(0.0, 0.03 * i as f64, 0.0), mat());
                }
                live.push((sys.add_body(b).unwrap(), name));
            } else {
                let count = count.min(live.len());
                let mut batch = Vec::new();
                for j in 0..count {
                    let at = (pick as usize + 7 * j) % live.len();
                    batch.push(live.swap_remove(at));
                }
                let handles: Vec<BodyHandle> = batch.iter().map(|(h, _)| *h).collect();
                let removed = sys.remove_bodies(&handles).unwrap();
                for ((_, name), body) in batch.iter().zip(&removed) {
                    prop_assert_eq!(body.name(), name.as_str());
                }
                stale.extend(handles);
            }
            prop_assert_eq!(sys.bodies().len(), live.len() + 1);
            prop_assert!(sys.body(g).is_ok());
            for (h, name) in &live {
                prop_assert_eq!(sys.body(*h).unwrap().name(), name.as_str());
            }
            for h in &stale {
                prop_assert_eq!(sys.body(*h).unwrap_err(), ChronoError::StaleBody { handle: *h });
            }
            check_collision_owners(&sys);
            for (i, b) in sys.bodies().iter().enumerate() {
                let mine: Vec<_> = (sys.collision().colliders().iter())
                    .filter(|c| c.owner() as usize == i)
                    .map(|c| (c.shape().clone(), *c.local_pose()))
                    .collect();
                let want: Vec<_> = b.colliders().iter().map(|c| (c.shape.clone(), c.local_pose)).collect();
                prop_assert_eq!(mine, want);
            }
            if op % 2 == 0 {
                let poses: Vec<_> = sys.bodies().iter().map(|b| b.pose()).collect();
                sys.step(1e-3).unwrap();
                check_contacts_fresh(&sys, &poses);
            }
        }
    }
}
