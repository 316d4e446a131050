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
