//! Pushing one density row (a fluid particle's or a body marker's) into the system's
//! rows: the surface mode, the body blocks in body coordinates, the known velocity of
//! fixed and kinematic bodies.

use chrono_core::Bodies;
use chrono_core::body::{BodyHandle, RigidBody};
use chrono_core::descriptor::{BlockId, ConstraintRows, RowEntry, RowId};
use chrono_core::math::Vector3;

use chrono_core::density_rows::{RowBuf, SurfaceMode, push_density_row};

use crate::settings::CfluidSettings;

/// What pushing one density row needs: the fluid's first block, the system's bodies and
/// the attached slots, the settings, the step and the compliance.
pub(super) struct PushRow<'a> {
    pub(super) first: BlockId,
    pub(super) bodies: &'a Bodies,
    pub(super) slots: &'a [(BodyHandle, usize)],
    pub(super) settings: &'a CfluidSettings,
    pub(super) h: f64,
    pub(super) eps: f64,
}

impl PushRow<'_> {
    /// Push the row in `buf` (a particle or marker of density `rho`, support fraction
    /// `phi`: `C = rho / rho_0 - phi`) by the surface mode, or unilateral whatever the
    /// density if `marker` or `phi < 1` (a surface particle pushes but never pulls) (a body face may be pushed by the
    /// fluid but never holds it: a bilateral marker row held the film under a sinking body
    /// in tension). The body blocks are turned into body coordinates (angular part in the
    /// body frame); a body without variables (fixed, kinematic) moves its markers at a
    /// known velocity, which goes into `b`.
    pub(super) fn push<'b>(
        &self,
        buf: &'b mut RowBuf,
        rho: f64,
        phi: f64,
        marker: bool,
        entries: &mut Vec<RowEntry<'b>>,
        rows: &mut ConstraintRows,
    ) -> RowId {
        let mut known = 0.0;
        buf.bodies.retain_mut(|(slot, c)| {
            let body = &self.bodies[self.slots[*slot as usize].0];
            *c = body_coefs(body, c);
            match body.block() {
                Some(_) => true,
                None => {
                    known += body.jacobian_times_velocity(c);
                    false
                }
            }
        });
        entries.clear();
        for (k, &p) in buf.particles.iter().enumerate() {
            entries.push(RowEntry {
                block: BlockId(self.first.0 + p),
                coefs: &buf.coefs[3 * k..3 * k + 3],
            });
        }
        for (slot, c) in &buf.bodies {
            let body = &self.bodies[self.slots[*slot as usize].0];
            if let Some(block) = body.block() {
                entries.push(RowEntry { block, coefs: c });
            }
        }
        let s = self.settings;
        let (h, eps) = (self.h, self.eps);
        let c = rho / s.rest_density - phi;
        let surface = if marker || phi < 1.0 {
            SurfaceMode::Unilateral
        } else if s.surface == SurfaceMode::OneSided && c < 0.0 && -c <= s.surface_deficit {
            // a small deficit inside the liquid: hold the rate, do not pull it back
            SurfaceMode::Clamped
        } else {
            s.surface
        };
        let id = push_density_row(
            rows,
            entries,
            c,
            h,
            eps,
            known,
            surface,
            s.max_recovery_rate,
        );
        entries.clear();
        id
    }

    /// Push the unilateral rows of the markers in `bufs` (densities `rho`) that have
    /// fluid neighbours; `ids` gets `(marker index, row)` of each.
    pub(super) fn push_markers<'b>(
        &self,
        bufs: &'b mut [RowBuf],
        rho: &[f64],
        entries: &mut Vec<RowEntry<'b>>,
        rows: &mut ConstraintRows,
        ids: &mut Vec<(u32, RowId)>,
    ) {
        ids.clear();
        for (k, (buf, rho)) in bufs.iter_mut().zip(rho).enumerate() {
            if !buf.particles.is_empty() {
                let id = self.push(buf, *rho, 1.0, true, entries, rows);
                ids.push((k as u32, id));
            }
        }
    }
}

/// The 6 row coefficients `[lin; R' ang]` of a body whose world linear and angular parts
/// are `c` (angular velocity in the body frame).
fn body_coefs(body: &RigidBody, c: &[f64; 6]) -> [f64; 6] {
    let a = body.rotation().inverse() * Vector3::new(c[3], c[4], c[5]);
    [c[0], c[1], c[2], a.x, a.y, a.z]
}
