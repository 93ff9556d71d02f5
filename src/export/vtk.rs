//! ParaView views in VTK XML (ASCII, readable by ParaView and VTK-based tools):
//! * [`impacts_vtp`]: impacts as a point cloud with velocity vectors, speeds, times;
//! * [`snapshot_vtp`] + [`pvd`]: shot positions at regular times, a series ParaView
//!   plays as an animation (the paper's Figure 10);
//! * [`mesh_vtu`]: any [`Mesh`] (the FE model of a deck) as an unstructured grid.

use crate::mesh::{ElementKind, Mesh};
use crate::record::Impact;
use std::fmt::Write;

/// One point-data array.
pub enum PointArray<'a> {
    /// Scalars.
    Scalar(&'a str, Vec<f64>),
    /// 3-vectors.
    Vector(&'a str, Vec<[f64; 3]>),
}

fn data_array(s: &mut String, a: &PointArray<'_>) {
    match a {
        PointArray::Scalar(name, v) => {
            let _ = writeln!(
                s,
                r#"        <DataArray type="Float64" Name="{name}" format="ascii">"#
            );
            for x in v {
                let _ = write!(s, "{x} ");
            }
        }
        PointArray::Vector(name, v) => {
            let _ = writeln!(
                s,
                r#"        <DataArray type="Float64" Name="{name}" NumberOfComponents="3" format="ascii">"#
            );
            for p in v {
                let _ = write!(s, "{} {} {} ", p[0], p[1], p[2]);
            }
        }
    }
    let _ = writeln!(s, "\n        </DataArray>");
}

/// A point cloud as VTK XML PolyData (one vertex per point).
pub fn points_vtp(points: &[[f64; 3]], arrays: &[PointArray<'_>]) -> String {
    let n = points.len();
    let mut s = String::new();
    let _ = writeln!(s, r#"<?xml version="1.0"?>"#);
    let _ = writeln!(
        s,
        r#"<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian">"#
    );
    let _ = writeln!(s, "  <PolyData>");
    let _ = writeln!(
        s,
        r#"    <Piece NumberOfPoints="{n}" NumberOfVerts="{n}" NumberOfLines="0" NumberOfStrips="0" NumberOfPolys="0">"#
    );
    let _ = writeln!(s, "      <PointData>");
    for a in arrays {
        data_array(&mut s, a);
    }
    let _ = writeln!(s, "      </PointData>");
    let _ = writeln!(s, "      <Points>");
    data_array(&mut s, &PointArray::Vector("Points", points.to_vec()));
    let _ = writeln!(s, "      </Points>");
    let _ = writeln!(s, "      <Verts>");
    let _ = writeln!(
        s,
        r#"        <DataArray type="Int64" Name="connectivity" format="ascii">"#
    );
    for k in 0..n {
        let _ = write!(s, "{k} ");
    }
    let _ = writeln!(s, "\n        </DataArray>");
    let _ = writeln!(
        s,
        r#"        <DataArray type="Int64" Name="offsets" format="ascii">"#
    );
    for k in 1..=n {
        let _ = write!(s, "{k} ");
    }
    let _ = writeln!(s, "\n        </DataArray>");
    let _ = writeln!(s, "      </Verts>");
    let _ = writeln!(s, "    </Piece>");
    let _ = writeln!(s, "  </PolyData>");
    let _ = writeln!(s, "</VTKFile>");
    s
}

/// Impacts at their contact points, SI, with velocity, speeds, time, shot id, first-hit
/// flag and diameter as point data (glyph by `velocity`, colour by `speed`).
pub fn impacts_vtp(impacts: &[Impact]) -> String {
    let pts: Vec<[f64; 3]> = impacts.iter().map(|i| [i.x_m, i.y_m, i.z_m]).collect();
    let sc = |f: fn(&Impact) -> f64| impacts.iter().map(f).collect::<Vec<f64>>();
    points_vtp(
        &pts,
        &[
            PointArray::Vector(
                "velocity_m_s",
                impacts
                    .iter()
                    .map(|i| [i.vx_m_s, i.vy_m_s, i.vz_m_s])
                    .collect(),
            ),
            PointArray::Scalar("speed_m_s", sc(|i| i.speed_m_s)),
            PointArray::Scalar("normal_speed_m_s", sc(|i| i.normal_speed_m_s)),
            PointArray::Scalar("angle_deg", sc(|i| i.angle_deg)),
            PointArray::Scalar("time_s", sc(|i| i.time_s)),
            PointArray::Scalar("shot", sc(|i| i.shot as f64)),
            PointArray::Scalar("first_hit", sc(|i| i.first_hit as f64)),
            PointArray::Scalar("diameter_m", sc(|i| i.diameter_m)),
        ],
    )
}

/// One recorded shot position.
#[derive(Debug, Clone, PartialEq)]
pub struct SnapshotPoint {
    /// Shot id.
    pub shot: u32,
    /// Centre, m.
    pub position: [f64; 3],
    /// Velocity, m/s.
    pub velocity: [f64; 3],
    /// Diameter, m.
    pub diameter: f64,
}

/// Shots at one instant, as PolyData (glyph with spheres scaled by `diameter_m`).
pub fn snapshot_vtp(points: &[SnapshotPoint]) -> String {
    let pts: Vec<[f64; 3]> = points.iter().map(|p| p.position).collect();
    points_vtp(
        &pts,
        &[
            PointArray::Vector("velocity_m_s", points.iter().map(|p| p.velocity).collect()),
            PointArray::Scalar(
                "speed_m_s",
                points
                    .iter()
                    .map(|p| {
                        (p.velocity[0].powi(2) + p.velocity[1].powi(2) + p.velocity[2].powi(2))
                            .sqrt()
                    })
                    .collect(),
            ),
            PointArray::Scalar("shot", points.iter().map(|p| p.shot as f64).collect()),
            PointArray::Scalar("diameter_m", points.iter().map(|p| p.diameter).collect()),
        ],
    )
}

/// A ParaView collection (`.pvd`) of `(time, file)` entries.
pub fn pvd(entries: &[(f64, String)]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, r#"<?xml version="1.0"?>"#);
    let _ = writeln!(
        s,
        r#"<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">"#
    );
    let _ = writeln!(s, "  <Collection>");
    for (t, f) in entries {
        let _ = writeln!(
            s,
            r#"    <DataSet timestep="{t}" group="" part="0" file="{f}"/>"#
        );
    }
    let _ = writeln!(s, "  </Collection>");
    let _ = writeln!(s, "</VTKFile>");
    s
}

/// A mesh as VTK XML UnstructuredGrid, with the element sets given as a cell array
/// `part` (index into `parts`, -1 for cells in none).
pub fn mesh_vtu(mesh: &Mesh, parts: &[&str]) -> String {
    let mut part = vec![-1.0; mesh.elements.len()];
    for (k, name) in parts.iter().enumerate() {
        if let Some(ids) = mesh.element_sets.get(*name) {
            for &e in ids {
                part[(e - 1) as usize] = k as f64;
            }
        }
    }
    let mut s = String::new();
    let _ = writeln!(s, r#"<?xml version="1.0"?>"#);
    let _ = writeln!(
        s,
        r#"<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">"#
    );
    let _ = writeln!(s, "  <UnstructuredGrid>");
    let _ = writeln!(
        s,
        r#"    <Piece NumberOfPoints="{}" NumberOfCells="{}">"#,
        mesh.nodes.len(),
        mesh.elements.len()
    );
    let _ = writeln!(s, "      <CellData>");
    data_array(&mut s, &PointArray::Scalar("part", part));
    let _ = writeln!(s, "      </CellData>");
    let _ = writeln!(s, "      <Points>");
    data_array(&mut s, &PointArray::Vector("Points", mesh.nodes.clone()));
    let _ = writeln!(s, "      </Points>");
    let _ = writeln!(s, "      <Cells>");
    let _ = writeln!(
        s,
        r#"        <DataArray type="Int64" Name="connectivity" format="ascii">"#
    );
    for e in &mesh.elements {
        for n in e.nodes {
            let _ = write!(s, "{} ", n - 1);
        }
    }
    let _ = writeln!(s, "\n        </DataArray>");
    let _ = writeln!(
        s,
        r#"        <DataArray type="Int64" Name="offsets" format="ascii">"#
    );
    for k in 1..=mesh.elements.len() {
        let _ = write!(s, "{} ", 8 * k);
    }
    let _ = writeln!(s, "\n        </DataArray>");
    let _ = writeln!(
        s,
        r#"        <DataArray type="UInt8" Name="types" format="ascii">"#
    );
    for e in &mesh.elements {
        let code = match e.kind {
            ElementKind::Hex8 => 12, // VTK_HEXAHEDRON, same corner order as C3D8
        };
        let _ = write!(s, "{code} ");
    }
    let _ = writeln!(s, "\n        </DataArray>");
    let _ = writeln!(s, "      </Cells>");
    let _ = writeln!(s, "    </Piece>");
    let _ = writeln!(s, "  </UnstructuredGrid>");
    let _ = writeln!(s, "</VTKFile>");
    s
}
