//! VTK XML PolyData (`.vtp`, ASCII) frames and `.pvd` collections for ParaView.
//!
//! - [`write_shapes_vtp`]: rigid shapes triangulated ([`Shape::to_trimesh`]) and placed at
//!   their world poses, one cell data array `body_id` (UInt32) per triangle. A half-space is
//!   drawn as a square of side [`ShapeMeshOptions::half_space_size`] (default 20 m)
//!   centered at its local origin.
//! - [`write_points_vtp`]: particles as vertex cells with named scalar and vector point data.
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

/// Write a ParaView collection: each `(time (s), file name)` is one frame; file names are
/// relative to the `.pvd` file's directory.
pub fn write_pvd(path: impl AsRef<Path>, frames: &[(f64, &str)]) -> Result<()> {
    let mut x = Xml::new("Collection");
    for (k, (t, file)) in frames.iter().enumerate() {
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
            "    <DataSet timestep=\"{time}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
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
    }
}
