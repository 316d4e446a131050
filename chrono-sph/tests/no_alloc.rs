//! The step loop does not grow any buffer after warm-up. The workspace forbids `unsafe`,
//! so a counting global allocator cannot be written here; instead every buffer's
//! capacity (particle arrays, grid, neighbour list, scratch) is fingerprinted, and the
//! step code was inspected for other allocations (`docs/performance.md`).

use chrono_sph::{SphBuilder, SphSettings};

#[test]
fn step_loop_does_not_allocate_after_warm_up() {
    let dp = 0.05;
    let settings = SphSettings {
        spacing: dp,
        sound_speed: 20.0,
        skin: 0.0,        // rebuild the list every step: the worst case
        reorder_every: 0, // a re-sort swaps buffers (no allocation, new addresses)
        shepard_every: 5,
        domain_lower: [0.0; 3],
        domain_upper: [0.6, 7.0 * dp, 0.6],
        periodic: [false, true, false],
        ..SphSettings::default()
    };
    let mut b = SphBuilder::new(settings).unwrap();
    b.add_fluid_box([0.0; 3], [0.3, 7.0 * dp, 0.4], Some(0.4))
        .unwrap();
    b.add_tank(
        [0.0; 3],
        [0.6, 7.0 * dp, 0.6],
        3,
        [true, true, false, false, true, false],
        0,
    )
    .unwrap();
    let mut sys = b.build().unwrap();
    // warm-up: buffers grow to their working size (a collapsing column changes the
    // neighbour counts, so warm up long enough for the counts to peak)
    for _ in 0..200 {
        sys.step().unwrap();
    }
    let before = sys.buffer_fingerprint();
    for _ in 0..20 {
        sys.step().unwrap();
        assert_eq!(sys.buffer_fingerprint(), before, "a buffer was reallocated");
    }
}
