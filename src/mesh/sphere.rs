//! A hex mesh of a ball: an `n x n x n` cube grid mapped onto the ball layer by layer
//! (the "spherified cube" map), which takes the cube's faces onto the sphere. Node sets `ALL`, `SURFACE`; element set `ALL`;
//! surface `SURFACE` (every outer face).

use super::{Mesh, structured_hexes};

/// The "spherified cube" map of `[-1, 1]^3` onto the unit ball:
/// `x' = x sqrt(1 - y^2/2 - z^2/2 + y^2 z^2/3)` and cyclic. It takes the cube's faces onto
/// the sphere. The worst elements sit at the cube's corners (scaled Jacobian 0.29 for
/// n = 4, 0.19 for n = 6): fine for rigid shots; a 7-block O-grid would do better for
/// elastic ones.
fn spherified(x: f64, y: f64, z: f64) -> [f64; 3] {
    let (x2, y2, z2) = (x * x, y * y, z * z);
    [
        x * (1.0 - y2 / 2.0 - z2 / 2.0 + y2 * z2 / 3.0).sqrt(),
        y * (1.0 - z2 / 2.0 - x2 / 2.0 + z2 * x2 / 3.0).sqrt(),
        z * (1.0 - x2 / 2.0 - y2 / 2.0 + x2 * y2 / 3.0).sqrt(),
    ]
}

/// Ball of `radius` at `centre` with `n` cells along each cube edge (n >= 2).
pub fn hex_sphere(centre: [f64; 3], radius: f64, n: usize) -> Mesh {
    let mut m = Mesh::default();
    let np = n + 1;
    let mut surface = Vec::new();
    for k in 0..np {
        for j in 0..np {
            for i in 0..np {
                let c = |t: usize| -1.0 + 2.0 * t as f64 / n as f64;
                let p = spherified(c(i), c(j), c(k));
                let id = m.add_node([
                    centre[0] + radius * p[0],
                    centre[1] + radius * p[1],
                    centre[2] + radius * p[2],
                ]);
                if i == 0 || j == 0 || k == 0 || i == n || j == n || k == n {
                    surface.push(id);
                }
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| (1 + i + np * (j + np * k)) as u32;
    let elements = structured_hexes(&mut m, (n, n, n), id);
    m.element_sets.insert("ALL".into(), elements);
    let mut faces = Vec::new();
    for side in ["XMIN", "XMAX", "YMIN", "YMAX", "ZMIN", "ZMAX"] {
        faces.extend(m.surfaces.remove(side).unwrap_or_default());
    }
    faces.sort();
    m.surfaces.insert("SURFACE".into(), faces);
    m.node_sets.insert("SURFACE".into(), surface);
    m.node_sets
        .insert("ALL".into(), (1..=m.nodes.len() as u32).collect());
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ball_volume_converges_and_elements_are_valid() {
        for n in [4, 6, 8] {
            let m = hex_sphere([0.0, 0.0, 0.0], 1.0, n);
            let v = m.volume(None);
            let exact = 4.0 / 3.0 * std::f64::consts::PI;
            // Straight-edged hexes under-fill the ball by O(1/n^2).
            assert!(
                v < exact && v > exact * (1.0 - 1.5 / (n * n) as f64),
                "n {n}: {v}"
            );
            assert!(
                m.min_scaled_jacobian() > 0.5 / n as f64 + 0.05,
                "n {n}: {}",
                m.min_scaled_jacobian()
            );
            assert_eq!(m.surfaces["SURFACE"].len(), 6 * n * n);
            for &node in &m.node_sets["SURFACE"] {
                let p = m.nodes[(node - 1) as usize];
                assert!(((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 1.0).abs() < 1e-12);
            }
        }
    }
}
