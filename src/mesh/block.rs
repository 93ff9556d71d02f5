//! The target block: a structured hex mesh of the specimen under the selected impacts,
//! fine (spacing `h_fine`) in refined zones around each impact and near the surface,
//! growing by `growth` per element away from them up to `h_max`.

use super::{Mesh, structured_hexes};

/// Grid coordinates on `[lo, hi]`: spacing `h_fine` inside the `zones`, growing linearly
/// with the distance from the nearest zone (about geometric growth `growth` per cell),
/// capped at `h_max`, rescaled to end exactly at `hi`.
pub fn graded_axis(
    lo: f64,
    hi: f64,
    zones: &[(f64, f64)],
    h_fine: f64,
    growth: f64,
    h_max: f64,
) -> Vec<f64> {
    let dist = |x: f64| {
        zones
            .iter()
            .map(|&(a, b)| {
                if x < a {
                    a - x
                } else if x > b {
                    x - b
                } else {
                    0.0
                }
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut xs = vec![lo];
    let mut x = lo;
    while x < hi - 1e-9 * (hi - lo) {
        let d = dist(x).min(dist((x + h_fine).min(hi)));
        let h = (h_fine + (growth - 1.0) * d).min(h_max);
        x += h;
        xs.push(x);
    }
    // Rescale so the last line lands on `hi` (the overshoot is at most one cell).
    let last = *xs.last().expect("BUG: non-empty axis");
    let n = xs.len();
    if n > 2 && (last - hi) > 0.5 * (last - xs[n - 2]) {
        xs.pop();
    }
    let last = *xs.last().expect("BUG: non-empty axis");
    let s = (hi - lo) / (last - lo);
    xs.iter().map(|&v| lo + (v - lo) * s).collect()
}

/// A hex block on the grid `xs x ys x zs`. Node sets `TOP`, `BOTTOM`, `SIDES`, `ALL`;
/// element set `ALL`; surfaces `TOP` (z max) and the other five sides.
pub fn graded_block(xs: &[f64], ys: &[f64], zs: &[f64]) -> Mesh {
    let mut m = Mesh::default();
    let (nx, ny, nz) = (xs.len(), ys.len(), zs.len());
    for &z in zs {
        for &y in ys {
            for &x in xs {
                m.add_node([x, y, z]);
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| (1 + i + nx * (j + ny * k)) as u32;
    let elements = structured_hexes(&mut m, (nx - 1, ny - 1, nz - 1), id);
    m.element_sets.insert("ALL".into(), elements);
    let mut top = Vec::new();
    let mut bottom = Vec::new();
    let mut sides = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                if k == nz - 1 {
                    top.push(id(i, j, k));
                }
                if k == 0 {
                    bottom.push(id(i, j, k));
                }
                if i == 0 || j == 0 || i == nx - 1 || j == ny - 1 {
                    sides.push(id(i, j, k));
                }
            }
        }
    }
    m.node_sets.insert("TOP".into(), top);
    m.node_sets.insert("BOTTOM".into(), bottom);
    m.node_sets.insert("SIDES".into(), sides);
    m.node_sets
        .insert("ALL".into(), (1..=m.nodes.len() as u32).collect());
    if let Some(top) = m.surfaces.remove("ZMAX") {
        m.surfaces.insert("TOP".into(), top);
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn graded_axis_is_fine_in_zones_and_monotone() {
        let xs = graded_axis(-2.0, 2.0, &[(-0.3, 0.3)], 0.05, 1.3, 0.5);
        assert_eq!(xs[0], -2.0);
        assert!((xs[xs.len() - 1] - 2.0).abs() < 1e-12);
        assert!(xs.windows(2).all(|w| w[1] > w[0]));
        for w in xs.windows(2) {
            let mid = 0.5 * (w[0] + w[1]);
            if mid.abs() < 0.25 {
                assert!(w[1] - w[0] < 0.06, "{w:?}");
            }
            assert!(w[1] - w[0] < 0.51);
        }
    }

    #[test]
    fn block_volume_sets_and_orientation() {
        let m = graded_block(&[0.0, 1.0, 3.0], &[0.0, 2.0], &[-1.0, -0.5, 0.0]);
        assert_eq!(m.elements.len(), 2 * 2);
        assert!((m.volume(None) - 3.0 * 2.0 * 1.0).abs() < 1e-12);
        assert!(m.min_scaled_jacobian() > 0.99);
        assert_eq!(m.node_sets["TOP"].len(), 6);
        assert_eq!(m.surfaces["TOP"].len(), 2);
        // Top faces point up: their nodes are all at z = 0.
        for f in &m.surfaces["TOP"] {
            assert!(
                m.face_nodes(*f)
                    .iter()
                    .all(|&n| m.nodes[(n - 1) as usize][2] == 0.0)
            );
        }
    }
}
