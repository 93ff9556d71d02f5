//! The target block: a structured hex mesh of the specimen under the selected impacts,
//! fine (spacing `h_fine`) in refined zones around each impact and near the surface,
//! growing by `growth` per element away from them up to `h_max`.

use super::{Mesh, structured_hexes};

/// Grid coordinates on `[lo, hi]`: spacing `h_fine` inside the `zones`, growing linearly
/// with the distance from the nearest zone (about geometric growth `growth` per cell),
/// capped at `h_max`.
///
/// The centre of every zone that overlaps no other (an impact with room around it) is the
/// middle of a cell of width `h_fine` whose two lines are anchored, and the lines between
/// two anchors (or an anchor and an end) are spread so that each cell spans the same
/// share of `dx / h(x)` (equidistribution). A block that is symmetric about a lone impact
/// is then meshed symmetrically about it, with the impact in the middle of an element's
/// top face. (Marching from `lo` and rescaling, as before session 47, put the impact
/// 0.06 mm off the middle of its element column, and a normal 70 m/s impact in CalculiX
/// rebounded with 1.3 m/s sideways; a node under the impact, meeting the shot's pole
/// node, gave 3.4 m/s.) Overlapping zones make one fine region, graded as a whole:
/// anchoring each of them would only add lines; a zone reaching an end of the axis (the
/// refined layer under the surface) is not anchored either. Anchors closer than
/// `h_fine / 2` to an end or to an anchor already kept are dropped, so that no cell is
/// much smaller than `h_fine`.
pub fn graded_axis(
    lo: f64,
    hi: f64,
    zones: &[(f64, f64)],
    h_fine: f64,
    growth: f64,
    h_max: f64,
) -> Vec<f64> {
    let mut sorted: Vec<(f64, f64)> = zones.to_vec();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    // The zones' union as sorted disjoint intervals: the distance to the nearest zone by
    // binary search (a selection can hold thousands of impacts).
    let mut union: Vec<(f64, f64)> = Vec::with_capacity(zones.len());
    for &(a, b) in &sorted {
        match union.last_mut() {
            Some(last) if a <= last.1 => last.1 = last.1.max(b),
            _ => union.push((a, b)),
        }
    }
    let dist = |x: f64| {
        let k = union.partition_point(|&(a, _)| a <= x);
        let before = k
            .checked_sub(1)
            .map_or(f64::INFINITY, |k| (x - union[k].1).max(0.0));
        let after = union.get(k).map_or(f64::INFINITY, |&(a, _)| a - x);
        before.min(after)
    };
    let spacing = |x: f64| (h_fine + (growth - 1.0) * dist(x)).min(h_max);
    // Anchors: the two lines of the middle cell of every zone that overlaps no other (an
    // impact with room around it). Overlapping zones are one fine region: anchoring each
    // would only add lines.
    let mut centres = Vec::new();
    let mut reach = f64::NEG_INFINITY;
    for (k, &(a, b)) in sorted.iter().enumerate() {
        // A zone reaching an end of the axis (the layer under the surface) is no impact.
        let alone =
            a > reach && sorted.get(k + 1).is_none_or(|next| next.0 > b) && a > lo && b < hi;
        reach = reach.max(b);
        let c = 0.5 * (a + b);
        if alone {
            centres.extend([c - 0.5 * h_fine, c + 0.5 * h_fine]);
        }
    }
    centres.retain(|&c| c > lo + 0.5 * h_fine && c < hi - 0.5 * h_fine);
    let mut anchors = vec![lo];
    for c in centres {
        if c - anchors[anchors.len() - 1] >= 0.5 * h_fine {
            anchors.push(c);
        }
    }
    if hi - anchors[anchors.len() - 1] < 0.5 * h_fine && anchors.len() > 1 {
        anchors.pop();
    }
    anchors.push(hi);
    // Each segment: the cumulative `dx / h` on an even sampling, inverted linearly. Two
    // segments that mirror each other are sampled alike, so a spacing symmetric about a
    // lone impact gives lines symmetric about it.
    let mut xs = vec![lo];
    for w in anchors.windows(2) {
        let (a, b) = (w[0], w[1]);
        // 64 samples per finest cell: the lines land within a 64th of a cell of the exact
        // equidistribution.
        let samples = ((64.0 * (b - a) / h_fine).ceil() as usize).max(64);
        let at = |k: usize| a + (b - a) * k as f64 / samples as f64;
        let mut cum = vec![0.0; samples + 1];
        for k in 0..samples {
            let (x0, x1) = (at(k), at(k + 1));
            cum[k + 1] = cum[k] + (x1 - x0) * 0.5 * (1.0 / spacing(x0) + 1.0 / spacing(x1));
        }
        let total = cum[samples];
        // Rounded up: no cell is wider than the spacing asks (within the sampling).
        let n = ((total - 1e-6).ceil() as usize).max(1);
        let mut k = 0;
        for m in 1..n {
            let target = total * m as f64 / n as f64;
            while cum[k + 1] < target {
                k += 1;
            }
            let f = (target - cum[k]) / (cum[k + 1] - cum[k]);
            xs.push(at(k) + f * (at(k + 1) - at(k)));
        }
        xs.push(b);
    }
    xs
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
    fn graded_axis_is_symmetric_about_a_lone_impact() {
        // One impact: in the middle of a cell, and the lines mirror each other about it.
        let xs = graded_axis(-1.0, 1.0, &[(-0.4, 0.4)], 0.1, 1.5, 0.4);
        assert!(xs.contains(&-0.05) && xs.contains(&0.05), "{xs:?}");
        let n = xs.len();
        for k in 0..n {
            assert!((xs[k] + xs[n - 1 - k]).abs() < 1e-9, "{xs:?}");
        }
        // Several impacts: the lone one's centre is a cell's middle; the two that overlap
        // make one fine region, not anchored. Cells stay near h_fine in the zones and
        // grow by at most about `growth` outside them.
        let zones = [(-0.9, -0.1), (0.05, 0.85), (0.07, 0.87)];
        let xs = graded_axis(-2.0, 3.0, &zones, 0.1, 1.5, 0.4);
        let has = |x: f64| xs.iter().any(|&l| (l - x).abs() < 1e-12);
        // A layer at the end (the z axis under the surface): no anchors.
        let zs = graded_axis(-1.0, 0.0, &[(-0.4, 0.0)], 0.1, 1.5, 0.4);
        assert!(
            !zs.iter()
                .any(|&z| (z + 0.25).abs() < 1e-12 || (z + 0.15).abs() < 1e-12),
            "{zs:?}"
        );
        assert!(has(-0.55) && has(-0.45), "{xs:?}");
        assert!(!has(0.4) && !has(0.5) && !has(0.42) && !has(0.52), "{xs:?}");
        for w in xs.windows(2).filter(|w| w[0] > 0.05 && w[1] < 0.87) {
            assert!(w[1] - w[0] > 0.09, "{xs:?}");
        }
        let h: Vec<f64> = xs.windows(2).map(|w| w[1] - w[0]).collect();
        assert!(h.iter().all(|&d| d > 0.05 && d < 0.4 + 1e-9), "{h:?}");
        for w in h.windows(2) {
            assert!(w[1] / w[0] < 1.7 && w[0] / w[1] < 1.7, "{h:?}");
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
