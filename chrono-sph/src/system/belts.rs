//! Moving-belt walls ([`crate::WallBelt`]): the belt velocity of each wall group.

use crate::carrier::NO_CARRIER;
use crate::data::{ParticleData, WALL};
use crate::error::{Result, SphError};
use crate::settings::SphSettings;

/// The velocity of a tank wall marker of group `g` (m/s): the wall motion's `v` plus the
/// group's belt velocity, if any ([`crate::WallBelt`]). Without belts `v` itself, so the
/// arithmetic of scenes without belts is unchanged.
#[inline(always)]
pub(crate) fn belt_velocity(belts: &[[f64; 3]], g: u16, v: [f64; 3]) -> [f64; 3] {
    match belts.get(g as usize) {
        Some(b) => [v[0] + b[0], v[1] + b[1], v[2] + b[2]],
        None => v,
    }
}

/// The belt velocity of each wall group, indexed by group (zero for groups without a
/// belt; empty without belts). Errors: a belt velocity with a component along the wall
/// normal of one of its group's markers (a belt moves along its own plane), naming the
/// group; a belt group without tank wall markers.
pub(super) fn belt_table(s: &SphSettings, d: &ParticleData) -> Result<Vec<[f64; 3]>> {
    let Some(top) = s.wall_belts.iter().map(|b| b.group).max() else {
        return Ok(Vec::new());
    };
    let mut t = vec![[0.0; 3]; top as usize + 1];
    for (k, b) in s.wall_belts.iter().enumerate() {
        t[b.group as usize] = b.velocity;
        let speed = b.velocity.iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut markers = 0;
        for i in 0..d.len() {
            if d.kind[i] != WALL || d.carrier[i] != NO_CARRIER || d.group[i] != b.group {
                continue;
            }
            markers += 1;
            let n = d.wall_normal[i];
            let vn = n[0] * b.velocity[0] + n[1] * b.velocity[1] + n[2] * b.velocity[2];
            if vn.abs() > 1e-12 * speed {
                return Err(SphError::invalid(
                    format!("settings.wall_belts[{k}].velocity"),
                    format!("{:?}", b.velocity),
                    format!(
                        "must be tangential to the walls of group {} (normal {n:?})",
                        b.group
                    ),
                ));
            }
        }
        if markers == 0 {
            return Err(SphError::invalid(
                format!("settings.wall_belts[{k}].group"),
                b.group,
                "no tank wall marker has this group",
            ));
        }
    }
    Ok(t)
}
