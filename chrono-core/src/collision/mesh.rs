//! Triangulation of our shapes for visualization ([`Shape::to_trimesh`]).

use crate::error::{Result, check_positive};
use crate::math::{Vector3, tangent_frame};
use crate::shape::{Shape, TriangleMesh};

/// See [`Shape::to_trimesh`].
pub(crate) fn triangulate(
    shape: &Shape,
    subdivisions: u32,
    half_space_size: f64,
) -> Result<TriangleMesh> {
    match shape {
        Shape::TriMesh { vertices, indices } => Ok((vertices.clone(), indices.clone())),
        Shape::HeightField {
            heights,
            nrows,
            ncols,
            scale,
        } => Ok(heightfield_mesh(heights, *nrows, *ncols, scale)),
        Shape::HalfSpace { normal } => {
            check_positive("half_space_size", half_space_size)?;
            let n = normal.normalize();
            let (u, w) = tangent_frame(&n);
            let a = 0.5 * half_space_size;
            let vertices = vec![-a * u - a * w, a * u - a * w, a * u + a * w, -a * u + a * w];
            Ok((vertices, vec![[0, 1, 2], [0, 2, 3]]))
        }
        _ => super::convert::parry_trimesh(shape, subdivisions.max(3)),
    }
}

/// Triangles of a height field in our Z-up layout (see [`Shape::HeightField`]).
fn heightfield_mesh(
    heights: &[f64],
    nrows: usize,
    ncols: usize,
    scale: &Vector3<f64>,
) -> TriangleMesh {
    let mut vertices = Vec::with_capacity(nrows * ncols);
    for i in 0..nrows {
        for j in 0..ncols {
            let x = scale.x * (j as f64 / (ncols - 1) as f64 - 0.5);
            let y = scale.y * (i as f64 / (nrows - 1) as f64 - 0.5);
            vertices.push(Vector3::new(x, y, scale.z * heights[i * ncols + j]));
        }
    }
    let mut indices = Vec::with_capacity(2 * (nrows - 1) * (ncols - 1));
    let id = |i: usize, j: usize| (i * ncols + j) as u32;
    for i in 0..nrows - 1 {
        for j in 0..ncols - 1 {
            // Counter-clockwise seen from +Z.
            indices.push([id(i, j), id(i, j + 1), id(i + 1, j + 1)]);
            indices.push([id(i, j), id(i + 1, j + 1), id(i + 1, j)]);
        }
    }
    (vertices, indices)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn normal(v: &[Vector3<f64>], t: [u32; 3]) -> Vector3<f64> {
        let [a, b, c] = t.map(|i| v[i as usize]);
        (b - a).cross(&(c - a))
    }

    #[test]
    fn heightfield_mesh_follows_the_documented_layout() {
        let heights = vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        let hf = Shape::HeightField {
            heights,
            nrows: 2,
            ncols: 3,
            scale: Vector3::new(4.0, 2.0, 0.5),
        };
        let (v, t) = hf.to_trimesh(8, 1.0).unwrap();
        assert_eq!((v.len(), t.len()), (6, 4));
        // Node (1, 2): last row (y = +1), last column (x = +2), height 5 * 0.5.
        assert!((v[5] - Vector3::new(2.0, 1.0, 2.5)).norm() < 1e-12);
        assert!(
            t.iter().all(|&t| normal(&v, t).z > 0.0),
            "triangles face +Z"
        );
    }

    #[test]
    fn halfspace_is_a_square_facing_its_normal() {
        let (v, t) = Shape::HalfSpace {
            normal: Vector3::new(0.0, 0.0, 3.0),
        }
        .to_trimesh(8, 20.0)
        .unwrap();
        assert!(t.iter().all(|&t| normal(&v, t).z > 0.0));
        assert!(
            v.iter().all(|p| p.z.abs() < 1e-12
                && p.x.abs() <= 10.0 + 1e-12
                && p.y.abs() <= 10.0 + 1e-12)
        );
        assert!(((v[0] - v[2]).norm() - 20.0 * 2f64.sqrt()).abs() < 1e-9);
        assert!(
            Shape::HalfSpace {
                normal: Vector3::z()
            }
            .to_trimesh(8, 0.0)
            .is_err()
        );
    }

    #[test]
    fn parry_shapes_are_closed_and_sized() {
        for (s, r) in [
            (Shape::Sphere { radius: 0.5 }, 0.5),
            (
                Shape::Box {
                    half_extents: Vector3::new(0.5, 0.5, 0.5),
                },
                0.75f64.sqrt(),
            ),
            (
                Shape::Capsule {
                    half_length: 0.5,
                    radius: 0.25,
                },
                0.75,
            ),
            (
                Shape::Cylinder {
                    half_length: 0.5,
                    radius: 0.5,
                },
                0.5f64.sqrt(),
            ),
        ] {
            let (v, t) = s.to_trimesh(16, 1.0).unwrap();
            let far = v.iter().map(|p| p.norm()).fold(0.0, f64::max);
            assert!((far - r).abs() < 1e-9, "{s:?}: {far}");
            // Closed, outward: the divergence theorem gives a positive volume near the true one.
            let vol: f64 = t
                .iter()
                .map(|&[a, b, c]| v[a as usize].dot(&v[b as usize].cross(&v[c as usize])) / 6.0)
                .sum();
            let exact = s.volume().unwrap();
            assert!(
                vol > 0.9 * exact && vol <= exact * (1.0 + 1e-9),
                "{s:?}: {vol} vs {exact}"
            );
        }
    }
}
