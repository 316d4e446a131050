//! A structured tetrahedral mesh of a box, with the node sets of its six faces.
//!
//! The box `[origin, origin + size]` is divided into `nx x ny x nz` equal hexahedral
//! cells; each cell is split into tetrahedra ([`HexSplit`]) so that neighbouring cells
//! share their face diagonals (a conforming mesh). Grid node `(i, j, k)`,
//! `0 <= i <= nx` ..., is node `i + (nx + 1) (j + (ny + 1) k)`.
//!
//! The generator returns plain positions and connectivity ([`BoxMesh`]) so that a caller
//! can move nodes (a distorted patch) before the elements take their reference shapes
//! in [`BoxMesh::into_mesh`].

use nalgebra::{Matrix3, Vector3};

use crate::error::{FeaError, Result, finite3, positive};
use crate::material::SolidMaterial;
use crate::node::NodeId;
use crate::tet_mesh::TetMesh;

/// How a hexahedral cell is split into tetrahedra.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum HexSplit {
    /// Six tetrahedra around the main diagonal `(0,0,0)-(1,1,1)` of every cell (Kuhn /
    /// Freudenthal split): all cells alike, conforming.
    #[default]
    Six,
    /// Five tetrahedra: four corner tetrahedra and a central one; the orientation
    /// alternates with the parity of `i + j + k` so that face diagonals match.
    Five,
}

/// The six faces of the box: node sets (grid nodes on the face, in grid order).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BoxFaces {
    /// Nodes on `x = origin.x`.
    pub x_min: Vec<NodeId>,
    /// Nodes on `x = origin.x + size.x`.
    pub x_max: Vec<NodeId>,
    /// Nodes on `y = origin.y`.
    pub y_min: Vec<NodeId>,
    /// Nodes on `y = origin.y + size.y`.
    pub y_max: Vec<NodeId>,
    /// Nodes on `z = origin.z`.
    pub z_min: Vec<NodeId>,
    /// Nodes on `z = origin.z + size.z`.
    pub z_max: Vec<NodeId>,
}

/// A structured box mesh before the elements are built (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct BoxMesh {
    /// Node positions (reference configuration), m. May be moved before
    /// [`into_mesh`](Self::into_mesh).
    pub positions: Vec<Vector3<f64>>,
    /// Tetrahedra as node indices (right-handed for the undistorted grid).
    pub tets: Vec<[usize; 4]>,
    /// Node sets of the six faces.
    pub faces: BoxFaces,
    /// Cells along x, y, z.
    pub divisions: [usize; 3],
}

/// Cell corner `(a, b, c)` (bits) as an index `a + 2 b + 4 c`.
const fn corner(a: usize, b: usize, c: usize) -> usize {
    a + 2 * b + 4 * c
}

/// The six Kuhn tetrahedra of the unit cube: paths from corner 0 to corner 7 adding one
/// axis at a time (each permutation of the axes).
const KUHN: [[usize; 4]; 6] = [
    [0, 1, 3, 7],
    [0, 1, 5, 7],
    [0, 2, 3, 7],
    [0, 2, 6, 7],
    [0, 4, 5, 7],
    [0, 4, 6, 7],
];

/// Five tetrahedra of the unit cube, even parity: the central tetrahedron on the even
/// corners `000, 110, 101, 011`, and each odd corner with its three neighbours.
const FIVE_EVEN: [[usize; 4]; 5] = [
    [
        corner(0, 0, 0),
        corner(1, 1, 0),
        corner(1, 0, 1),
        corner(0, 1, 1),
    ],
    [
        corner(1, 0, 0),
        corner(0, 0, 0),
        corner(1, 1, 0),
        corner(1, 0, 1),
    ],
    [
        corner(0, 1, 0),
        corner(0, 0, 0),
        corner(1, 1, 0),
        corner(0, 1, 1),
    ],
    [
        corner(0, 0, 1),
        corner(0, 0, 0),
        corner(1, 0, 1),
        corner(0, 1, 1),
    ],
    [
        corner(1, 1, 1),
        corner(1, 1, 0),
        corner(1, 0, 1),
        corner(0, 1, 1),
    ],
];

/// Odd parity: the roles of the even and odd corners exchanged.
const FIVE_ODD: [[usize; 4]; 5] = [
    [
        corner(1, 0, 0),
        corner(0, 1, 0),
        corner(0, 0, 1),
        corner(1, 1, 1),
    ],
    [
        corner(0, 0, 0),
        corner(1, 0, 0),
        corner(0, 1, 0),
        corner(0, 0, 1),
    ],
    [
        corner(1, 1, 0),
        corner(1, 0, 0),
        corner(0, 1, 0),
        corner(1, 1, 1),
    ],
    [
        corner(1, 0, 1),
        corner(1, 0, 0),
        corner(0, 0, 1),
        corner(1, 1, 1),
    ],
    [
        corner(0, 1, 1),
        corner(0, 1, 0),
        corner(0, 0, 1),
        corner(1, 1, 1),
    ],
];

impl BoxMesh {
    /// The box `[origin, origin + size]` (m, `size` > 0 componentwise) with
    /// `divisions = [nx, ny, nz]` cells (each >= 1), split by `split`. Errors name the
    /// field and value.
    pub fn new(
        origin: Vector3<f64>,
        size: Vector3<f64>,
        divisions: [usize; 3],
        split: HexSplit,
    ) -> Result<Self> {
        finite3("box.origin", &origin)?;
        for (i, axis) in ["x", "y", "z"].iter().enumerate() {
            positive(&format!("box.size.{axis}"), size[i])?;
            if divisions[i] == 0 {
                return Err(FeaError::invalid(
                    format!("box.divisions.{axis}"),
                    0,
                    "must be >= 1",
                ));
            }
        }
        let [nx, ny, nz] = divisions;
        let id = |i: usize, j: usize, k: usize| i + (nx + 1) * (j + (ny + 1) * k);
        let mut positions = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
        let mut faces = BoxFaces::default();
        for k in 0..=nz {
            for j in 0..=ny {
                for i in 0..=nx {
                    let frac = Vector3::new(
                        i as f64 / nx as f64,
                        j as f64 / ny as f64,
                        k as f64 / nz as f64,
                    );
                    positions.push(origin + size.component_mul(&frac));
                    let n = NodeId(id(i, j, k));
                    for (on, set) in [
                        (i == 0, &mut faces.x_min),
                        (i == nx, &mut faces.x_max),
                        (j == 0, &mut faces.y_min),
                        (j == ny, &mut faces.y_max),
                        (k == 0, &mut faces.z_min),
                        (k == nz, &mut faces.z_max),
                    ] {
                        if on {
                            set.push(n);
                        }
                    }
                }
            }
        }
        let per_cell = match split {
            HexSplit::Six => 6,
            HexSplit::Five => 5,
        };
        let mut tets = Vec::with_capacity(per_cell * nx * ny * nz);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let c: [usize; 8] =
                        std::array::from_fn(|b| id(i + (b & 1), j + ((b >> 1) & 1), k + (b >> 2)));
                    let pattern: &[[usize; 4]] = match split {
                        HexSplit::Six => &KUHN,
                        HexSplit::Five if (i + j + k) % 2 == 0 => &FIVE_EVEN,
                        HexSplit::Five => &FIVE_ODD,
                    };
                    for t in pattern {
                        let mut tet = t.map(|b| c[b]);
                        let x = tet.map(|n| positions[n]);
                        let d = Matrix3::from_columns(&[x[1] - x[0], x[2] - x[0], x[3] - x[0]]);
                        if d.determinant() < 0.0 {
                            tet.swap(2, 3);
                        }
                        tets.push(tet);
                    }
                }
            }
        }
        Ok(Self {
            positions,
            tets,
            faces,
            divisions,
        })
    }

    /// The grid node `(i, j, k)` (`i <= nx`, ...), `None` outside the grid.
    pub fn grid_node(&self, i: usize, j: usize, k: usize) -> Option<NodeId> {
        let [nx, ny, nz] = self.divisions;
        (i <= nx && j <= ny && k <= nz).then(|| NodeId(i + (nx + 1) * (j + (ny + 1) * k)))
    }

    /// Whether node `n` lies on a face of the box.
    pub fn is_boundary(&self, n: NodeId) -> bool {
        let [nx, ny, _] = self.divisions;
        let i = n.0 % (nx + 1);
        let j = (n.0 / (nx + 1)) % (ny + 1);
        let k = n.0 / ((nx + 1) * (ny + 1));
        i == 0 || j == 0 || k == 0 || i == nx || j == ny || k == self.divisions[2]
    }

    /// Build the [`TetMesh`]: nodes at [`positions`](Self::positions) (their reference
    /// positions), every tetrahedron with `material`. Errors: an element made degenerate
    /// or inverted by moved nodes (the error names the element and its volume).
    pub fn into_mesh(&self, material: SolidMaterial) -> Result<TetMesh> {
        let mut mesh = TetMesh::new();
        for p in &self.positions {
            mesh.add_node(*p)?;
        }
        for t in &self.tets {
            mesh.add_tet(t.map(NodeId), material)?;
        }
        Ok(mesh)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn material() -> SolidMaterial {
        SolidMaterial::new(1e6, 0.3, 1000.0, 0.0).unwrap()
    }

    #[test]
    fn both_splits_fill_the_box_conformingly() {
        for split in [HexSplit::Six, HexSplit::Five] {
            let size = Vector3::new(2.0, 0.5, 0.75);
            let b = BoxMesh::new(Vector3::new(1.0, -1.0, 0.0), size, [4, 3, 2], split).unwrap();
            let mesh = b.into_mesh(material()).unwrap();
            assert!((mesh.volume() - size.product()).abs() < 1e-13, "{split:?}");
            assert_eq!(b.faces.x_min.len(), 4 * 3);
            assert_eq!(b.faces.z_max.len(), 5 * 4);
            // Conforming: every interior triangle is shared by two elements, so the
            // boundary triangles of all nodes are the 2 per grid square of the surface.
            let all: Vec<NodeId> = (0..b.positions.len()).map(NodeId).collect();
            let surface = mesh.boundary_triangles(&all);
            assert_eq!(surface.len(), 2 * 2 * (4 * 3 + 3 * 2 + 4 * 2), "{split:?}");
            // Each face's triangles cover its area.
            let mut m = mesh.clone();
            let area = m.add_traction(&b.faces.x_max, Vector3::x()).unwrap();
            assert!((area - 0.5 * 0.75).abs() < 1e-14);
            let total: Vector3<f64> = m.nodes().iter().map(|n| n.force).sum();
            assert!((total - Vector3::x() * area).norm() < 1e-14);
            // Outward orientation of the boundary triangles.
            for t in m.boundary_triangles(&b.faces.x_max) {
                let x = t.map(|n| m.nodes()[n].reference_position);
                assert!((x[1] - x[0]).cross(&(x[2] - x[0])).x > 0.0);
            }
        }
    }

    #[test]
    fn grid_indexing_and_bad_input() {
        let b = BoxMesh::new(
            Vector3::zeros(),
            Vector3::repeat(1.0),
            [2, 2, 2],
            HexSplit::Six,
        )
        .unwrap();
        assert_eq!(b.grid_node(1, 1, 1), Some(NodeId(13)));
        assert!(!b.is_boundary(NodeId(13)));
        assert!(b.is_boundary(NodeId(12)));
        assert_eq!(b.grid_node(3, 0, 0), None);
        let e = BoxMesh::new(
            Vector3::zeros(),
            Vector3::new(1.0, -2.0, 1.0),
            [1, 1, 1],
            HexSplit::Six,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("box.size.y") && e.contains("-2"), "{e}");
        let e = BoxMesh::new(
            Vector3::zeros(),
            Vector3::repeat(1.0),
            [1, 0, 1],
            HexSplit::Five,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("box.divisions.y"), "{e}");
        // A node pushed through a face inverts an element: the error names it.
        let mut b = b;
        b.positions[13] = Vector3::new(1.0, 1.0, 2.5);
        let e = b.into_mesh(material()).unwrap_err().to_string();
        assert!(e.contains("element") && e.contains("volume"), "{e}");
    }
}
