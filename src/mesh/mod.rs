//! Mesh model: nodes, elements, node sets, element sets and surfaces in one
//! serde-serialisable structure (the role meshio plays in Python). Every FE deck and VTK
//! writer reads a [`Mesh`]; no format builds its own. Ids are compact and 1-based:
//! node `k` of `nodes` has id `k + 1`, element `k` of `elements` has id `k + 1`.
//!
//! Builders: [`block::graded_block`] (the target, refined under the impacts) and
//! [`sphere::hex_sphere`] (a shot). [`Mesh::append`] merges meshes with renumbering.

pub mod block;
pub mod sphere;

use serde::Serialize;
use std::collections::BTreeMap;

/// Element kinds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ElementKind {
    /// 8-node hexahedron (Abaqus/CalculiX C3D8 node order).
    Hex8,
}

/// One element.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Element {
    /// Kind.
    pub kind: ElementKind,
    /// Node ids (1-based), C3D8 order: bottom face 1-2-3-4 counter-clockwise seen from
    /// outside below, top face 5-6-7-8 above them.
    pub nodes: [u32; 8],
}

/// Faces of a hex in Abaqus/CalculiX numbering (S1..S6), as positions in `nodes`,
/// ordered so the normal points out of the element.
pub const HEX_FACES: [[usize; 4]; 6] = [
    [0, 3, 2, 1],
    [4, 5, 6, 7],
    [0, 1, 5, 4],
    [1, 2, 6, 5],
    [2, 3, 7, 6],
    [3, 0, 4, 7],
];

/// An element face: element id (1-based) and face number 1..6 (`S1`..`S6`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, PartialOrd, Ord)]
pub struct Face {
    /// Element id.
    pub element: u32,
    /// Face number, 1..6.
    pub face: u8,
}

/// The mesh model.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Mesh {
    /// Node coordinates, in the unit the mesh was built in.
    pub nodes: Vec<[f64; 3]>,
    /// Elements.
    pub elements: Vec<Element>,
    /// Named node sets (node ids).
    pub node_sets: BTreeMap<String, Vec<u32>>,
    /// Named element sets (element ids).
    pub element_sets: BTreeMap<String, Vec<u32>>,
    /// Named surfaces (element faces).
    pub surfaces: BTreeMap<String, Vec<Face>>,
}

impl Mesh {
    /// Adds a node, returning its id.
    pub fn add_node(&mut self, p: [f64; 3]) -> u32 {
        self.nodes.push(p);
        self.nodes.len() as u32
    }

    /// Appends `other`, renumbering its ids after this mesh's and prefixing its set and
    /// surface names with `prefix`. Returns (node id offset, element id offset).
    pub fn append(&mut self, other: &Mesh, prefix: &str) -> (u32, u32) {
        let dn = self.nodes.len() as u32;
        let de = self.elements.len() as u32;
        self.nodes.extend_from_slice(&other.nodes);
        self.elements.extend(other.elements.iter().map(|e| Element {
            kind: e.kind,
            nodes: e.nodes.map(|n| n + dn),
        }));
        for (k, v) in &other.node_sets {
            self.node_sets
                .insert(format!("{prefix}{k}"), v.iter().map(|n| n + dn).collect());
        }
        for (k, v) in &other.element_sets {
            self.element_sets
                .insert(format!("{prefix}{k}"), v.iter().map(|e| e + de).collect());
        }
        for (k, v) in &other.surfaces {
            self.surfaces.insert(
                format!("{prefix}{k}"),
                v.iter()
                    .map(|f| Face {
                        element: f.element + de,
                        face: f.face,
                    })
                    .collect(),
            );
        }
        (dn, de)
    }

    /// Multiplies every coordinate by `factor` (unit conversion).
    pub fn scaled(&self, factor: f64) -> Mesh {
        let mut m = self.clone();
        for p in &mut m.nodes {
            *p = p.map(|c| c * factor);
        }
        m
    }

    /// Corner node ids of a face.
    pub fn face_nodes(&self, f: Face) -> [u32; 4] {
        let e = &self.elements[(f.element - 1) as usize];
        HEX_FACES[(f.face - 1) as usize].map(|k| e.nodes[k])
    }

    /// Smallest corner Jacobian determinant over all elements, relative to the
    /// element's mean edge length cubed (positive: every element is valid).
    pub fn min_scaled_jacobian(&self) -> f64 {
        let mut min = f64::INFINITY;
        for e in &self.elements {
            let p: Vec<[f64; 3]> = e
                .nodes
                .iter()
                .map(|&n| self.nodes[(n - 1) as usize])
                .collect();
            // For each corner: its three edge neighbours in C3D8 order.
            const NB: [[usize; 3]; 8] = [
                [1, 3, 4],
                [2, 0, 5],
                [3, 1, 6],
                [0, 2, 7],
                [7, 5, 0],
                [4, 6, 1],
                [5, 7, 2],
                [6, 4, 3],
            ];
            for (c, nb) in NB.iter().enumerate() {
                let d = |k: usize| {
                    let q = p[nb[k]];
                    [q[0] - p[c][0], q[1] - p[c][1], q[2] - p[c][2]]
                };
                let (a, b, w) = (d(0), d(1), d(2));
                let det = a[0] * (b[1] * w[2] - b[2] * w[1]) - a[1] * (b[0] * w[2] - b[2] * w[0])
                    + a[2] * (b[0] * w[1] - b[1] * w[0]);
                let len = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                let scale = len(a) * len(b) * len(w);
                min = min.min(det / scale);
            }
        }
        min
    }

    /// Total volume (sum of hex volumes by the divergence theorem on their faces).
    pub fn volume(&self, elset: Option<&str>) -> f64 {
        let ids: Vec<u32> = match elset {
            Some(name) => self.element_sets.get(name).cloned().unwrap_or_default(),
            None => (1..=self.elements.len() as u32).collect(),
        };
        let mut vol = 0.0;
        for id in ids {
            let e = &self.elements[(id - 1) as usize];
            for face in HEX_FACES {
                // Split each quad into two triangles; V = sum (1/6) a . (b x c).
                let q = face.map(|k| self.nodes[(e.nodes[k] - 1) as usize]);
                for (a, b, c) in [(q[0], q[1], q[2]), (q[0], q[2], q[3])] {
                    vol += (a[0] * (b[1] * c[2] - b[2] * c[1])
                        - a[1] * (b[0] * c[2] - b[2] * c[0])
                        + a[2] * (b[0] * c[1] - b[1] * c[0]))
                        / 6.0;
                }
            }
        }
        vol
    }
}

/// Adds the hexes of a structured grid of `nx x ny x nz` cells whose node `(i, j, k)` has
/// id `id(i, j, k)`, and returns the new element ids by cell with the boundary faces
/// (`x-`, `x+`, `y-`, `y+`, `z-`, `z+`) as surfaces of `mesh`.
pub(crate) fn structured_hexes(
    mesh: &mut Mesh,
    (nx, ny, nz): (usize, usize, usize),
    id: impl Fn(usize, usize, usize) -> u32,
) -> Vec<u32> {
    let mut ids = Vec::with_capacity(nx * ny * nz);
    let mut faces: BTreeMap<&str, Vec<Face>> = BTreeMap::new();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let nodes = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                mesh.elements.push(Element {
                    kind: ElementKind::Hex8,
                    nodes,
                });
                let e = mesh.elements.len() as u32;
                ids.push(e);
                let mut add = |name, face| {
                    faces
                        .entry(name)
                        .or_default()
                        .push(Face { element: e, face })
                };
                if k == 0 {
                    add("ZMIN", 1);
                }
                if k + 1 == nz {
                    add("ZMAX", 2);
                }
                if j == 0 {
                    add("YMIN", 3);
                }
                if i + 1 == nx {
                    add("XMAX", 4);
                }
                if j + 1 == ny {
                    add("YMAX", 5);
                }
                if i == 0 {
                    add("XMIN", 6);
                }
            }
        }
    }
    for (k, v) in faces {
        mesh.surfaces.insert(k.to_string(), v);
    }
    ids
}
