//! Grid queries against brute force (proptest), periodic images, determinism, reordering.

use proptest::prelude::*;

use super::*;

/// Brute-force neighbours of `p` (minimum image on periodic axes), `skip` excluded.
fn brute(
    pos: Positions<'_>,
    p: [f64; 3],
    radius: f64,
    skip: usize,
    period: [f64; 3],
) -> Vec<usize> {
    let mut out = Vec::new();
    for j in 0..pos[0].len() {
        if j == skip {
            continue;
        }
        let mut r2 = 0.0;
        for a in 0..3 {
            let mut d = p[a] - pos[a][j];
            if period[a] > 0.0 {
                d -= period[a] * (d / period[a]).round();
            }
            r2 += d * d;
        }
        if r2 <= radius * radius {
            out.push(j);
        }
    }
    out
}

fn cloud(seed_xyz: &[(f64, f64, f64)]) -> [Vec<f64>; 3] {
    [
        seed_xyz.iter().map(|p| p.0).collect(),
        seed_xyz.iter().map(|p| p.1).collect(),
        seed_xyz.iter().map(|p| p.2).collect(),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Neighbour lists, pairs and point queries equal brute force, with fixed bounds
    /// (some particles outside the box), auto bounds and periodic axes.
    #[test]
    fn queries_match_brute_force(
        pts in prop::collection::vec((-0.2f64..1.2, -0.2f64..1.2, -0.2f64..1.2), 0..300),
        cutoff in 0.08f64..0.45,
        frac in 0.3f64..1.0,
        mode in 0usize..4,
        probe in (-0.3f64..1.3, -0.3f64..1.3, -0.3f64..1.3),
    ) {
        let radius = cutoff * frac;
        let (config, period) = match mode {
            0 => (GridConfig::bounded(cutoff, [0.0; 3], [1.0; 3]), [0.0; 3]),
            1 => (GridConfig::auto(cutoff), [0.0; 3]),
            2 => (
                GridConfig::bounded(cutoff, [0.0; 3], [1.0; 3]).with_periodic([true, false, true]),
                [1.0, 0.0, 1.0],
            ),
            _ => (
                GridConfig::bounded(cutoff, [-0.2, -0.2, -0.2], [1.2, 1.2, 1.2])
                    .with_periodic([true, true, true]),
                [1.4, 1.4, 1.4],
            ),
        };
        let c = cloud(&pts);
        let pos: Positions<'_> = [&c[0], &c[1], &c[2]];
        let mut grid = CellGrid::new(config).unwrap();
        grid.build(pos).unwrap();
        // order is a permutation, sorted by cell
        let mut seen = vec![false; pts.len()];
        for &i in grid.order() { seen[i as usize] = true; }
        prop_assert!(seen.iter().all(|&s| s));
        for c in 0..grid.num_cells() {
            for k in grid.cell_range(c) {
                prop_assert_eq!(grid.cell_of(grid.order()[k] as usize), c);
            }
        }
        let mut list = NeighborList::new();
        grid.neighbor_list(pos, radius, &mut list).unwrap();
        prop_assert_eq!(list.len(), pts.len());
        let mut npairs = 0;
        for i in 0..pts.len() {
            let p = [c[0][i], c[1][i], c[2][i]];
            let mut got: Vec<usize> = list.neighbors(i).iter().map(|&j| j as usize).collect();
            got.sort_unstable();
            let want = brute(pos, p, radius, i, period);
            npairs += want.iter().filter(|&&j| j > i).count();
            prop_assert_eq!(&got, &want, "particle {}", i);
            let mut via_cb = Vec::new();
            grid.for_each_neighbor(pos, i, radius, |j, d, r2| {
                let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                assert!((dd - r2).abs() <= 1e-12);
                via_cb.push(j);
            }).unwrap();
            via_cb.sort_unstable();
            prop_assert_eq!(&via_cb, &want);
        }
        let mut pairs = Vec::new();
        grid.unique_pairs(pos, radius, &mut PairScratch::default(), &mut pairs).unwrap();
        prop_assert_eq!(pairs.len(), npairs);
        prop_assert!(pairs.iter().all(|p| p[0] < p[1]));
        let mut serial = Vec::new();
        grid.for_each_pair(pos, radius, |i, j, _, _| serial.push([i as u32, j as u32])).unwrap();
        prop_assert_eq!(&serial, &pairs);
        let q = [probe.0, probe.1, probe.2];
        let mut got = Vec::new();
        grid.for_each_in_radius(pos, q, radius, |j, _, _| got.push(j)).unwrap();
        got.sort_unstable();
        prop_assert_eq!(got, brute(pos, q, radius, usize::MAX, period));
    }
}

#[test]
fn output_is_independent_of_the_thread_count() {
    let n = 5000;
    let mut rng = crate::rng::Rng::new(12345);
    let mut rnd = || rng.uniform();
    let c: [Vec<f64>; 3] = std::array::from_fn(|_| (0..n).map(|_| rnd()).collect());
    let pos: Positions<'_> = [&c[0], &c[1], &c[2]];
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut grid = CellGrid::new(GridConfig::bounded(0.05, [0.0; 3], [1.0; 3])).unwrap();
            grid.build(pos).unwrap();
            let mut list = NeighborList::new();
            grid.neighbor_list(pos, 0.05, &mut list).unwrap();
            let mut pairs = Vec::new();
            grid.unique_pairs(pos, 0.05, &mut PairScratch::default(), &mut pairs)
                .unwrap();
            (
                grid.order().to_vec(),
                list.offsets.clone(),
                list.indices.clone(),
                pairs,
            )
        })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn reordering_keeps_the_neighbour_sets() {
    let n = 2000;
    let c: [Vec<f64>; 3] = std::array::from_fn(|a| {
        (0..n)
            .map(|i| ((i * (7 + 3 * a)) % 997) as f64 / 997.0)
            .collect()
    });
    let mut x = c.clone();
    let pos: Positions<'_> = [&c[0], &c[1], &c[2]];
    let mut grid = CellGrid::new(GridConfig::bounded(0.1, [0.0; 3], [1.0; 3])).unwrap();
    grid.build(pos).unwrap();
    let mut before = NeighborList::new();
    grid.neighbor_list(pos, 0.1, &mut before).unwrap();
    let order = grid.order().to_vec();
    let mut scratch = Vec::new();
    for v in x.iter_mut() {
        permute(&order, v, &mut scratch);
    }
    grid.reordered();
    assert!(
        grid.order()
            .iter()
            .enumerate()
            .all(|(k, &o)| o as usize == k)
    );
    let pos2: Positions<'_> = [&x[0], &x[1], &x[2]];
    let mut after = NeighborList::new();
    grid.neighbor_list(pos2, 0.1, &mut after).unwrap();
    for k in 0..n {
        let mut a: Vec<u32> = after
            .neighbors(k)
            .iter()
            .map(|&j| order[j as usize])
            .collect();
        let mut b = before.neighbors(order[k] as usize).to_vec();
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a, b);
    }
    // particles sorted by cell are contiguous in cell order
    for k in 1..n {
        assert!(grid.cell_of(k - 1) <= grid.cell_of(k));
    }
}

#[test]
fn bad_configurations_are_rejected_with_the_field() {
    let e = CellGrid::new(GridConfig::auto(0.0)).unwrap_err();
    assert!(e.to_string().contains("grid.cutoff"), "{e}");
    let e = CellGrid::new(GridConfig::auto(0.1).with_periodic([false, true, false])).unwrap_err();
    assert!(e.to_string().contains("grid.periodic[1]"), "{e}");
    let e = CellGrid::new(
        GridConfig::bounded(0.1, [0.0; 3], [0.15, 1.0, 1.0]).with_periodic([true, false, false]),
    )
    .unwrap_err();
    assert!(e.to_string().contains("period"), "{e}");
    let e = CellGrid::new(GridConfig::bounded(0.1, [0.0; 3], [1.0, -1.0, 1.0])).unwrap_err();
    assert!(e.to_string().contains("grid.upper[1]"), "{e}");
    let mut g = CellGrid::new(GridConfig::bounded(0.1, [0.0; 3], [1.0; 3])).unwrap();
    let x = [0.5, f64::NAN];
    let e = g.build([&x, &x, &x]).unwrap_err();
    assert!(e.to_string().contains("position[1][0]"), "{e}");
    let y = [0.5, 0.5];
    g.build([&y, &y, &y]).unwrap();
    let e = g
        .neighbor_list([&y, &y, &y], 0.2, &mut NeighborList::new())
        .unwrap_err();
    assert!(e.to_string().contains("radius"), "{e}");
}
