//! VTK XML PolyData (`.vtp`, ASCII) frames and `.pvd` collections for ParaView.
//!
//! - [`write_shapes_vtp`]: rigid shapes triangulated ([`Shape::to_trimesh`]) and placed at
//!   their world poses, one cell data array `body_id` (UInt32) per triangle. A half-space is
//!   drawn as a square of side [`ShapeMeshOptions::half_space_size`] (default 20 m)
//!   centered at its local origin.
//! - [`write_points_vtp`]: particles as vertex cells with named scalar and vector point data.
//! - [`write_cells_vtu`]: an unstructured grid (`.vtu`) of one cell type (tetrahedra,
//!   quadrilaterals, line segments of a finite-element mesh ...) with named point and
//!   cell data.
//! - [`write_pvd`]: a collection of `(time, file)` so ParaView animates a series.
//!
//! Numbers are written at full precision; non-finite values are rejected (VTK readers
//! do not parse them), the error naming the array and index.

use std::path::Path;

use super::{fmt_f64, io_error};
use crate::error::{ChronoError, Result};
use crate::math::{Isometry3, Point3, Vector3};
use crate::shape::Shape;

/// How shapes are turned into triangles for [`write_shapes_vtp_with`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeMeshOptions {
    /// Angular subdivisions of spheres, capsules and cylinders (>= 3).
    pub subdivisions: u32,
    /// Side (m) of the square drawn for a half-space.
    pub half_space_size: f64,
}

impl Default for ShapeMeshOptions {
    fn default() -> Self {
        Self {
            subdivisions: 16,
            half_space_size: 20.0,
        }
    }
}

/// Write rigid shapes at their world poses, with the default [`ShapeMeshOptions`].
/// Each entry is `(world pose of the shape, shape, body id)`.
pub fn write_shapes_vtp(
    path: impl AsRef<Path>,
    shapes: &[(Isometry3<f64>, &Shape, u32)],
) -> Result<()> {
    write_shapes_vtp_with(path, shapes, &ShapeMeshOptions::default())
}

/// [`write_shapes_vtp`] with explicit meshing options.
pub fn write_shapes_vtp_with(
    path: impl AsRef<Path>,
    shapes: &[(Isometry3<f64>, &Shape, u32)],
    options: &ShapeMeshOptions,
) -> Result<()> {
    let mut points: Vec<Vector3<f64>> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut body_ids: Vec<u32> = Vec::new();
    for (k, (pose, shape, body)) in shapes.iter().enumerate() {
        shape.validate(&format!("shapes[{k}].shape"))?;
        let (v, t) = shape.to_trimesh(options.subdivisions, options.half_space_size)?;
        let base = u32::try_from(points.len())
            .map_err(|_| ChronoError::invalid("shapes", points.len(), "too many points"))?;
        points.extend(v.iter().map(|p| (pose * Point3::from(*p)).coords));
        triangles.extend(t.iter().map(|tri| tri.map(|i| i + base)));
        body_ids.extend(std::iter::repeat_n(*body, t.len()));
    }
    let mut x = Xml::new("PolyData");
    x.s.push_str(&format!(
        "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"{}\">\n",
        points.len(),
        triangles.len()
    ));
    x.points(&points)?;
    x.s.push_str("      <CellData Scalars=\"body_id\">\n");
    x.ints("UInt32", "body_id", body_ids.iter().map(|&b| b as u64));
    x.s.push_str("      </CellData>\n      <Polys>\n");
    x.ints(
        "Int64",
        "connectivity",
        triangles.iter().flatten().map(|&i| i as u64),
    );
    x.ints(
        "Int64",
        "offsets",
        (1..=triangles.len() as u64).map(|k| 3 * k),
    );
    x.s.push_str("      </Polys>\n    </Piece>\n");
    x.finish(path.as_ref())
}

/// Write particles as vertex cells with point data: `scalars` (one value per point) and
/// `vectors` (one 3-vector per point), each named.
pub fn write_points_vtp(
    path: impl AsRef<Path>,
    points: &[Vector3<f64>],
    scalars: &[(&str, &[f64])],
    vectors: &[(&str, &[Vector3<f64>])],
) -> Result<()> {
    let n = points.len();
    for (name, v) in scalars {
        if v.len() != n {
            return Err(ChronoError::invalid(
                format!("scalars[\"{name}\"].len()"),
                v.len(),
                format!("must equal the number of points ({n})"),
            ));
        }
    }
    for (name, v) in vectors {
        if v.len() != n {
            return Err(ChronoError::invalid(
                format!("vectors[\"{name}\"].len()"),
                v.len(),
                format!("must equal the number of points ({n})"),
            ));
        }
    }
    let mut x = Xml::new("PolyData");
    x.s.push_str(&format!(
        "    <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"{n}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n"
    ));
    x.points(points)?;
    x.s.push_str("      <PointData>\n");
    for (name, v) in scalars {
        x.floats(name, 1, v.iter().copied())?;
    }
    for (name, v) in vectors {
        x.floats(name, 3, v.iter().flat_map(|p| [p.x, p.y, p.z]))?;
    }
    x.s.push_str("      </PointData>\n      <Verts>\n");
    x.ints("Int64", "connectivity", 0..n as u64);
    x.ints("Int64", "offsets", 1..=n as u64);
    x.s.push_str("      </Verts>\n    </Piece>\n");
    x.finish(path.as_ref())
}

/// VTK cell type of a linear tetrahedron (`VTK_TETRA`).
pub const VTK_TETRA: u8 = 10;
/// VTK cell type of a triangle (`VTK_TRIANGLE`).
pub const VTK_TRIANGLE: u8 = 5;
/// VTK cell type of a straight line segment (`VTK_LINE`).
pub const VTK_LINE: u8 = 3;
/// VTK cell type of a bilinear quadrilateral (`VTK_QUAD`).
pub const VTK_QUAD: u8 = 9;

/// An unstructured grid of cells of one VTK type for [`write_cells_vtu`].
#[derive(Debug, Clone, Copy)]
pub struct CellGrid<'a> {
    /// Point positions, m.
    pub points: &'a [Vector3<f64>],
    /// VTK cell type ([`VTK_TETRA`], [`VTK_TRIANGLE`] ...).
    pub cell_type: u8,
    /// Points per cell (4 for a tetrahedron).
    pub nodes_per_cell: usize,
    /// Point indices, `nodes_per_cell` per cell.
    pub connectivity: &'a [usize],
    /// Named point scalars (one value per point).
    pub point_scalars: &'a [(&'a str, &'a [f64])],
    /// Named point vectors (one 3-vector per point).
    pub point_vectors: &'a [(&'a str, &'a [Vector3<f64>])],
    /// Named cell scalars (one value per cell).
    pub cell_scalars: &'a [(&'a str, &'a [f64])],
}

/// Write an unstructured grid (`.vtu`, ASCII): the cells of `grid` with its point and
/// cell data. Errors name the array: a connectivity length that is not a multiple of
/// `nodes_per_cell`, an index out of range, a data array of the wrong length, a
/// non-finite number.
pub fn write_cells_vtu(path: impl AsRef<Path>, grid: &CellGrid<'_>) -> Result<()> {
    let n = grid.points.len();
    let k = grid.nodes_per_cell;
    if k == 0 || !grid.connectivity.len().is_multiple_of(k) {
        return Err(ChronoError::invalid(
            "connectivity.len()",
            grid.connectivity.len(),
            format!("must be a multiple of nodes_per_cell ({k}, > 0)"),
        ));
    }
    let cells = grid.connectivity.len() / k;
    if let Some(i) = grid.connectivity.iter().position(|&c| c >= n) {
        return Err(ChronoError::invalid(
            format!("connectivity[{i}]"),
            grid.connectivity[i],
            format!("must be < the number of points ({n})"),
        ));
    }
    let check = |kind: &str, name: &str, len: usize, want: usize| {
        if len == want {
            Ok(())
        } else {
            Err(ChronoError::invalid(
                format!("{kind}[\"{name}\"].len()"),
                len,
                format!("must be {want}"),
            ))
        }
    };
    for (name, v) in grid.point_scalars {
        check("point_scalars", name, v.len(), n)?;
    }
    for (name, v) in grid.point_vectors {
        check("point_vectors", name, v.len(), n)?;
    }
    for (name, v) in grid.cell_scalars {
        check("cell_scalars", name, v.len(), cells)?;
    }
    let mut x = Xml::new("UnstructuredGrid");
    x.s.push_str(&format!(
        "    <Piece NumberOfPoints=\"{n}\" NumberOfCells=\"{cells}\">\n"
    ));
    x.points(grid.points)?;
    x.s.push_str("      <PointData>\n");
    for (name, v) in grid.point_scalars {
        x.floats(name, 1, v.iter().copied())?;
    }
    for (name, v) in grid.point_vectors {
        x.floats(name, 3, v.iter().flat_map(|p| [p.x, p.y, p.z]))?;
    }
    x.s.push_str("      </PointData>\n      <CellData>\n");
    for (name, v) in grid.cell_scalars {
        x.floats(name, 1, v.iter().copied())?;
    }
    x.s.push_str("      </CellData>\n      <Cells>\n");
    x.ints(
        "Int64",
        "connectivity",
        grid.connectivity.iter().map(|&i| i as u64),
    );
    x.ints("Int64", "offsets", (1..=cells as u64).map(|c| c * k as u64));
    x.ints(
        "UInt8",
        "types",
        std::iter::repeat_n(u64::from(grid.cell_type), cells),
    );
    x.s.push_str("      </Cells>\n    </Piece>\n");
    x.finish(path.as_ref())
}

/// Write a ParaView collection: each `(time (s), file name)` is one frame; file names are
/// relative to the `.pvd` file's directory.
pub fn write_pvd(path: impl AsRef<Path>, frames: &[(f64, &str)]) -> Result<()> {
    let parts: Vec<(f64, usize, &str)> = frames.iter().map(|&(t, f)| (t, 0, f)).collect();
    write_pvd_parts(path, &parts)
}

/// Write a ParaView collection of frames in parts: each `(time (s), part, file name)` is
/// one piece of a frame (a distributed run's rank files: ParaView shows the parts of a
/// time step together); file names are relative to the `.pvd` file's directory.
pub fn write_pvd_parts(path: impl AsRef<Path>, frames: &[(f64, usize, &str)]) -> Result<()> {
    let mut x = Xml::new("Collection");
    for (k, (t, part, file)) in frames.iter().enumerate() {
        if !t.is_finite() {
            return Err(ChronoError::invalid(
                format!("frames[{k}].time"),
                t,
                "must be finite",
            ));
        }
        let mut time = String::new();
        fmt_f64(*t, &mut time);
        x.s.push_str(&format!(
            "    <DataSet timestep=\"{time}\" group=\"\" part=\"{part}\" file=\"{}\"/>\n",
            escape(file)
        ));
    }
    x.finish(path.as_ref())
}

/// Escape text for an XML attribute.
fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A VTK XML document being built in memory.
struct Xml {
    s: String,
    kind: &'static str,
}

impl Xml {
    fn new(kind: &'static str) -> Self {
        let mut s = String::from("<?xml version=\"1.0\"?>\n");
        s.push_str(&format!(
            "<VTKFile type=\"{kind}\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <{kind}>\n"
        ));
        Self { s, kind }
    }

    fn points(&mut self, points: &[Vector3<f64>]) -> Result<()> {
        self.s.push_str("      <Points>\n");
        self.floats("Points", 3, points.iter().flat_map(|p| [p.x, p.y, p.z]))?;
        self.s.push_str("      </Points>\n");
        Ok(())
    }

    fn floats(
        &mut self,
        name: &str,
        components: usize,
        values: impl Iterator<Item = f64>,
    ) -> Result<()> {
        self.s.push_str(&format!(
            "        <DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{components}\" format=\"ascii\">\n",
            escape(name)
        ));
        for (k, v) in values.enumerate() {
            if !v.is_finite() {
                return Err(ChronoError::invalid(
                    format!("{name}[{}]", k / components),
                    v,
                    "must be finite",
                ));
            }
            self.s.push_str(if k % (3 * components.max(1)) == 0 {
                "          "
            } else {
                " "
            });
            fmt_f64(v, &mut self.s);
            if (k + 1) % (3 * components.max(1)) == 0 {
                self.s.push('\n');
            }
        }
        self.s.push_str("\n        </DataArray>\n");
        Ok(())
    }

    fn ints(&mut self, ty: &str, name: &str, values: impl Iterator<Item = u64>) {
        self.s.push_str(&format!(
            "        <DataArray type=\"{ty}\" Name=\"{name}\" format=\"ascii\">\n"
        ));
        for (k, v) in values.enumerate() {
            self.s
                .push_str(if k % 12 == 0 { "          " } else { " " });
            self.s.push_str(&v.to_string());
            if (k + 1) % 12 == 0 {
                self.s.push('\n');
            }
        }
        self.s.push_str("\n        </DataArray>\n");
    }

    fn finish(mut self, path: &Path) -> Result<()> {
        self.s
            .push_str(&format!("  </{}>\n</VTKFile>\n", self.kind));
        std::fs::write(path, self.s).map_err(|e| io_error(path, e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("chrono-core-vtk-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    /// The value of attribute `name` in the first element that has it.
    fn attr(text: &str, name: &str) -> usize {
        let key = format!(" {name}=\"");
        let start = text.find(&key).unwrap_or_else(|| panic!("no {name}")) + key.len();
        text[start..].split('"').next().unwrap().parse().unwrap()
    }

    /// The numbers of the data array `name`.
    fn array(text: &str, name: &str) -> Vec<f64> {
        let key = format!("Name=\"{name}\"");
        let at = text.find(&key).unwrap_or_else(|| panic!("no array {name}"));
        let body = &text[at..];
        let body = &body[body.find('>').unwrap() + 1..body.find("</DataArray>").unwrap()];
        body.split_whitespace()
            .map(|s| s.parse().unwrap())
            .collect()
    }

    #[test]
    fn shapes_file_has_consistent_counts() {
        let path = temp("shapes.vtp");
        let ball = Shape::Sphere { radius: 0.5 };
        let cube = Shape::Box {
            half_extents: Vector3::new(1.0, 2.0, 3.0),
        };
        let ground = Shape::HalfSpace {
            normal: Vector3::z(),
        };
        let pose = Isometry3::translation(0.0, 0.0, 10.0);
        write_shapes_vtp(
            &path,
            &[
                (pose, &ball, 3),
                (Isometry3::identity(), &cube, 4),
                (Isometry3::identity(), &ground, 0),
            ],
        )
        .unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.starts_with("<?xml") && text.trim_end().ends_with("</VTKFile>"));
        let (np, nc) = (attr(&text, "NumberOfPoints"), attr(&text, "NumberOfPolys"));
        let pts = array(&text, "Points");
        assert_eq!(pts.len(), 3 * np);
        assert!(pts.iter().all(|x| x.is_finite()));
        let ids = array(&text, "body_id");
        assert_eq!(ids.len(), nc);
        let conn = array(&text, "connectivity");
        assert_eq!(conn.len(), 3 * nc);
        assert!(conn.iter().all(|&i| (i as usize) < np));
        assert_eq!(
            array(&text, "offsets").last().copied(),
            Some(3.0 * nc as f64)
        );
        // The box has 12 triangles, the half-space 2; the sphere sits around z = 10.
        assert_eq!(ids.iter().filter(|&&b| b == 4.0).count(), 12);
        assert_eq!(ids.iter().filter(|&&b| b == 0.0).count(), 2);
        let max_z = pts.chunks(3).map(|p| p[2]).fold(f64::MIN, f64::max);
        assert!((max_z - 10.5).abs() < 1e-9, "{max_z}");
    }

    #[test]
    fn tetra_grid_file() {
        let path = temp("tets.vtu");
        let pts = vec![
            Vector3::zeros(),
            Vector3::x(),
            Vector3::y(),
            Vector3::z(),
            Vector3::new(1.0, 1.0, 1.0),
        ];
        let disp = vec![Vector3::new(0.0, 0.0, -0.1); 5];
        let grid = CellGrid {
            points: &pts,
            cell_type: VTK_TETRA,
            nodes_per_cell: 4,
            connectivity: &[0, 1, 2, 3, 1, 4, 2, 3],
            point_scalars: &[],
            point_vectors: &[("displacement", &disp)],
            cell_scalars: &[("von_mises", &[1.5, 2.5])],
        };
        write_cells_vtu(&path, &grid).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("type=\"UnstructuredGrid\""));
        assert_eq!(
            (attr(&text, "NumberOfPoints"), attr(&text, "NumberOfCells")),
            (5, 2)
        );
        assert_eq!(array(&text, "von_mises"), vec![1.5, 2.5]);
        assert_eq!(array(&text, "offsets"), vec![4.0, 8.0]);
        assert_eq!(array(&text, "types"), vec![10.0, 10.0]);
        assert_eq!(array(&text, "displacement").len(), 15);
        let bad = CellGrid {
            connectivity: &[0, 1, 2, 7],
            ..grid
        };
        let e = write_cells_vtu(&path, &bad).unwrap_err().to_string();
        assert!(e.contains("connectivity[3]") && e.contains('7'), "{e}");
        let bad = CellGrid {
            cell_scalars: &[("von_mises", &[1.0])],
            ..grid
        };
        let e = write_cells_vtu(&path, &bad).unwrap_err().to_string();
        assert!(e.contains("von_mises"), "{e}");
    }

    #[test]
    fn points_file_and_collection() {
        let path = temp("points.vtp");
        let pts = vec![Vector3::new(0.0, 0.0, 0.0), Vector3::new(1.0, 2.0, 3.0)];
        let rho = [1000.0, 1001.5];
        let vel = vec![Vector3::new(0.1, 0.0, 0.0), Vector3::new(0.0, -0.2, 0.0)];
        write_points_vtp(&path, &pts, &[("density", &rho)], &[("velocity", &vel)]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            (attr(&text, "NumberOfPoints"), attr(&text, "NumberOfVerts")),
            (2, 2)
        );
        assert_eq!(array(&text, "density"), rho.to_vec());
        assert_eq!(
            array(&text, "velocity"),
            vec![0.1, 0.0, 0.0, 0.0, -0.2, 0.0]
        );
        let e = write_points_vtp(&path, &pts, &[("density", &rho[..1])], &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("density") && e.contains('1'), "{e}");
        let e = write_points_vtp(&path, &pts, &[("p", &[0.0, f64::NAN])], &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains("p[1]") && e.contains("NaN"), "{e}");

        let pvd = temp("series.pvd");
        write_pvd(&pvd, &[(0.0, "f_0000.vtp"), (0.01, "f_0001.vtp")]).unwrap();
        let text = std::fs::read_to_string(&pvd).unwrap();
        assert_eq!(text.matches("<DataSet ").count(), 2);
        assert!(text.contains("timestep=\"0.01\"") && text.contains("file=\"f_0001.vtp\""));

        let pvd = temp("parts.pvd");
        write_pvd_parts(
            &pvd,
            &[(0.0, 0, "f_0000_r0.vtp"), (0.0, 1, "f_0000_r1.vtp")],
        )
        .unwrap();
        let text = std::fs::read_to_string(&pvd).unwrap();
        assert_eq!(text.matches("<DataSet ").count(), 2);
        assert!(text.contains("part=\"1\" file=\"f_0000_r1.vtp\""), "{text}");
        let e = write_pvd_parts(&pvd, &[(f64::NAN, 0, "a.vtp")])
            .unwrap_err()
            .to_string();
        assert!(e.contains("frames[0].time"), "{e}");
    }
}
