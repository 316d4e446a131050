//! Constraint rows: sparse Jacobian rows grouped by kind, built by bodies, joints, contacts
//! and physics items every step.

use super::variables::BlockId;

/// The kind of a row group, which fixes the admissible set of its multipliers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RowGroup {
    /// Free multiplier (joints, density constraints): `c_i = 0`.
    Bilateral = 0,
    /// Multiplier in `[lo, hi]` (motors with force limits).
    Box = 1,
    /// Multiplier `>= 0` (frictionless contact, joint limits).
    Unilateral = 2,
    /// Triplets `(n, u, w)` in the Coulomb cone `|(g_u, g_w)| <= mu g_n`.
    Friction = 3,
    /// Six rows `(n, u, w, s, r_u, r_w)` per contact: sliding, spinning and rolling friction,
    /// `|(g_u, g_w)| <= mu g_n`, `|g_s| <= mu_s g_n`, `|(g_ru, g_rw)| <= mu_r g_n`
    /// (Tasora and Anitescu 2013, "A complementarity-based rolling friction model for rigid
    /// contacts", Meccanica 48). `s, r_u, r_w` are torque impulses (N m s).
    Rolling = 4,
    /// [`PER_BODY_ROWS`] rows `(n, u, w, s, a_n, a_u, a_w, b_n, b_u, b_w)` per contact:
    /// sliding and spinning friction as in [`Rolling`](Self::Rolling), and a rolling
    /// resistance on each body's *own* rotation (Zhou et al. 1999, Physica A 269): `a_*`
    /// touch body A's angular velocity only, `b_*` body B's, each a ball
    /// `|(g_an, g_au, g_aw)| <= mu_r g_n`, `|(g_bn, g_bu, g_bw)| <= mu_r g_n` (the rows of a
    /// body without variables have no entries).
    RollingPerBody = 5,
}

/// The number of row groups.
pub const N_GROUPS: usize = 6;

/// Rows of one contact of the [`RowGroup::RollingPerBody`] group.
pub const PER_BODY_ROWS: usize = 10;

/// One block of a row: the coefficients of `D_i'` on the dof of one variable block.
#[derive(Debug, Clone, Copy)]
pub struct RowEntry<'a> {
    /// The variable block.
    pub block: BlockId,
    /// One coefficient per dof of the block.
    pub coefs: &'a [f64],
}

/// A row as pushed: its group and its index in that group (for friction, the normal row of
/// the triplet; `u` and `w` follow it). [`CcpProblem::row_index`](super::CcpProblem::row_index)
/// maps it to the global row after assembly.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct RowId {
    /// The group.
    pub group: RowGroup,
    /// Index of the row within its group.
    pub index: u32,
}

#[derive(Debug, Clone, Default)]
pub(crate) struct GroupRows {
    pub row_ptr: Vec<u32>,
    pub ent_block: Vec<u32>,
    pub ent_coef: Vec<u32>,
    pub coefs: Vec<f64>,
    pub b: Vec<f64>,
    pub eps: Vec<f64>,
    /// Box bounds (Box group only).
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    /// One friction coefficient per triplet (Friction group), three per contact
    /// (`mu, mu_spin, mu_roll`, Rolling and RollingPerBody groups).
    pub mu: Vec<f64>,
    /// Friction group: the contact frames given with
    /// [`ConstraintRows::set_contact_frame`], by triplet index (increasing).
    pub frames: Vec<(u32, ContactFrame)>,
    /// Per entry of `frames`: how its rows relate to it ([`FrameKind`]).
    pub frame_kind: Vec<FrameKind>,
}

/// How a friction triplet's rows relate to its [`ContactFrame`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum FrameKind {
    /// Explicit rows given with the frame: the assembly checks that they match it.
    Checked,
    /// No explicit rows: the frame alone ([`ConstraintRows::push_friction_frame`]); the
    /// rows are `[∓d; (R' r) x (R' (∓d))]` on each side's rigid-body block, with `R` the
    /// block's rotation ([`Variables::add_oriented`](super::Variables::add_oriented)).
    Only,
}

impl GroupRows {
    fn clear(&mut self) {
        self.row_ptr.clear();
        self.row_ptr.push(0);
        self.ent_block.clear();
        self.ent_coef.clear();
        self.coefs.clear();
        self.b.clear();
        self.eps.clear();
        self.lo.clear();
        self.hi.clear();
        self.mu.clear();
        self.frames.clear();
        self.frame_kind.clear();
    }

    pub fn n_rows(&self) -> usize {
        self.b.len()
    }

    fn push(&mut self, entries: &[RowEntry], b: f64, eps: f64) -> u32 {
        if self.row_ptr.is_empty() {
            self.row_ptr.push(0);
        }
        for e in entries {
            self.ent_block.push(e.block.0);
            self.ent_coef.push(self.coefs.len() as u32);
            // A rigid body's 6 coefficients as a fixed-size copy (not a library call).
            match <&[f64; 6]>::try_from(e.coefs) {
                Ok(c) => self.coefs.extend_from_slice(c),
                Err(_) => self.coefs.extend_from_slice(e.coefs),
            }
        }
        self.row_ptr.push(self.ent_block.len() as u32);
        self.b.push(b);
        self.eps.push(eps);
        (self.b.len() - 1) as u32
    }
}

/// The geometry of a friction triplet between two rigid bodies with isotropic inertia
/// (spheres): with it [`CcpProblem::apply_n`](super::CcpProblem::apply_n) computes the
/// triplet's share of `N g` from the contact frame and the two lever arms (matrix-free, 9
/// numbers instead of 36 Jacobian coefficients), while the explicit rows stay the
/// reference for every row-level access.
///
/// It describes rows pushed by [`ConstraintRows::push_friction`] as: row `d` (`d` = `n`,
/// `u`, `w` with `(u, w) = `[`tangent_frame`](crate::math::tangent_frame)`(n)`) has on
/// block A (if any) the entry `[-d; (R_A' r_A) x (R_A' (-d))]` and then on block B (if
/// any) `[d; (R_B' r_B) x (R_B' d)]` (the relative velocity of B's contact point with
/// respect to A's along `d`, angular velocities in the body frames; the layout of
/// `RigidBody::point_jacobian`). The problem checks this at assembly (the blocks, the
/// linear coefficients exactly, the angular ones' norms to 1e-9) and uses the
/// matrix-free path only for triplets that pass and whose blocks are rigid bodies with
/// isotropic inertia touched by no other kind of row; the others use the explicit rows.
/// (The crate's own NSC contact rows between rigid bodies are frame-only,
/// `ConstraintRows::push_friction_frame`: no explicit rows to check; the other conditions
/// still apply.)
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactFrame {
    /// Unit contact normal `n` (world, from A to B).
    pub normal: [f64; 3],
    /// The variable blocks of side A and side B (`None`: no variables, e.g. a fixed body).
    pub blocks: [Option<BlockId>; 2],
    /// The lever arms `p - x` from each body's center of mass to its contact point (world,
    /// m).
    pub arms: [[f64; 3]; 2],
}

/// The rows of one step, in six groups ([`RowGroup`]). Reused across steps: [`clear`](Self::clear) keeps
/// the allocations.
///
/// Row `i` stands for the constraint velocity `c_i = D_i' v + b_i + eps_i g_i`:
/// bilateral rows require `c_i = 0`, unilateral `0 <= g_i ⊥ c_i >= 0`, friction triplets the
/// cone complementarity of the seed. `b_i` carries stabilization (`Phi_i / h`) and known
/// velocities (e.g. of kinematic bodies); `eps_i >= 0` is the compliance (regularization).
#[derive(Debug, Clone, Default)]
pub struct ConstraintRows {
    pub(crate) groups: [GroupRows; N_GROUPS],
}

impl ConstraintRows {
    /// An empty set.
    pub fn new() -> Self {
        let mut s = Self::default();
        s.clear();
        s
    }

    /// Remove all rows, keeping the allocations.
    pub fn clear(&mut self) {
        for g in &mut self.groups {
            g.clear();
        }
    }

    /// Number of rows in a group.
    pub fn n_rows(&self, group: RowGroup) -> usize {
        self.groups[group as usize].n_rows()
    }

    /// Total number of rows.
    pub fn total_rows(&self) -> usize {
        self.groups.iter().map(|g| g.n_rows()).sum()
    }

    /// Add a bilateral row `D_i' v + b + eps g = 0`.
    pub fn push_bilateral(&mut self, entries: &[RowEntry], b: f64, eps: f64) -> RowId {
        let index = self.groups[RowGroup::Bilateral as usize].push(entries, b, eps);
        RowId {
            group: RowGroup::Bilateral,
            index,
        }
    }

    /// Add a unilateral row `0 <= g ⊥ D_i' v + b + eps g >= 0`.
    pub fn push_unilateral(&mut self, entries: &[RowEntry], b: f64, eps: f64) -> RowId {
        let index = self.groups[RowGroup::Unilateral as usize].push(entries, b, eps);
        RowId {
            group: RowGroup::Unilateral,
            index,
        }
    }

    /// Add a box-bounded row: `g` in `[lo, hi]` (impulse bounds, N s), with the mixed
    /// complementarity conditions of a box (e.g. a motor with a torque limit).
    pub fn push_box(&mut self, entries: &[RowEntry], b: f64, eps: f64, lo: f64, hi: f64) -> RowId {
        let g = &mut self.groups[RowGroup::Box as usize];
        let index = g.push(entries, b, eps);
        g.lo.push(lo);
        g.hi.push(hi);
        RowId {
            group: RowGroup::Box,
            index,
        }
    }

    /// Add a frictional contact: three rows (normal `n`, tangents `u`, `w`), each with its
    /// entries, right-hand side and compliance, and the friction coefficient `mu`.
    /// Returns the id of the normal row; the tangent rows are the next two of the group.
    pub fn push_friction(
        &mut self,
        mu: f64,
        rows: [&[RowEntry]; 3],
        b: [f64; 3],
        eps: [f64; 3],
    ) -> RowId {
        let g = &mut self.groups[RowGroup::Friction as usize];
        let index = g.push(rows[0], b[0], eps[0]);
        g.push(rows[1], b[1], eps[1]);
        g.push(rows[2], b[2], eps[2]);
        g.mu.push(mu);
        RowId {
            group: RowGroup::Friction,
            index,
        }
    }

    /// Attach the geometry of the friction triplet `row` (returned by
    /// [`push_friction`](Self::push_friction)), so that `N g` can be applied matrix-free
    /// for it (see [`ContactFrame`]). Triplets must be given in the order they were pushed;
    /// a frame for another group's row, or out of order, is ignored.
    pub fn set_contact_frame(&mut self, row: RowId, frame: ContactFrame) {
        self.push_frame(row, frame, FrameKind::Checked);
    }

    /// Add a frictional contact between rigid bodies given by its geometry alone: the
    /// three rows `n, u, w` (`(u, w)` = [`tangent_frame`](crate::math::tangent_frame)`(n)`)
    /// are those [`ContactFrame`] describes (the arms `p - x` as
    /// [`RigidBody::point_jacobians`](crate::RigidBody::point_jacobians) takes them: the
    /// same coefficients, bit for bit), on blocks added with
    /// [`Variables::add_oriented`](super::Variables::add_oriented) (the assembly rejects
    /// a block without a rotation or with other than 6 dof, naming the row). No
    /// coefficients are stored: the assembly builds them only if a row-level access needs
    /// them (between spheres applied matrix-free, none does). Returns the id of the normal
    /// row.
    pub(crate) fn push_friction_frame(
        &mut self,
        mu: f64,
        frame: ContactFrame,
        b: [f64; 3],
        eps: [f64; 3],
    ) -> RowId {
        let g = &mut self.groups[RowGroup::Friction as usize];
        let index = g.push(&[], b[0], eps[0]);
        g.push(&[], b[1], eps[1]);
        g.push(&[], b[2], eps[2]);
        g.mu.push(mu);
        let row = RowId {
            group: RowGroup::Friction,
            index,
        };
        self.push_frame(row, frame, FrameKind::Only);
        row
    }

    pub(super) fn push_frame(&mut self, row: RowId, frame: ContactFrame, kind: FrameKind) {
        let g = &mut self.groups[RowGroup::Friction as usize];
        let k = row.index / 3;
        let in_order = g.frames.last().is_none_or(|&(last, _)| last < k);
        if row.group == RowGroup::Friction
            && row.index.is_multiple_of(3)
            && (k as usize) < g.mu.len()
            && in_order
        {
            g.frames.push((k, frame));
            g.frame_kind.push(kind);
        }
    }

    /// Add a contact with sliding, spinning and rolling friction: six rows `n, u, w` (force
    /// rows, as in [`push_friction`](Self::push_friction)), `s` (torque about the normal),
    /// `r_u, r_w` (torques about the tangents), with friction coefficients
    /// `mu = [mu_slide, mu_spin, mu_roll]` (`mu_spin`, `mu_roll` in m: torque per normal
    /// force). Returns the id of the normal row; the other five follow it.
    pub fn push_rolling_friction(
        &mut self,
        mu: [f64; 3],
        rows: [&[RowEntry]; 6],
        b: [f64; 6],
        eps: [f64; 6],
    ) -> RowId {
        let g = &mut self.groups[RowGroup::Rolling as usize];
        let index = g.push(rows[0], b[0], eps[0]);
        for j in 1..6 {
            g.push(rows[j], b[j], eps[j]);
        }
        g.mu.extend_from_slice(&mu);
        RowId {
            group: RowGroup::Rolling,
            index,
        }
    }

    /// Add a contact with sliding and spinning friction and a per-body rolling resistance:
    /// [`PER_BODY_ROWS`] rows `n, u, w, s` (as in
    /// [`push_rolling_friction`](Self::push_rolling_friction)), then `a_n, a_u, a_w` (body
    /// A's angular velocity only) and `b_n, b_u, b_w` (body B's), with coefficients
    /// `mu = [mu_slide, mu_spin, mu_roll]`; see [`RowGroup::RollingPerBody`]. Returns the id
    /// of the normal row; the other rows follow it.
    pub fn push_rolling_per_body(
        &mut self,
        mu: [f64; 3],
        rows: [&[RowEntry]; PER_BODY_ROWS],
        b: [f64; PER_BODY_ROWS],
        eps: [f64; PER_BODY_ROWS],
    ) -> RowId {
        let g = &mut self.groups[RowGroup::RollingPerBody as usize];
        let index = g.push(rows[0], b[0], eps[0]);
        for j in 1..PER_BODY_ROWS {
            g.push(rows[j], b[j], eps[j]);
        }
        g.mu.extend_from_slice(&mu);
        RowId {
            group: RowGroup::RollingPerBody,
            index,
        }
    }
}
