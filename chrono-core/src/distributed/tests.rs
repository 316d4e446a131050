use super::*;

#[test]
fn balanced_cuts_split_the_count_and_do_not_cut_a_plane() {
    // 10 planes of 10 particles at x = 0.1 k
    let coords: Vec<f64> = (0..100).map(|i| 0.1 * (i / 10) as f64).collect();
    let s = Slabs::balanced(&coords, &[1.0; 100], 4, 0.15).unwrap();
    assert_eq!(s.cuts.len(), 3);
    let mut n = [0usize; 4];
    for &c in &coords {
        n[s.owner(c)] += 1;
    }
    // planes are not cut: 25 per rank is impossible, 20-30 each
    assert!(n.iter().all(|&k| (20..=30).contains(&k)), "{n:?}");
    assert_eq!(n.iter().sum::<usize>(), 100);
    for &c in &s.cuts {
        let k = (c / 0.1 - 0.5).round();
        assert!(
            (c - 0.1 * (k + 0.5)).abs() < 1e-12,
            "cut {c} not between planes"
        );
    }
}

#[test]
fn weights_move_the_cut() {
    // 50 light particles left of 1, 50 heavy right of 1: the cut moves right of the
    // middle so each side carries half the weight
    let coords: Vec<f64> = (0..100).map(|i| 0.02 * i as f64).collect();
    let w: Vec<f64> = (0..100).map(|i| if i < 50 { 0.25 } else { 1.0 }).collect();
    let s = Slabs::balanced(&coords, &w, 2, 0.01).unwrap();
    let left: f64 = coords
        .iter()
        .zip(&w)
        .filter(|(c, _)| s.owner(**c) == 0)
        .map(|(_, w)| w)
        .sum();
    assert!(
        (left - 31.25).abs() <= 1.0,
        "left weight {left} of 62.5, cut {:?}",
        s.cuts
    );
}

#[test]
fn too_many_ranks_is_an_error_naming_them() {
    let coords: Vec<f64> = (0..100).map(|i| 0.01 * i as f64).collect();
    let e = Slabs::balanced(&coords, &[1.0; 100], 8, 0.3)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("ranks") && e.contains("more ranks than slabs"),
        "{e}"
    );
    let e = Slabs::balanced(&coords[..3], &[1.0; 3], 4, 0.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("ranks"), "{e}");
}

#[test]
fn near_covers_the_slab_and_its_halo() {
    let s = Slabs {
        cuts: vec![1.0, 2.0],
    };
    assert_eq!(s.owner(0.5), 0);
    assert_eq!(s.owner(1.0), 1);
    assert_eq!(s.owner(2.5), 2);
    assert!(s.near(1, 0.95, 0.1) && s.near(1, 2.05, 0.1));
    assert!(!s.near(1, 0.85, 0.1) && !s.near(1, 2.15, 0.1));
    assert!(s.near(0, -1e9, 0.1) && s.near(2, 1e9, 0.1));
}

#[test]
fn histogram_cuts_balance_the_count() {
    let counts = vec![10.0; 100];
    let s = Slabs::from_histogram(&counts, 0.0, 1.0, 4, 0.05).unwrap();
    for (c, e) in s.cuts.iter().zip([0.25, 0.5, 0.75]) {
        assert!((c - e).abs() < 1e-12, "{c} vs {e}");
    }
}

#[test]
fn local_transport_collectives() {
    let ranks = LocalTransport::ranks(3);
    let out: Vec<_> = std::thread::scope(|s| {
        let hs: Vec<_> = ranks
            .into_iter()
            .map(|mut t| {
                s.spawn(move || {
                    let me = t.rank();
                    let send: Vec<Vec<f64>> =
                        (0..3).map(|q| vec![(10 * me + q) as f64; q + 1]).collect();
                    let mut recv = vec![Vec::new(); 3];
                    t.all_to_all(&send, &mut recv).unwrap();
                    let mut m = [me as f64, -(me as f64)];
                    t.all_max(&mut m).unwrap();
                    let mut sum = [0.1 * me as f64];
                    t.all_sum(&mut sum).unwrap();
                    (recv, m, sum)
                })
            })
            .collect();
        hs.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for (me, (recv, m, sum)) in out.iter().enumerate() {
        for (q, r) in recv.iter().enumerate() {
            assert_eq!(r, &vec![(10 * q + me) as f64; me + 1]);
        }
        assert_eq!(m, &[2.0, 0.0]);
        assert_eq!(sum[0], (0.0 + 0.1) + 0.2);
    }
}

#[test]
fn a_rank_that_leaves_fails_the_others_collective() {
    let mut ranks = LocalTransport::ranks(2);
    let gone = ranks.pop().unwrap();
    let mut t = ranks.pop().unwrap();
    drop(gone);
    let e = t.all_max(&mut [1.0]).unwrap_err().to_string();
    assert!(e.contains("rank 1"), "{e}");
}

#[test]
fn a_launch_by_mpirun_is_seen() {
    // the variables are read, not set: a test cannot safely set the environment of a
    // threaded process; without a launcher there is no rank count
    if std::env::var("OMPI_COMM_WORLD_SIZE").is_err() && std::env::var("PMI_SIZE").is_err() {
        assert_eq!(launched_ranks(), None);
        assert!(require_single_process("test").is_ok());
    }
}
