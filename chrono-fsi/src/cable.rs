//! BCE markers on ANCF cable/beam meshes (chrono-fea's gradient-deficient element, nodes
//! `[r, r_x]`): filled discs of markers over a round cross-section at the fluid spacing,
//! placed with the element's shape functions, and the fluid's marker forces put back on
//! the nodal coordinates with the same weights.
//!
//! # Placement
//!
//! Element `e` (reference length `l`) carries `n_s = max(1, round(l / dp))` stations at
//! `xi_j = (j + 1/2) / n_s`; each station a disc of rings of radius
//! `rho_k = a - (k + 1/2) dp` (down to the axis; a ring below `dp / 4` is one marker on the
//! axis) with `max(1, round(2 pi rho_k / dp))` markers, where `a = sqrt(A / pi)` is the
//! radius of the round section of the element's area `A`. The outer ring is `dp / 2`
//! inside the surface, as the markers of rigid bodies ([`crate::markers`]); the discs fill
//! the section so a free end is closed. In the reference configuration a marker sits at
//! `r0(xi) + d0`, `d0 = rho (cos theta n1 + sin theta n2)` with `(t0, n1, n2)` an
//! orthonormal frame on the reference tangent `t0 = r0_x / |r0_x|`.
//!
//! In the current configuration, with the Hermite shape functions `S_k(xi)` and their
//! derivatives `S'_k` (`chrono_fea::element::cable::hermite`) over the element
//! coordinates `e = [r_A, r_x,A, r_B, r_x,B]`:
//!
//! ```text
//! r = sum_k S_k e_k,   g = r_x = sum_k S'_k e_k,   t = g / |g|
//! x_m = r + d,         d = R(t0 -> t) d0
//! ```
//!
//! with `R(t0 -> t)` the smallest rotation taking `t0` to `t` (Rodrigues). The cable has
//! no twist coordinate, so a rotation about the axis is not seen; a rigid motion whose
//! rotation axis is normal to a straight beam moves the markers rigidly (test).
//!
//! # Velocities and loads (consistent virtual work)
//!
//! The marker velocity is the linearization of the placement: the centre line's velocity
//! plus the section's rotation rate `t x t_dot` (the twist-free part) acting on the
//! offset, `(t x t_dot) x d = - t (d . g_dot) / |g|` (as `d . t = 0`):
//!
//! ```text
//! v_m = J e_dot,   J_k = S_k I - (S'_k / |g|) t d^T            (3 x 3 per block k)
//! ```
//!
//! and a marker force `F` enters the nodal coordinates as `Q_k = J_k^T F =
//! S_k F - (S'_k / |g|) d (t . F)`: the virtual work `F . J e_dot = Q . e_dot` for every
//! nodal velocity (test, round-off). A rigid translation (`S'_k` sums to zero over the
//! position blocks, `S_k` to one) gets the whole marker force, so fluid plus mesh linear
//! momentum is conserved. Over a multibody step the nodes move with their velocity at the
//! step's start, `e(s) = e + (s - t) e_dot`, and the markers with `x_m + (s - t) v_m` (exact
//! for the centre line, first order in the section's rotation).

use std::f64::consts::PI;

use chrono_core::math::Vector3;
use chrono_fea::element::cable::hermite;
use chrono_fea::{CableMesh, NodeId};

use crate::builder::MIN_CELLS_ACROSS;
use crate::error::{FsiError, Result};

/// The BCE markers of one cable mesh (see the [module docs](self)): per marker its
/// element, station and reference offset, and the current offset, tangent and `1 / |g|`
/// of the last placement.
#[derive(Debug, Clone, Default)]
pub struct CableMarkers {
    element: Vec<u32>,
    xi: Vec<f64>,
    t0: Vec<Vector3<f64>>,
    d0: Vec<Vector3<f64>>,
    /// Current offset `d`, unit tangent `t` and `1 / |g|`.
    d: Vec<Vector3<f64>>,
    t: Vec<Vector3<f64>>,
    inv_g: Vec<f64>,
    /// Station of each marker along the reference centre line from node 0 of its
    /// element, m, and the element's reference length, m.
    station: Vec<f64>,
}

/// The radius of the round section of an element's material (`sqrt(A / pi)`), m.
pub fn section_radius(mesh: &CableMesh, element: usize) -> f64 {
    (mesh.elements()[element].material().area / PI).sqrt()
}

impl CableMarkers {
    /// Markers on every element of `mesh` at spacing `dp` (m), in its current
    /// configuration; `support` is the kernel support `2 h` (m), `name` names the mesh in
    /// errors. Errors (naming the element and the value): a section thinner than the
    /// kernel support or resolved by fewer than [`MIN_CELLS_ACROSS`] spacings, a mesh
    /// without elements, a degenerate reference slope.
    pub fn new(name: &str, mesh: &CableMesh, dp: f64, support: f64) -> Result<Self> {
        if mesh.elements().is_empty() {
            return Err(FsiError::invalid(
                format!("cable \"{name}\" elements"),
                0,
                "the mesh has no element",
            ));
        }
        let mut m = Self::default();
        for (e, el) in mesh.elements().iter().enumerate() {
            let a = section_radius(mesh, e);
            let what = || format!("cable \"{name}\" element {e}");
            if 2.0 * a < support {
                return Err(FsiError::BodyThinnerThanSupport {
                    body: what(),
                    shape: "round section (diameter sqrt(4 A / pi))".into(),
                    thickness: 2.0 * a,
                    support,
                });
            }
            if 2.0 * a < MIN_CELLS_ACROSS * dp {
                return Err(FsiError::Unresolved {
                    body: what(),
                    shape: "round section (diameter sqrt(4 A / pi))".into(),
                    thickness: 2.0 * a,
                    spacing: dp,
                    min_cells: MIN_CELLS_ACROSS,
                });
            }
            let l = el.length();
            let e0 = reference_coordinates(mesh, e);
            let n_s = ((l / dp).round() as usize).max(1);
            for j in 0..n_s {
                let xi = (j as f64 + 0.5) / n_s as f64;
                let (_, sx, _) = hermite(xi, l);
                let g0 = combine(&sx, &e0);
                let ng = g0.norm();
                if !(ng > 1e-12 && ng.is_finite()) {
                    return Err(FsiError::invalid(
                        format!("{} reference slope at xi = {xi}", what()),
                        ng,
                        "must be a finite non-zero vector",
                    ));
                }
                let t0 = g0 / ng;
                let (n1, n2) = normal_frame(&t0);
                let mut k = 0;
                loop {
                    let rho = a - (k as f64 + 0.5) * dp;
                    if rho <= 0.0 {
                        break;
                    }
                    let (rho, n) = if rho < 0.25 * dp {
                        (0.0, 1)
                    } else {
                        (rho, ((2.0 * PI * rho / dp).round() as usize).max(1))
                    };
                    for i in 0..n {
                        // rings staggered by half a marker so neighbouring rings interleave
                        let th = 2.0 * PI * (i as f64 + 0.5 * (k % 2) as f64) / n as f64;
                        m.element.push(e as u32);
                        m.xi.push(xi);
                        m.t0.push(t0);
                        m.d0.push(rho * (th.cos() * n1 + th.sin() * n2));
                        m.station.push(xi * l);
                    }
                    if rho == 0.0 {
                        break;
                    }
                    k += 1;
                }
            }
        }
        let n = m.len();
        m.d = m.d0.clone();
        m.t = m.t0.clone();
        m.inv_g = vec![1.0; n];
        Ok(m)
    }

    /// Number of markers.
    pub fn len(&self) -> usize {
        self.element.len()
    }

    /// Whether there is no marker.
    pub fn is_empty(&self) -> bool {
        self.element.is_empty()
    }

    /// Element of each marker.
    pub fn elements(&self) -> &[u32] {
        &self.element
    }

    /// Distance of each marker's station from node 0 of its element along the reference
    /// centre line, m.
    pub fn stations(&self) -> &[f64] {
        &self.station
    }

    /// The unit offset direction `d / |d|` (zero on the axis) and the unit tangent `t` of
    /// marker `i` at the last [`place`](Self::place).
    pub fn frame(&self, i: usize) -> (Vector3<f64>, Vector3<f64>) {
        let d = self.d[i];
        let n = d.norm();
        (if n > 0.0 { d / n } else { d }, self.t[i])
    }

    /// Places the markers for the nodal coordinates of `mesh` and the nodal velocities
    /// `vel(node) = (r_dot, r_x_dot)`: writes the positions (m) and velocities (m/s) into
    /// `x` and `v` (one entry per marker) and keeps the offsets, tangents and `1 / |g|`
    /// for [`nodal_loads`](Self::nodal_loads). Errors: a slope folded back against the
    /// reference tangent (the smallest rotation is undefined) or zero, naming the element.
    pub fn place(
        &mut self,
        name: &str,
        mesh: &CableMesh,
        vel: impl Fn(NodeId) -> (Vector3<f64>, Vector3<f64>),
        x: &mut [[f64; 3]],
        v: &mut [[f64; 3]],
    ) -> Result<()> {
        let els = mesh.elements();
        let nodes = mesh.nodes();
        for i in 0..self.len() {
            let e = self.element[i] as usize;
            let el = &els[e];
            let (a, b) = (&nodes[el.nodes[0]], &nodes[el.nodes[1]]);
            let coords = [a.position, a.slope, b.position, b.slope];
            let (va, vb) = (vel(NodeId(el.nodes[0])), vel(NodeId(el.nodes[1])));
            let rates = [va.0, va.1, vb.0, vb.1];
            let (s, sx, _) = hermite(self.xi[i], el.length());
            let (mut r, mut g, mut rd, mut gd) = (
                Vector3::zeros(),
                Vector3::zeros(),
                Vector3::zeros(),
                Vector3::zeros(),
            );
            for k in 0..4 {
                r += s[k] * coords[k];
                g += sx[k] * coords[k];
                rd += s[k] * rates[k];
                gd += sx[k] * rates[k];
            }
            let ng = g.norm();
            let t = g / ng;
            let t0 = self.t0[i];
            let c = t0.dot(&t);
            if !(ng > 0.0 && ng.is_finite() && c > -1.0 + 1e-9) {
                return Err(FsiError::invalid(
                    format!("cable \"{name}\" element {e} slope at xi = {}", self.xi[i]),
                    format!("{:?}", [g.x, g.y, g.z]),
                    "must be finite, non-zero and not folded back against the reference tangent",
                ));
            }
            // Rodrigues: the smallest rotation taking t0 to t, applied to d0
            let w = t0.cross(&t);
            let d0 = self.d0[i];
            let d = c * d0 + w.cross(&d0) + w * (w.dot(&d0) / (1.0 + c));
            let p = r + d;
            let vm = rd - t * (d.dot(&gd) / ng);
            x[i] = [p.x, p.y, p.z];
            v[i] = [vm.x, vm.y, vm.z];
            self.d[i] = d;
            self.t[i] = t;
            self.inv_g[i] = 1.0 / ng;
        }
        Ok(())
    }

    /// Adds the generalized nodal loads of the marker forces `f` (N, one per marker) to
    /// `q` (6 per node of `mesh`: N on the positions, N m on the slopes), `Q_k = J_k^T F`
    /// at the last [`place`](Self::place) (see the [module docs](self)). Summed in marker
    /// order (deterministic).
    pub fn nodal_loads(&self, mesh: &CableMesh, f: &[[f64; 3]], q: &mut [f64]) {
        let els = mesh.elements();
        for (i, fi) in f.iter().enumerate().take(self.len()) {
            let el = &els[self.element[i] as usize];
            let (s, sx, _) = hermite(self.xi[i], el.length());
            let fv = Vector3::new(fi[0], fi[1], fi[2]);
            let axial = self.t[i].dot(&fv) * self.inv_g[i];
            for k in 0..4 {
                let qk = s[k] * fv - (sx[k] * axial) * self.d[i];
                let g0 = 6 * el.nodes[k / 2] + 3 * (k % 2);
                for c in 0..3 {
                    q[g0 + c] += qk[c];
                }
            }
        }
    }
}

/// The element's coordinates `[r_A, r_x,A, r_B, r_x,B]` in the reference configuration.
fn reference_coordinates(mesh: &CableMesh, e: usize) -> [Vector3<f64>; 4] {
    let el = &mesh.elements()[e];
    let (a, b) = (&mesh.nodes()[el.nodes[0]], &mesh.nodes()[el.nodes[1]]);
    [
        a.reference_position,
        a.reference_slope,
        b.reference_position,
        b.reference_slope,
    ]
}

fn combine(w: &[f64; 4], e: &[Vector3<f64>; 4]) -> Vector3<f64> {
    (0..4).fold(Vector3::zeros(), |acc, k| acc + w[k] * e[k])
}

/// Two unit normals completing `t` to a right-handed frame `(t, n1, n2)`: `n1` from the
/// world axis least aligned with `t`.
fn normal_frame(t: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let i = (0..3)
        .min_by(|&a, &b| t[a].abs().total_cmp(&t[b].abs()))
        .unwrap_or(0);
    let axis = Vector3::ith(i, 1.0);
    let n1 = (axis - t * t.dot(&axis)).normalize();
    (n1, t.cross(&n1))
}

/// The number of elements at each node of `mesh` (1 at a free end).
pub fn node_uses(mesh: &CableMesh) -> Vec<u32> {
    let mut uses = vec![0u32; mesh.nodes().len()];
    for el in mesh.elements() {
        uses[el.nodes[0]] += 1;
        uses[el.nodes[1]] += 1;
    }
    uses
}

/// Signed distance (m, negative inside) of the world point `p` to the round beam of
/// `mesh` in its current configuration: the union over the elements of tubes of the
/// section radius around the centre line (sampled by `SAMPLES` chords per element),
/// closed flat at the free ends (nodes of one element). Used to carve the fluid.
/// `uses[n]` is the number of elements at node `n` ([`node_uses`]).
pub fn cable_distance(mesh: &CableMesh, uses: &[u32], p: &Vector3<f64>) -> f64 {
    const SAMPLES: usize = 8;
    let els = mesh.elements();
    let mut best = f64::INFINITY;
    for (e, el) in els.iter().enumerate() {
        let a = section_radius(mesh, e);
        let (na, nb) = (&mesh.nodes()[el.nodes[0]], &mesh.nodes()[el.nodes[1]]);
        let coords = [na.position, na.slope, nb.position, nb.slope];
        let at = |xi: f64| combine(&hermite(xi, el.length()).0, &coords);
        let mut r0 = at(0.0);
        for j in 0..SAMPLES {
            let r1 = at((j + 1) as f64 / SAMPLES as f64);
            let seg = r1 - r0;
            let len2 = seg.norm_squared().max(1e-300);
            let tau = (p - r0).dot(&seg) / len2;
            let free_start = j == 0 && uses[el.nodes[0]] == 1;
            let free_end = j + 1 == SAMPLES && uses[el.nodes[1]] == 1;
            let d = if (tau < 0.0 && free_start) || (tau > 1.0 && free_end) {
                // beyond a free end: the flat cap
                let len = len2.sqrt();
                let axial = if tau < 0.0 {
                    -tau * len
                } else {
                    (tau - 1.0) * len
                };
                let radial = ((p - r0) - seg * tau).norm() - a;
                if radial > 0.0 {
                    (radial * radial + axial * axial).sqrt()
                } else {
                    axial
                }
            } else {
                // the tube (inside, the distance to the mantle: enough for carving)
                (p - (r0 + seg * tau.clamp(0.0, 1.0))).norm() - a
            };
            best = best.min(d);
            r0 = r1;
        }
    }
    best
}
