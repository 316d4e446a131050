//! Nodes: ANCF position + gradient nodes (cables) and position nodes (solids).

use nalgebra::Vector3;

/// Index of a node in a [`CableMesh`](crate::mesh::CableMesh) or a
/// [`TetMesh`](crate::tet_mesh::TetMesh).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeId(pub usize);

/// An ANCF node with a position and one position gradient ("slope"): 6 coordinates
/// `e = [r, r_x]` with `r` the position (m) and `r_x = dr/dx` the derivative of the
/// position along the element's reference arc length `x` (dimensionless; unit length
/// and tangent to the centre line in the undeformed state). This is the node of the
/// gradient-deficient cable/beam element (Gerstmayr & Shabana 2006). The ANCF shell
/// (`element::shell`) uses the same node with the gradient along the thickness instead:
/// `slope` holds the transverse gradient (director) `r_z = dr/dz`, a unit normal to the
/// mid-surface in the undeformed state (Yamashita et al. 2015).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GradientNode {
    /// Current position `r`, m.
    pub position: Vector3<f64>,
    /// Current slope `r_x`, -.
    pub slope: Vector3<f64>,
    /// Position in the reference (stress-free) configuration, m.
    pub reference_position: Vector3<f64>,
    /// Slope in the reference configuration (unit tangent), -.
    pub reference_slope: Vector3<f64>,
    /// Which of the 6 coordinates `[r, r_x]` a support holds at their current value.
    pub fixed: [bool; 6],
    /// Applied nodal force, N (a dead load: constant direction).
    pub force: Vector3<f64>,
}

impl GradientNode {
    /// Number of coordinates of a node.
    pub const NDOF: usize = 6;

    /// A free, unloaded node at its reference configuration.
    pub fn new(position: Vector3<f64>, slope: Vector3<f64>) -> Self {
        Self {
            position,
            slope,
            reference_position: position,
            reference_slope: slope,
            fixed: [false; 6],
            force: Vector3::zeros(),
        }
    }

    /// Displacement from the reference position, m.
    pub fn displacement(&self) -> Vector3<f64> {
        self.position - self.reference_position
    }

    /// Whether coordinate `k` (0..3 position, 3..6 slope) is held fixed.
    pub fn is_fixed(&self, k: usize) -> bool {
        self.fixed[k]
    }
}

/// A node of a solid element: a position only (3 coordinates), the node of the
/// tetrahedron ([`Tet4`](crate::element::Tet4)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolidNode {
    /// Current position, m.
    pub position: Vector3<f64>,
    /// Position in the reference (stress-free) configuration, m.
    pub reference_position: Vector3<f64>,
    /// Which of the 3 coordinates a support holds at their current value.
    pub fixed: [bool; 3],
    /// Applied nodal force, N (a dead load: constant direction).
    pub force: Vector3<f64>,
}

impl SolidNode {
    /// Number of coordinates of a node.
    pub const NDOF: usize = 3;

    /// A free, unloaded node at its reference position.
    pub fn new(position: Vector3<f64>) -> Self {
        Self {
            position,
            reference_position: position,
            fixed: [false; 3],
            force: Vector3::zeros(),
        }
    }

    /// Displacement from the reference position, m.
    pub fn displacement(&self) -> Vector3<f64> {
        self.position - self.reference_position
    }
}

/// A node of the fully parameterized ANCF beam ([`AncfBeam`](crate::element::AncfBeam)):
/// 12 coordinates `[r, r_x, r_y, r_z]`, the position (m) and the three position
/// gradients (dimensionless): `r_x` along the centre line (unit tangent in the reference
/// configuration), `r_y`, `r_z` the cross-section axes (unit, orthogonal to the tangent
/// and to each other in the reference configuration).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamNode {
    /// Current position `r`, m.
    pub position: Vector3<f64>,
    /// Current gradients `[r_x, r_y, r_z]`.
    pub gradients: [Vector3<f64>; 3],
    /// Position in the reference (stress-free) configuration, m.
    pub reference_position: Vector3<f64>,
    /// Gradients in the reference configuration.
    pub reference_gradients: [Vector3<f64>; 3],
    /// Which of the 12 coordinates a support holds at their current value.
    pub fixed: [bool; 12],
    /// Applied nodal force, N (a dead load).
    pub force: Vector3<f64>,
    /// Applied generalized forces on the gradients `[r_x, r_y, r_z]`, N m (dead loads;
    /// a couple, see [`BeamMesh::set_torque`](crate::beam_mesh::BeamMesh::set_torque)).
    pub gradient_force: [Vector3<f64>; 3],
}

impl BeamNode {
    /// Number of coordinates of a node.
    pub const NDOF: usize = 12;

    /// A free, unloaded node at its reference configuration.
    pub fn new(position: Vector3<f64>, gradients: [Vector3<f64>; 3]) -> Self {
        Self {
            position,
            gradients,
            reference_position: position,
            reference_gradients: gradients,
            fixed: [false; 12],
            force: Vector3::zeros(),
            gradient_force: [Vector3::zeros(); 3],
        }
    }

    /// Displacement from the reference position, m.
    pub fn displacement(&self) -> Vector3<f64> {
        self.position - self.reference_position
    }

    /// The rotation angle (rad) of the cross-section about the reference tangent, from
    /// the current `r_y` projected on the reference section plane: the twist for small
    /// bending rotations.
    pub fn twist(&self) -> f64 {
        let [_, a0, b0] = self.reference_gradients;
        let a = self.gradients[1];
        a.dot(&b0).atan2(a.dot(&a0))
    }
}
