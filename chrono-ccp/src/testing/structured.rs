//! Small problems with known structure: one particle on the ground, a stack of boxes.

use chrono_core::descriptor::{
    BlockId, CcpProblem, ConstraintRows, MassOperator, RowEntry, Variables,
};
use chrono_core::math::{GRAVITY, Matrix3, Vector3};

/// One particle of mass `m` (kg) on the ground (normal +z, tangents +x, +y) with friction
/// `mu`, velocity `v` (m/s) before the step of `h` s under gravity ([`GRAVITY`]): returns
/// the problem, or the error of a bad mass.
pub fn particle_on_ground(m: f64, mu: f64, v: [f64; 3], h: f64) -> chrono_core::Result<CcpProblem> {
    let mut vars = Variables::new();
    let p = vars.add(MassOperator::particle(m)?);
    let mut rows = ConstraintRows::new();
    let n = [RowEntry {
        block: p,
        coefs: &[0.0, 0.0, 1.0],
    }];
    let u = [RowEntry {
        block: p,
        coefs: &[1.0, 0.0, 0.0],
    }];
    let w = [RowEntry {
        block: p,
        coefs: &[0.0, 1.0, 0.0],
    }];
    rows.push_friction(mu, [&n, &u, &w], [0.0; 3], [0.0; 3]);
    let k = [m * v[0], m * v[1], m * (v[2] + GRAVITY.z * h)];
    let mut problem = CcpProblem::new();
    problem.assemble(&vars, &rows, &k)?;
    Ok(problem)
}

/// A stack of `levels` unit cubes on the ground, the mass tripling per level (the top box of
/// 5 is 81 times the bottom one), 4 corner contacts (friction `mu`) per interface, at rest,
/// one step of `h` s under gravity. Rows are built directly (identity orientations). Unit
/// density of mass: the bottom box is 1 kg.
pub fn box_stack(levels: usize, mu: f64, h: f64) -> chrono_core::Result<CcpProblem> {
    box_stack_ratio(levels, 3.0, mu, h)
}

/// [`box_stack`] with mass ratio `ratio` between consecutive levels.
pub fn box_stack_ratio(
    levels: usize,
    ratio: f64,
    mu: f64,
    h: f64,
) -> chrono_core::Result<CcpProblem> {
    let mut vars = Variables::new();
    let mut masses = Vec::new();
    let mut ids: Vec<BlockId> = Vec::new();
    for i in 0..levels {
        let m = ratio.powi(i as i32);
        let j = Matrix3::from_diagonal_element(m / 6.0);
        ids.push(vars.add(MassOperator::rigid_body(m, j)?));
        masses.push(m);
    }
    let mut rows = ConstraintRows::new();
    let dirs = [Vector3::z(), Vector3::x(), Vector3::y()];
    for level in 0..levels {
        // contact between `level - 1` (or the ground) and `level`, on the bottom face of `level`
        for (sx, sy) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
            let r_up = Vector3::new(sx, sy, -0.5);
            let r_down = Vector3::new(sx, sy, 0.5);
            let up: Vec<[f64; 6]> = dirs.iter().map(|d| rigid_coefs(r_up, *d)).collect();
            let down: Vec<[f64; 6]> = dirs.iter().map(|d| rigid_coefs(r_down, -d)).collect();
            let row = |j: usize| {
                let mut e = vec![RowEntry {
                    block: ids[level],
                    coefs: &up[j],
                }];
                if level > 0 {
                    e.push(RowEntry {
                        block: ids[level - 1],
                        coefs: &down[j],
                    });
                }
                e
            };
            let (rn, ru, rw) = (row(0), row(1), row(2));
            rows.push_friction(mu, [&rn, &ru, &rw], [0.0; 3], [0.0; 3]);
        }
    }
    let mut k = vec![0.0; vars.ndof()];
    for (i, m) in masses.iter().enumerate() {
        k[6 * i + 2] = m * GRAVITY.z * h;
    }
    let mut problem = CcpProblem::new();
    problem.assemble(&vars, &rows, &k)?;
    Ok(problem)
}

/// Coefficients `[d, r x d]` of a rigid body (identity orientation, so body frame = world
/// frame) for the velocity along `d` of the material point at `r` from its center of mass.
pub fn rigid_coefs(r: Vector3<f64>, d: Vector3<f64>) -> [f64; 6] {
    let a = r.cross(&d);
    [d.x, d.y, d.z, a.x, a.y, a.z]
}
