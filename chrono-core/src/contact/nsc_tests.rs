//! The NSC rows of contacts between rigid bodies, stored as their frames
//! ([`super::nsc::add_contact_rows`]): the coefficients the assembly builds are
//! `RigidBody::point_jacobian`'s, the same rows given explicitly with checked frames select
//! the same matrix-free triplets with the same bits, and a problem of spheres alone (its
//! coefficients deferred) agrees with its explicit form to rounding.

use nalgebra::{UnitQuaternion, Vector3};

use super::nsc::{NscRowSettings, TripletScratch, add_contact_rows};
use super::nsc_plain::{add_plain_rows_par, plain_triplet, push_plain};
use crate::body::{RigidBody, RigidBodyBuilder};
use crate::collision::{ColliderId, ContactKey, ContactPoint};
use crate::contact::smc::RollingModel;
use crate::descriptor::{
    CcpProblem, CcpWork, ConstraintRows, FrameKind, RowEntry, RowGroup, Variables,
};
use crate::material::ContactMaterial;
use crate::rng::Rng;

/// Spheres with random rotations (isotropic inertia), an anisotropic body, a fixed and a
/// moving kinematic body (no variables), and contacts between random pairs of them.
fn scene(seed: u64) -> (Vec<RigidBody>, Variables, Vec<ContactPoint>) {
    scene_with(seed, 60, false)
}

/// [`scene`] with `n` contacts; with `no_vars` the fixed–kinematic pair (no variables, so
/// no rows) is kept where it is drawn.
fn scene_with(seed: u64, n: u32, no_vars: bool) -> (Vec<RigidBody>, Variables, Vec<ContactPoint>) {
    scene_full(seed, n, no_vars, false)
}

/// [`scene_with`]; with `spheres_only` the anisotropic body is a sphere too.
fn scene_full(
    seed: u64,
    n: u32,
    no_vars: bool,
    spheres_only: bool,
) -> (Vec<RigidBody>, Variables, Vec<ContactPoint>) {
    let mut rng = Rng::splitmix64(seed);
    let mut bodies = Vec::new();
    let rot = |rng: &mut Rng| {
        UnitQuaternion::from_euler_angles(
            rng.range(-3.0, 3.0),
            rng.range(-1.5, 1.5),
            rng.range(-3.0, 3.0),
        )
    };
    let v3 =
        |rng: &mut Rng, s: f64| Vector3::new(rng.range(-s, s), rng.range(-s, s), rng.range(-s, s));
    for i in 0..12 {
        let b = match i {
            10 => RigidBodyBuilder::fixed(),
            11 => RigidBodyBuilder::kinematic()
                .linear_velocity(v3(&mut rng, 1.0))
                .angular_velocity(v3(&mut rng, 2.0)),
            9 if !spheres_only => RigidBodyBuilder::dynamic()
                .mass(2.0)
                .inertia_diagonal(Vector3::new(0.1, 0.2, 0.3)),
            _ => RigidBodyBuilder::dynamic()
                .mass(rng.range(0.5, 2.0))
                .inertia_diagonal(Vector3::repeat(rng.range(0.01, 0.1))),
        };
        bodies.push(
            b.position(v3(&mut rng, 1.0))
                .rotation(rot(&mut rng))
                .build()
                .unwrap(),
        );
    }
    let mut vars = Variables::new();
    for b in bodies.iter_mut().filter(|b| b.is_dynamic()) {
        b.block = Some(vars.add_oriented(b.mass_operator().unwrap(), b.rotation));
    }
    let mut points = Vec::new();
    for c in 0..n {
        let a = rng.int(0, 11);
        let mut b = (a + 1 + rng.int(0, 10)) % 12;
        if a + b == 21 && !no_vars {
            // fixed against kinematic: no rows
            b = 0;
        }
        let normal = v3(&mut rng, 1.0).normalize();
        let p = v3(&mut rng, 1.0);
        points.push(ContactPoint {
            collider_a: ColliderId(a as u32),
            collider_b: ColliderId(b as u32),
            owner_a: a as u32,
            owner_b: b as u32,
            point_a: p - normal * 1e-3,
            point_b: p + normal * 1e-3,
            normal,
            distance: rng.range(-1e-3, 1e-3),
            key: ContactKey {
                collider_a: a as u32,
                collider_b: b as u32,
                feature_a: c,
                feature_b: 0,
            },
            material: ContactMaterial::smc(1e7, 0.3, 0.5, 0.4),
            radius: 0.01,
        });
    }
    (bodies, vars, points)
}

fn rows_of(bodies: &[RigidBody], points: &[ContactPoint]) -> ConstraintRows {
    let mut rows = ConstraintRows::new();
    let settings = NscRowSettings {
        h: 1e-3,
        max_recovery_speed: 0.5,
        rolling_model: RollingModel::default(),
    };
    let mut out = Vec::new();
    add_contact_rows(
        points,
        bodies,
        settings,
        &mut rows,
        &mut TripletScratch::default(),
        &mut out,
    )
    .unwrap();
    assert_eq!(out.len(), points.len());
    rows
}

/// The rows of `points` given explicitly (built from the bodies, `point_jacobian`) with
/// frames the assembly checks: the same triplets as the frame-only rows of [`rows_of`].
fn explicit_rows_of(bodies: &[RigidBody], points: &[ContactPoint]) -> ConstraintRows {
    let settings = NscRowSettings {
        h: 1e-3,
        max_recovery_speed: 0.5,
        rolling_model: RollingModel::default(),
    };
    let mut explicit = ConstraintRows::new();
    for cp in points {
        let (a, b) = (&bodies[cp.owner_a as usize], &bodies[cp.owner_b as usize]);
        let (u, w) = crate::math::tangent_frame(&cp.normal);
        let dirs = [cp.normal, u, w];
        let Some(t) = plain_triplet(settings, cp, a, b, &dirs) else {
            continue;
        };
        let entries = |d: &Vector3<f64>| {
            let mut e = Vec::new();
            if let Some(blk) = a.block {
                e.push((blk, a.point_jacobian(&cp.point_a, &-d)));
            }
            if let Some(blk) = b.block {
                e.push((blk, b.point_jacobian(&cp.point_b, d)));
            }
            e
        };
        let e: Vec<_> = dirs.iter().map(entries).collect();
        let re: Vec<Vec<RowEntry>> = (e.iter())
            .map(|r| {
                (r.iter())
                    .map(|(block, c)| RowEntry {
                        block: *block,
                        coefs: c,
                    })
                    .collect()
            })
            .collect();
        let id = explicit.push_friction(t.mu_of(), [&re[0], &re[1], &re[2]], t.b_of(), t.eps_of());
        explicit.set_contact_frame(id, t.frame_of());
    }
    explicit
}

#[test]
fn sphere_pair_rows_are_point_jacobians() {
    let (bodies, vars, points) = scene(7);
    let rows = rows_of(&bodies, &points);
    let k = vec![0.0; vars.ndof()];
    let mut p = CcpProblem::new();
    p.assemble(&vars, &rows, &k).unwrap();
    for (c, cp) in points.iter().enumerate() {
        let (a, b) = (&bodies[cp.owner_a as usize], &bodies[cp.owner_b as usize]);
        let (u, w) = crate::math::tangent_frame(&cp.normal);
        for (r, d) in [cp.normal, u, w].iter().enumerate() {
            let mut want = Vec::new();
            if let Some(blk) = a.block {
                want.push((blk, a.point_jacobian(&cp.point_a, &-d)));
            }
            if let Some(blk) = b.block {
                want.push((blk, b.point_jacobian(&cp.point_b, d)));
            }
            let have: Vec<_> = p.row_entries(3 * c + r).collect();
            assert_eq!(have.len(), want.len(), "contact {c} row {r}");
            for ((blk, _, coefs, _), (wb, wc)) in have.iter().zip(&want) {
                assert_eq!(blk, wb);
                let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(coefs), bits(wc), "contact {c} row {r}");
            }
        }
    }
}

#[test]
fn trusted_frames_select_what_the_check_selects_bit_for_bit() {
    for seed in 0..8 {
        let (bodies, vars, points) = scene(seed);
        let rows = rows_of(&bodies, &points);
        let g = &rows.groups[RowGroup::Friction as usize];
        assert_eq!(g.frame_kind.len(), points.len());
        assert!(g.frame_kind.iter().all(|&k| k == FrameKind::Only));
        assert!(g.coefs.is_empty(), "frame-only rows store no coefficients");
        let mut rng = Rng::splitmix64(100 + seed);
        let k: Vec<f64> = (0..vars.ndof()).map(|_| rng.range(-1.0, 1.0)).collect();
        let (mut p, mut q) = (CcpProblem::new(), CcpProblem::new());
        p.assemble(&vars, &rows, &k).unwrap();
        // the same rows given explicitly, with frames the assembly checks
        let checked = explicit_rows_of(&bodies, &points);
        let g = &checked.groups[RowGroup::Friction as usize];
        assert!(g.frame_kind.iter().all(|&k| k == FrameKind::Checked));
        q.assemble(&vars, &checked, &k).unwrap();
        assert_eq!(p.coefficients_deferred(), (false, false), "seed {seed}");
        assert!(p.n_matrix_free() > 0, "seed {seed}: no sphere pair");
        assert!(p.n_matrix_free() < points.len(), "seed {seed}: no fallback");
        assert_eq!(p.n_matrix_free(), q.n_matrix_free(), "seed {seed}");
        let gamma: Vec<f64> = (0..p.n_rows()).map(|_| rng.range(-1.0, 1.0)).collect();
        let (mut np, mut nq) = (vec![0.0; p.n_rows()], vec![0.0; p.n_rows()]);
        p.apply_n(&gamma, &mut np, &mut CcpWork::for_problem(&p));
        q.apply_n(&gamma, &mut nq, &mut CcpWork::for_problem(&q));
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&np), bits(&nq), "seed {seed}");
        assert_eq!(bits(p.r()), bits(q.r()), "seed {seed}");
        assert_eq!(bits(p.diag()), bits(q.diag()), "seed {seed}");
    }
}

#[test]
fn plain_rows_in_parallel_are_the_pushed_rows_bit_for_bit() {
    let settings = NscRowSettings {
        h: 1e-3,
        max_recovery_speed: 0.5,
        rolling_model: RollingModel::default(),
    };
    for (seed, n) in [(1, 1), (2, 700), (3, 5000)] {
        let (bodies, _, points) = scene_with(seed, n, true);
        // A triplet already in the group: the new rows' offsets start after it.
        let mut before = ConstraintRows::new();
        let first = &points[..1];
        add_contact_rows(
            first,
            &bodies,
            settings,
            &mut before,
            &mut TripletScratch::default(),
            &mut Vec::new(),
        )
        .unwrap();
        let (mut serial, mut par) = (before.clone(), before);
        let (mut out_s, mut out_p) = (Vec::new(), Vec::new());
        let mut skipped = 0;
        for cp in &points {
            let (a, b) = (&bodies[cp.owner_a as usize], &bodies[cp.owner_b as usize]);
            let (u, w) = crate::math::tangent_frame(&cp.normal);
            match plain_triplet(settings, cp, a, b, &[cp.normal, u, w]) {
                Some(t) => {
                    let row = push_plain(&mut serial, &t);
                    out_s.push(super::nsc::NscContact {
                        point: *cp,
                        u,
                        w,
                        row,
                    });
                }
                None => skipped += 1,
            }
        }
        add_plain_rows_par(&points, &bodies, settings, &mut par, &mut out_p);
        assert!(
            n < 5000 || skipped > 0,
            "seed {seed}: no contact without variables"
        );
        let (gs, gp) = (
            &serial.groups[RowGroup::Friction as usize],
            &par.groups[RowGroup::Friction as usize],
        );
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(gs.row_ptr, gp.row_ptr, "seed {seed}");
        assert_eq!(gs.ent_block, gp.ent_block, "seed {seed}");
        assert_eq!(gs.ent_coef, gp.ent_coef, "seed {seed}");
        assert_eq!(bits(&gs.coefs), bits(&gp.coefs), "seed {seed}");
        assert_eq!(bits(&gs.b), bits(&gp.b), "seed {seed}");
        assert_eq!(bits(&gs.eps), bits(&gp.eps), "seed {seed}");
        assert_eq!(bits(&gs.mu), bits(&gp.mu), "seed {seed}");
        assert_eq!(gs.frames, gp.frames, "seed {seed}");
        assert_eq!(gs.frame_kind, gp.frame_kind, "seed {seed}");
        assert_eq!(out_s, out_p, "seed {seed}");
        assert_eq!(out_p.len() + skipped, points.len());
    }
}

#[test]
fn spheres_alone_defer_their_coefficients_and_agree_with_explicit_rows() {
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    let close = |a: &[f64], b: &[f64], what: &str| {
        let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for (i, (x, y)) in a.iter().zip(b).enumerate() {
            assert!((x - y).abs() <= 1e-13 * scale, "{what}[{i}]: {x} vs {y}");
        }
    };
    for seed in 0..6 {
        let (bodies, vars, points) = scene_full(seed, 3000, false, true);
        let rows = rows_of(&bodies, &points);
        let mut rng = Rng::splitmix64(200 + seed);
        let k: Vec<f64> = (0..vars.ndof()).map(|_| rng.range(-1.0, 1.0)).collect();
        let (mut p, mut q) = (CcpProblem::new(), CcpProblem::new());
        p.assemble(&vars, &rows, &k).unwrap();
        assert!(p.explicit_free(), "seed {seed}");
        assert_eq!(p.coefficients_deferred(), (true, false), "seed {seed}");
        // the explicit form: rows built from the bodies, frames checked
        let explicit = explicit_rows_of(&bodies, &points);
        q.assemble(&vars, &explicit, &k).unwrap();
        assert_eq!(q.coefficients_deferred(), (false, false));
        assert_eq!(p.n_matrix_free(), q.n_matrix_free(), "seed {seed}");
        assert_eq!(p.n_coefs(), q.n_coefs(), "seed {seed}");
        close(p.diag(), q.diag(), "diag");
        close(p.r(), q.r(), "r");
        close(p.scales(), q.scales(), "scales");
        let gamma: Vec<f64> = (0..p.n_rows()).map(|_| rng.range(-1.0, 1.0)).collect();
        let (mut np, mut nq) = (vec![0.0; p.n_rows()], vec![0.0; p.n_rows()]);
        p.apply_n(&gamma, &mut np, &mut CcpWork::for_problem(&p));
        q.apply_n(&gamma, &mut nq, &mut CcpWork::for_problem(&q));
        assert_eq!(
            bits(&np),
            bits(&nq),
            "seed {seed}: the same matrix-free product"
        );
        let (mut vp, mut vq) = (vec![0.0; vars.ndof()], vec![0.0; vars.ndof()]);
        p.velocities(&gamma, &mut vp);
        q.velocities(&gamma, &mut vq);
        close(&vp, &vq, "velocities");
        assert_eq!(
            p.coefficients_deferred(),
            (true, false),
            "no row-level access yet"
        );
        // a row-level access builds the coefficients: the explicit rows' bits
        for i in 0..p.n_rows() {
            let (a, b): (Vec<_>, Vec<_>) = (p.row_entries(i).collect(), q.row_entries(i).collect());
            assert_eq!(a.len(), b.len());
            for (x, y) in a.iter().zip(&b) {
                assert_eq!((x.0, x.1), (y.0, y.1));
                assert_eq!(bits(x.2), bits(y.2), "seed {seed} row {i}: D");
                assert_eq!(bits(x.3), bits(y.3), "seed {seed} row {i}: M^-1 D");
            }
        }
        assert_eq!(p.coefficients_deferred(), (true, true));
        // the same momentum again: the same problem
        let (r, d) = (p.r().to_vec(), p.diag().to_vec());
        p.set_momentum(&k).unwrap();
        assert_eq!((bits(p.r()), bits(p.diag())), (bits(&r), bits(&d)));
    }
}

#[test]
fn frame_only_rows_need_oriented_blocks() {
    let (bodies, _, points) = scene(3);
    let rows = rows_of(&bodies, &points);
    let mut vars = Variables::new();
    for b in bodies.iter().filter(|b| b.is_dynamic()) {
        vars.add(b.mass_operator().unwrap());
    }
    let k = vec![0.0; vars.ndof()];
    let e = CcpProblem::new()
        .assemble(&vars, &rows, &k)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("rows.friction[") && e.contains("frame.blocks") && e.contains("rotation"),
        "{e}"
    );
    // a non-finite rotation is named too
    let mut vars = Variables::new();
    let nan = UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(f64::NAN, 0.0, 0.0, 0.0));
    for b in bodies.iter().filter(|b| b.is_dynamic()) {
        vars.add_oriented(b.mass_operator().unwrap(), nan);
    }
    let e = CcpProblem::new()
        .assemble(&vars, &rows, &k)
        .unwrap_err()
        .to_string();
    assert!(e.contains("frame.blocks") && e.contains("finite"), "{e}");
}

#[test]
fn a_bed_is_warm_started_and_stored_in_parallel_as_one_contact_at_a_time() {
    use super::nsc::{WarmStartCache, store, warm_start};
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    let (bodies, vars, points) = scene_with(11, 5000, false);
    let settings = NscRowSettings {
        h: 1e-3,
        max_recovery_speed: 0.5,
        rolling_model: RollingModel::default(),
    };
    let mut rows = ConstraintRows::new();
    let mut contacts = Vec::new();
    add_contact_rows(
        &points,
        &bodies,
        settings,
        &mut rows,
        &mut TripletScratch::default(),
        &mut contacts,
    )
    .unwrap();
    let mut p = CcpProblem::new();
    p.assemble(&vars, &rows, &vec![0.0; vars.ndof()]).unwrap();
    let mut rng = Rng::splitmix64(5);
    let gamma: Vec<f64> = (0..p.n_rows()).map(|_| rng.range(-1.0, 1.0)).collect();
    // stored all at once (parallel) and one contact at a time (serial, pushed in order)
    let mut cache = WarmStartCache::default();
    store(&contacts, &p, &gamma, &mut cache);
    assert_eq!(cache.len(), contacts.len());
    let mut all = vec![0.0; p.n_rows()];
    warm_start(&contacts, &mut cache, &p, &mut all);
    let mut one = vec![0.0; p.n_rows()];
    for c in &contacts {
        warm_start(std::slice::from_ref(c), &mut cache, &p, &mut one);
    }
    assert_eq!(bits(&all), bits(&one));
    // the impulses come back (the tangents projected on the same frame)
    for (a, b) in all.iter().zip(&gamma) {
        assert!((a - b).abs() <= 1e-14, "{a} vs {b}");
    }
}

#[test]
fn a_deferred_problem_survives_its_file_and_its_sub_problems() {
    use crate::descriptor::{HeldSubproblem, ProblemFile, ProblemFormat};
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    let (bodies, vars, points) = scene_full(4, 3000, false, true);
    let rows = rows_of(&bodies, &points);
    let mut rng = Rng::splitmix64(41);
    let k: Vec<f64> = (0..vars.ndof()).map(|_| rng.range(-1.0, 1.0)).collect();
    let mut p = CcpProblem::new();
    p.assemble(&vars, &rows, &k).unwrap();
    assert_eq!(p.coefficients_deferred(), (true, false));
    let g: Vec<f64> = (0..p.n_rows()).map(|_| rng.range(0.0, 1.0)).collect();
    let summary = |q: &CcpProblem| {
        let mut n = vec![0.0; q.n_rows()];
        q.apply_n(&g, &mut n, &mut CcpWork::for_problem(q));
        let mut v = vec![0.0; q.ndof()];
        q.velocities(&g, &mut v);
        [n, v, q.r().to_vec(), q.diag().to_vec(), q.scales().to_vec()].map(|x| bits(&x))
    };
    let want = summary(&p);
    // its rows again, and its file in both encodings: the same problem, deferred
    let mut again = CcpProblem::new();
    again
        .assemble(p.variables(), &p.constraint_rows(), p.momentum())
        .unwrap();
    assert_eq!(again.coefficients_deferred(), (true, false));
    assert_eq!(summary(&again), want);
    let file = ProblemFile::from_problem(&p, "deferred");
    assert!(file.frames.iter().all(|f| f.only));
    assert_eq!(file.rotations.len(), vars.len());
    let dir = std::env::temp_dir();
    for (name, format) in [
        ("ccp", ProblemFormat::Binary),
        ("json", ProblemFormat::Json),
    ] {
        let path = dir.join(format!("{}_deferred.{name}", std::process::id()));
        file.save(&path, format).unwrap();
        let q = ProblemFile::load_problem(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(q.coefficients_deferred(), (true, false), "{name}");
        assert_eq!(summary(&q), want, "{name}");
    }
    assert_eq!(
        p.coefficients_deferred(),
        (true, false),
        "nothing above built them"
    );
    // a held sub-problem (every other contact) keeps the blocks' rotations
    let fr = p.sections().friction.clone();
    let sub_rows: Vec<usize> = fr.step_by(6).flat_map(|i| i..i + 3).collect();
    let mut h = HeldSubproblem::new();
    h.build(&p, &sub_rows, &g).unwrap();
    assert_eq!(h.problem().coefficients_deferred(), (true, false));
    assert_eq!(h.problem().n_rows(), sub_rows.len());
    // a file without the rotations, or marking a triplet with entries frame-only, is
    // refused naming the field
    let mut no_rot = file.clone();
    no_rot.rotations.clear();
    let e = no_rot.to_problem().unwrap_err().to_string();
    assert!(e.contains("frame.blocks") && e.contains("rotation"), "{e}");
    let mut q = CcpProblem::new();
    q.assemble(&vars, &explicit_rows_of(&bodies, &points), &k)
        .unwrap();
    let mut marked = ProblemFile::from_problem(&q, "explicit");
    assert!(marked.frames.iter().all(|f| !f.only));
    marked.frames[3].only = true;
    let e = marked.to_problem().unwrap_err().to_string();
    assert!(
        e.contains("frames[3].only") && e.contains("no entries"),
        "{e}"
    );
}
