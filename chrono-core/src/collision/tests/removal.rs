//! Removing owners in place (`CollisionWorld::remove_owners`): the collider layout, the
//! returned map, the excluded pairs, and contacts equal to a world built afresh.

use super::*;

fn sphere() -> Shape {
    Shape::Sphere { radius: 0.5 }
}

fn owners(w: &CollisionWorld) -> Vec<u32> {
    w.colliders().iter().map(|c| c.owner()).collect()
}

/// A world with the same colliders (and owners), built afresh in their order.
fn rebuilt(w: &CollisionWorld) -> CollisionWorld {
    let mut fresh = CollisionWorld::new(w.envelope()).unwrap();
    for c in w.colliders() {
        fresh
            .add_collider(c.owner(), c.shape(), *c.local_pose(), c.material())
            .unwrap();
    }
    fresh
}

#[test]
fn blocks_move_and_the_map_follows() {
    // Owners 0: plane; 1: two boxes; 2: sphere; 3: box.
    let mut w = CollisionWorld::new(0.01).unwrap();
    w.add_collider(0, &plane(), Isometry3::identity(), mat())
        .unwrap();
    w.add_collider(1, &unit_box(), Isometry3::identity(), mat())
        .unwrap();
    w.add_collider(1, &unit_box(), at(1.0, 0.0, 0.0), mat())
        .unwrap();
    w.add_collider(2, &sphere(), Isometry3::identity(), mat())
        .unwrap();
    w.add_collider(3, &unit_box(), Isometry3::identity(), mat())
        .unwrap();
    w.exclude_pair(1, 3);
    w.exclude_pair(2, 3);
    // Owner 1 leaves, owner 3 takes its number (fewer colliders: owner 2's shift).
    let map = w.remove_owner(1, Some(3));
    assert_eq!(map, [Some(0), None, None, Some(2), Some(1)]);
    assert_eq!(owners(&w), [0, 1, 2]);
    assert!(matches!(w.colliders()[1].shape(), Shape::Box { .. }));
    assert!(w.is_pair_excluded(1, 2));
    assert!(!w.is_pair_excluded(1, 3));
    // The last owner leaves: nothing moves.
    assert_eq!(w.remove_owner(2, None), [Some(0), Some(1), None]);
    assert_eq!(owners(&w), [0, 1]);
    assert!(!w.is_pair_excluded(1, 2));
}

#[test]
fn colliders_added_out_of_owner_order_are_sorted_once() {
    let mut w = CollisionWorld::new(0.01).unwrap();
    for o in [2, 0, 1] {
        w.add_collider(o, &sphere(), at(o as f64, 0.0, 0.0), mat())
            .unwrap();
    }
    assert_eq!(w.remove_owner(0, Some(2)), [Some(0), None, Some(1)]);
    assert_eq!(owners(&w), [0, 1]);
    assert_eq!(*w.colliders()[0].local_pose(), at(2.0, 0.0, 0.0));
    // A moved owner below the removed one (not a swap-remove from the end).
    let mut w = world(0.01, &[sphere(), sphere(), sphere()]);
    assert_eq!(w.remove_owner(2, Some(0)), [Some(1), Some(0), None]);
    assert_eq!(owners(&w), [1, 2]);
}

/// Boxes resting on boxes and spheres (manifolds and analytic pairs) keep their pair
/// states through removals; the contacts then are those of a world built afresh, with
/// and without the sphere grid.
#[test]
fn contacts_after_removal_are_those_of_a_fresh_world() {
    for grid in [usize::MAX, 0] {
        contacts_after_removal(grid);
    }
}

fn contacts_after_removal(grid: usize) {
    let mut w = CollisionWorld::new(0.05).unwrap();
    w.set_grid_min_spheres(grid);
    w.add_collider(0, &plane(), Isometry3::identity(), mat())
        .unwrap();
    let n = 12u32;
    let pose = |o: u32| at(0.9 * (o % 4) as f64, 0.0, 0.49 + 0.99 * (o / 4) as f64);
    for o in 1..=n {
        let s = if o % 3 == 0 { sphere() } else { unit_box() };
        w.add_collider(o, &s, Isometry3::identity(), mat()).unwrap();
        if o % 5 == 0 {
            w.add_collider(o, &sphere(), at(0.0, 0.6, 0.0), mat())
                .unwrap();
        }
    }
    let mut poses: Vec<Isometry3<f64>> = (0..=n).map(pose).collect();
    poses[0] = Isometry3::identity();
    let first = detect(&mut w, &poses);
    assert!(!first.is_empty());
    // Swap-removes of owners 2, 5 and 1 (as the bodies would be).
    let mut removals = Vec::new();
    let mut last = n;
    for o in [2u32, 5, 1] {
        let moved = (o != last).then_some(last);
        if let Some(m) = moved {
            poses.swap(o as usize, m as usize);
        }
        poses.pop();
        removals.push((o, moved));
        last -= 1;
    }
    let before = w.len();
    w.remove_owners(&removals);
    // As many new colliders as left (the sphere grid must see the new ones, not count).
    for k in 0..(before - w.len()) as u32 {
        let o = last + 1 + k;
        w.add_collider(o, &sphere(), Isometry3::identity(), mat())
            .unwrap();
        poses.push(at(0.9 * k as f64, 2.0, 0.5));
    }
    let mine = detect(&mut w, &poses);
    let mut fresh = rebuilt(&w);
    fresh.set_grid_min_spheres(grid);
    assert_eq!(mine, detect(&mut fresh, &poses));
    assert_eq!(w.used_grid(), grid == 0);
    check_invariants(&mine);
}
