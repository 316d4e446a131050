//! The sphere grid finds the same contacts as the sort-and-sweep path.

use super::*;

/// A deterministic cloud: `n` spheres of radius 0.05..0.08 on a jittered lattice (some
/// touching), two per owner for every fifth owner (clumps), a floor, a box and a
/// capsule among them.
fn scene(n: usize) -> (CollisionWorld, Vec<Isometry3<f64>>) {
    let mut w = CollisionWorld::new(0.01).unwrap();
    let mut poses = vec![Isometry3::identity()];
    w.add_collider(0, &plane(), Isometry3::identity(), mat())
        .unwrap();
    let mut rng = crate::rng::Rng::new(12345);
    let mut rnd = || rng.uniform();
    let side = (n as f64).cbrt().ceil() as usize;
    for k in 0..n {
        let (i, j, l) = (k % side, (k / side) % side, k / (side * side));
        let owner = poses.len() as u32;
        let p = Vector3::new(
            i as f64 * 0.14 + 0.02 * rnd(),
            j as f64 * 0.14 + 0.02 * rnd(),
            0.03 + l as f64 * 0.14 + 0.02 * rnd(),
        );
        poses.push(Isometry3::translation(p.x, p.y, p.z));
        let r = 0.05 + 0.03 * rnd();
        w.add_collider(
            owner,
            &Shape::Sphere { radius: r },
            Isometry3::identity(),
            mat(),
        )
        .unwrap();
        if k % 5 == 0 {
            w.add_collider(
                owner,
                &Shape::Sphere { radius: 0.03 },
                at(0.06, 0.0, 0.0),
                mat(),
            )
            .unwrap();
        }
    }
    let owner = poses.len() as u32;
    poses.push(Isometry3::translation(0.5, 0.5, 0.5));
    w.add_collider(owner, &unit_box(), Isometry3::identity(), mat())
        .unwrap();
    let owner = poses.len() as u32;
    poses.push(Isometry3::translation(0.2, 0.9, 0.3));
    w.add_collider(
        owner,
        &Shape::Capsule {
            half_length: 0.3,
            radius: 0.1,
        },
        Isometry3::identity(),
        mat(),
    )
    .unwrap();
    (w, poses)
}

fn sorted(mut cs: Vec<ContactPoint>) -> Vec<ContactPoint> {
    cs.sort_by_key(|c| c.key);
    cs
}

#[test]
fn grid_and_sweep_find_the_same_contacts() {
    let (mut w, poses) = scene(600);
    w.exclude_pair(1, 2);
    w.set_grid_min_spheres(usize::MAX);
    let sweep = detect(&mut w, &poses);
    assert!(!w.used_grid());
    w.set_grid_min_spheres(0);
    let grid = detect(&mut w, &poses);
    assert!(w.used_grid());
    check_invariants(&grid);
    assert!(grid.len() > 300, "{}", grid.len());
    let (sweep, grid) = (sorted(sweep), sorted(grid));
    assert_eq!(sweep.len(), grid.len());
    for (a, b) in sweep.iter().zip(&grid) {
        assert_eq!(a.key, b.key);
        assert!((a.distance - b.distance).abs() < 1e-12, "{a:?} {b:?}");
        assert!((a.normal - b.normal).norm() < 1e-12);
    }
    // No contact between the excluded owners or within a clump.
    assert!(grid.iter().all(|c| c.owner_a != c.owner_b));
    assert!(
        grid.iter()
            .all(|c| (c.owner_a.min(c.owner_b), c.owner_a.max(c.owner_b)) != (1, 2))
    );
    // Deterministic: a second call gives the same list in the same order.
    let again = detect(&mut w, &poses);
    assert_eq!(sorted(again).len(), grid.len());
}

/// Poses of step `k` of a drift: every owner but the fixed ones moves a little along its
/// own direction (some far enough to force rebuilds of the Verlet list).
fn drifted(poses: &[Isometry3<f64>], k: usize) -> Vec<Isometry3<f64>> {
    let mut rng = crate::rng::Rng::new(777);
    poses
        .iter()
        .map(|p| {
            let v =
                Vector3::new(rng.uniform(), rng.uniform(), rng.uniform()) - Vector3::repeat(0.5);
            let t = p.translation.vector + v * (0.004 * k as f64);
            Isometry3::from_parts(t.into(), p.rotation)
        })
        .collect()
}

#[test]
fn verlet_skin_finds_the_same_contacts_in_the_same_order() {
    let build = || {
        let (mut w, mut poses) = scene(700);
        // Walls that cut through the cloud: tilted, and facing -x / +y.
        for n in [
            Vector3::new(0.3, -0.2, 1.0),
            Vector3::new(-1.0, 0.0, 0.1),
            Vector3::new(0.0, 1.0, 0.0),
        ] {
            let owner = poses.len() as u32;
            let o = Vector3::new(0.6, 0.65, 0.4);
            poses.push(Isometry3::translation(
                o.x - 0.3 * n.x,
                o.y - 0.3 * n.y,
                o.z - 0.3 * n.z,
            ));
            w.add_collider(
                owner,
                &Shape::HalfSpace { normal: n },
                Isometry3::identity(),
                mat(),
            )
            .unwrap();
        }
        w.set_grid_min_spheres(0);
        (w, poses)
    };
    let (mut plain, poses) = build();
    let (mut skinned, _) = build();
    skinned.set_sphere_skin(0.6).unwrap();
    assert!(plain.set_sphere_skin(-1.0).is_err());
    let (mut sweep, _) = build();
    sweep.set_grid_min_spheres(usize::MAX);
    // The floor and the three walls are fixed.
    let n = poses.len();
    let active: Vec<bool> = (0..n).map(|i| i != 0 && i + 3 < n).collect();
    let detect = |w: &mut CollisionWorld, p: &[Isometry3<f64>]| {
        let mut out = Vec::new();
        w.detect(p, &active, &mut out).unwrap();
        out
    };
    for k in 0..30 {
        let p = drifted(&poses, k);
        let a = detect(&mut plain, &p);
        let b = detect(&mut skinned, &p);
        assert!(a.len() > 300, "{}", a.len());
        assert_eq!(a, b, "step {k}");
        // The walls' boundary-cell query finds what testing every sphere finds.
        let c = detect(&mut sweep, &p);
        let (a, c) = (sorted(a), sorted(c));
        assert_eq!(a.len(), c.len(), "step {k}");
        for (x, y) in a.iter().zip(&c) {
            assert_eq!(x.key, y.key);
        }
    }
    assert_eq!(plain.sphere_grid_rebuilds(), 30);
    let r = skinned.sphere_grid_rebuilds();
    assert!((2..30).contains(&r), "{r} rebuilds");
}
