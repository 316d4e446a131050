//! A height field over a regular grid, bilinear between the nodes.

use std::path::Path;

use chrono_core::math::{Isometry3, Vector3};
use chrono_core::{BodyHandle, ContactMaterial, RigidBodyBuilder, Shape, System};

use super::Terrain;
use crate::error::{Result, VehicleError, check_finite, check_non_negative, check_positive};

/// Terrain heights on a regular grid of `nx` by `ny` nodes.
///
/// Node `(i, j)` (`i` in `0..nx` along X, `j` in `0..ny` along Y) is at
/// `(x0 + i dx, y0 + j dy)` with height `heights[j * nx + i]` (m). Between nodes the
/// height is bilinear: with `u = (x - x0)/dx - i` and `v = (y - y0)/dy - j` in `[0, 1]`,
///
/// ```text
/// h(x, y) = (1-u)(1-v) h_ij + u (1-v) h_(i+1)j + (1-u) v h_i(j+1) + u v h_(i+1)(j+1)
/// ```
///
/// and the normal is `(-dh/dx, -dh/dy, 1)` normalized, from the same bilinear patch.
/// Outside the grid the position is clamped to its edge (the terrain continues flat at
/// the edge heights).
///
/// The collider made by [`Terrain::add_to_system`] is a [`Shape::HeightField`] over the
/// same nodes, which splits each cell into two triangles: inside a cell whose four nodes
/// are not coplanar the collider and the bilinear surface differ by at most a quarter of
/// the cell's twist `|h_00 - h_10 - h_01 + h_11|`.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightmapTerrain {
    origin: [f64; 2],
    spacing: [f64; 2],
    nx: usize,
    ny: usize,
    heights: Vec<f64>,
    friction: f64,
}

impl HeightmapTerrain {
    /// A grid of `nx * ny` heights laid out as in the type docs (`heights[j * nx + i]`),
    /// its first node at `origin` (m), node spacing `spacing = [dx, dy]` (m).
    ///
    /// Errors name the field: `heightmap.nx`/`ny` below 2, `heightmap.heights.len()` not
    /// `nx * ny`, a non-finite `heightmap.heights[k]`, non-positive spacing, non-finite
    /// origin, negative friction.
    pub fn new(
        nx: usize,
        ny: usize,
        origin: [f64; 2],
        spacing: [f64; 2],
        heights: Vec<f64>,
        friction: f64,
    ) -> Result<Self> {
        if nx < 2 {
            return Err(VehicleError::invalid("heightmap.nx", nx, "must be >= 2"));
        }
        if ny < 2 {
            return Err(VehicleError::invalid("heightmap.ny", ny, "must be >= 2"));
        }
        if heights.len() != nx * ny {
            return Err(VehicleError::invalid(
                "heightmap.heights.len()",
                heights.len(),
                format!("must be nx * ny = {nx} * {ny} = {}", nx * ny),
            ));
        }
        if let Some(k) = heights.iter().position(|h| !h.is_finite()) {
            return Err(VehicleError::invalid(
                format!("heightmap.heights[{k}]"),
                heights[k],
                "must be finite",
            ));
        }
        check_finite("heightmap.origin.x", origin[0])?;
        check_finite("heightmap.origin.y", origin[1])?;
        check_positive("heightmap.spacing.x", spacing[0])?;
        check_positive("heightmap.spacing.y", spacing[1])?;
        check_non_negative("heightmap.friction", friction)?;
        Ok(Self {
            origin,
            spacing,
            nx,
            ny,
            heights,
            friction,
        })
    }

    /// A grid sampled from `f(x, y)` at the nodes.
    pub fn from_fn(
        nx: usize,
        ny: usize,
        origin: [f64; 2],
        spacing: [f64; 2],
        friction: f64,
        f: impl Fn(f64, f64) -> f64,
    ) -> Result<Self> {
        let mut heights = Vec::with_capacity(nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                heights.push(f(
                    origin[0] + i as f64 * spacing[0],
                    origin[1] + j as f64 * spacing[1],
                ));
            }
        }
        Self::new(nx, ny, origin, spacing, heights, friction)
    }

    /// Read a grid from a text file (see [`parse`](Self::parse)).
    pub fn from_file(
        path: impl AsRef<Path>,
        origin: [f64; 2],
        spacing: [f64; 2],
        friction: f64,
    ) -> Result<Self> {
        let path = path.as_ref();
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| VehicleError::Data {
            path: name.clone(),
            message: e.to_string(),
        })?;
        Self::parse(&text, &name, origin, spacing, friction)
    }

    /// Parse a grid from text: one grid row per line (row `j` = `j`-th data line, at
    /// `y = y0 + j dy`), heights separated by commas, semicolons or white space (so CSV
    /// and plain grids both work); empty lines and lines starting with `#` are skipped.
    /// Every row must have as many values as the first. `name` names the source in
    /// errors, which give the line (1-based) and column of a bad value.
    pub fn parse(
        text: &str,
        name: &str,
        origin: [f64; 2],
        spacing: [f64; 2],
        friction: f64,
    ) -> Result<Self> {
        let err = |message: String| VehicleError::Data {
            path: name.to_string(),
            message,
        };
        let mut heights = Vec::new();
        let (mut nx, mut ny) = (0usize, 0usize);
        for (ln, line) in text.lines().enumerate() {
            let t = line.trim();
            if t.is_empty() || t.starts_with('#') {
                continue;
            }
            let mut count = 0;
            for (col, tok) in t
                .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
                .filter(|s| !s.is_empty())
                .enumerate()
            {
                let v: f64 = tok.parse().map_err(|_| {
                    err(format!(
                        "line {}, column {}: cannot read {tok:?} as a height (m)",
                        ln + 1,
                        col + 1
                    ))
                })?;
                if !v.is_finite() {
                    return Err(err(format!(
                        "line {}, column {}: height {v} is not finite",
                        ln + 1,
                        col + 1
                    )));
                }
                heights.push(v);
                count += 1;
            }
            if ny == 0 {
                nx = count;
            } else if count != nx {
                return Err(err(format!(
                    "line {}: {count} heights, but the first row has {nx}",
                    ln + 1
                )));
            }
            ny += 1;
        }
        if ny < 2 || nx < 2 {
            return Err(err(format!(
                "a height grid needs at least 2 rows and 2 columns, found {ny} rows of {nx}"
            )));
        }
        Self::new(nx, ny, origin, spacing, heights, friction)
    }

    /// Number of nodes along X and along Y.
    pub fn size(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// The heights, `heights[j * nx + i]`, m.
    pub fn heights(&self) -> &[f64] {
        &self.heights
    }

    /// Cell index, local coordinate in the cell, and whether the coordinate was inside the
    /// grid range (else the slope along it is 0), for one axis.
    #[inline]
    fn locate(p: f64, p0: f64, d: f64, n: usize) -> (usize, f64, bool) {
        let u = (p - p0) / d;
        let max = (n - 1) as f64;
        let inside = (0.0..=max).contains(&u);
        let u = if u.is_nan() { 0.0 } else { u.clamp(0.0, max) };
        let i = (u.floor() as usize).min(n - 2);
        (i, u - i as f64, inside)
    }

    /// Height and gradient `(h, dh/dx, dh/dy)` at `(x, y)`.
    pub fn height_and_gradient(&self, x: f64, y: f64) -> (f64, f64, f64) {
        let (i, u, in_x) = Self::locate(x, self.origin[0], self.spacing[0], self.nx);
        let (j, v, in_y) = Self::locate(y, self.origin[1], self.spacing[1], self.ny);
        let at = |i: usize, j: usize| self.heights[j * self.nx + i];
        let (h00, h10, h01, h11) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
        let h =
            (1.0 - u) * (1.0 - v) * h00 + u * (1.0 - v) * h10 + (1.0 - u) * v * h01 + u * v * h11;
        let hx = if in_x {
            ((1.0 - v) * (h10 - h00) + v * (h11 - h01)) / self.spacing[0]
        } else {
            0.0
        };
        let hy = if in_y {
            ((1.0 - u) * (h01 - h00) + u * (h11 - h10)) / self.spacing[1]
        } else {
            0.0
        };
        (h, hx, hy)
    }
}

impl Terrain for HeightmapTerrain {
    fn height(&self, x: f64, y: f64) -> f64 {
        self.height_and_gradient(x, y).0
    }

    fn normal(&self, x: f64, y: f64) -> Vector3<f64> {
        let (_, hx, hy) = self.height_and_gradient(x, y);
        Vector3::new(-hx, -hy, 1.0).normalize()
    }

    fn friction(&self, _x: f64, _y: f64) -> f64 {
        self.friction
    }

    /// A fixed body at the grid's center with a [`Shape::HeightField`] of the same nodes
    /// (height scale 1, so the collider's heights are the terrain's).
    fn add_to_system(&self, sys: &mut System, material: ContactMaterial) -> Result<BodyHandle> {
        let (lx, ly) = (
            (self.nx - 1) as f64 * self.spacing[0],
            (self.ny - 1) as f64 * self.spacing[1],
        );
        let center = Vector3::new(self.origin[0] + 0.5 * lx, self.origin[1] + 0.5 * ly, 0.0);
        let shape = Shape::HeightField {
            heights: self.heights.clone(),
            nrows: self.ny,
            ncols: self.nx,
            scale: Vector3::new(lx, ly, 1.0),
        };
        let b = RigidBodyBuilder::fixed()
            .name("heightmap terrain")
            .position(center)
            .collider(shape, Isometry3::identity(), material);
        Ok(sys.add_body(b)?)
    }
}
