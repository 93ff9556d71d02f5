//! `peenflow run` draws impacts.png / impacts.svg: where the shots hit, coloured by
//! normal impact speed, and the histograms of normal speed and impact angle;
//! `peenflow export` draws selection.png / selection.svg: the selected impacts over all.

use crate::common;
use common::*;
use std::fs;

/// `(cx, fill)` of the SVG's circles of radius `r` (the map's points; legend markers
/// have radius 4).
fn circles(svg: &str, r: &str) -> Vec<(f64, String)> {
    svg.split("<circle ")
        .skip(1)
        .filter(|c| c.contains(&format!("r=\"{r}\"")))
        .map(|c| {
            let attr = |name: &str| {
                let i = c.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
                c[i..].split('"').next().unwrap().to_string()
            };
            (attr("cx").parse().unwrap(), attr("fill"))
        })
        .collect()
}

#[test]
fn a_run_draws_where_and_how_fast_the_shots_hit() {
    let tmp = tempfile::tempdir().unwrap();
    // Four shots dropped in vacuum at 10, 20, 30 and 40 m/s; the last one drifts 10 m/s
    // along x, so it touches 0.15 mm further than where it started.
    let mut scene = String::from(
        "title = \"four drops\"\nduration_ms = 0.2\n[shots]\ndiameter_mm = 0.8\n\
         [shots.feed]\ntype = \"list\"\n",
    );
    for (x, vx, vz) in [
        (-3.0, 0.0, 10.0),
        (-1.0, 0.0, 20.0),
        (1.0, 0.0, 30.0),
        (3.0, 10.0, 40.0),
    ] {
        scene += &format!(
            "[[shots.feed.shots]]\nposition_mm = [{x}, 0.0, 1.0]\nvelocity_m_s = [{vx}, 0.0, -{vz}]\n"
        );
    }
    scene += "[effects]\ndrag = false\nlateral_force = false\ngravity = false\n\
              shot_shot_contact = false\nnozzle_wall_contact = false\n";
    fs::write(tmp.path().join("four.toml"), scene).unwrap();
    let o = peenflow(&["run", "four.toml", "--out", "out"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("impacts.png, impacts.svg"));
    let dir = tmp.path().join("out");

    // A PNG of 1400 x 760 pixels, and no temporary file left behind.
    let png = fs::read(dir.join("impacts.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let be = |k: usize| u32::from_be_bytes(png[k..k + 4].try_into().unwrap());
    assert_eq!((be(16), be(20)), (1400, 760));
    let names: Vec<String> = fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");

    // The title's counts are summary.json's.
    let svg = fs::read_to_string(dir.join("impacts.svg")).unwrap();
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let title = format!(
        "four drops: {} impacts ({} first hits, {} rebound hits)",
        summary["impacts"], summary["first_hits"], summary["rebound_hits"]
    );
    assert!(svg.contains(&title), "{title}");
    assert_eq!(summary["impacts"], 4);

    // One point per impact, drawn slowest first, so in order of x here; placed linearly
    // in the contact points' x (impacts.csv) to within a pixel; the fastest in the top
    // colour of the scale (viridis' yellow), the others darker.
    let points = circles(&svg, "3");
    assert_eq!(points.len(), 4, "{points:?}");
    let mut rdr = csv::Reader::from_path(dir.join("impacts.csv")).unwrap();
    let header = rdr.headers().unwrap().clone();
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    let mut hits: Vec<(f64, f64)> = rdr
        .records()
        .map(|r| {
            let r = r.unwrap();
            (
                r[col("normal_speed_m_s")].parse().unwrap(),
                r[col("x_m")].parse().unwrap(),
            )
        })
        .collect();
    hits.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert!((hits[3].1 - 3.15e-3).abs() < 1e-6, "{hits:?}");
    let scale = (points[3].0 - points[0].0) / (hits[3].1 - hits[0].1);
    for (p, h) in points.iter().zip(&hits) {
        let want = points[0].0 + scale * (h.1 - hits[0].1);
        assert!((p.0 - want).abs() <= 1.0, "{p:?} against {want}");
    }
    assert_eq!(points[3].1, "#FEE825");
    assert!(points[..3].iter().all(|p| p.1 != "#FEE825"));
    // No rebound hits: no ring in the legend, no rebound bars.
    for label in ["\nrebound hit\n", "\nrebound hits\n"] {
        assert!(!svg.contains(label), "a legend entry for no rebound hits");
    }
    assert!(svg.contains("\nfirst hit\n") && svg.contains("\nfirst hits\n"));
}

#[test]
fn an_export_draws_its_selection_against_every_impact() {
    let tmp = tempfile::tempdir().unwrap();
    let t = tmp.path();
    let o = peenflow(&["run", "--out", "run", "-q"], t);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(t.join("run/summary.json")).unwrap()).unwrap();
    let all = summary["impacts"].as_u64().unwrap();
    // (outline colour, legend) of the --window and of the FE target block.
    let (window, block) = ("#FF7F0E", "#9467BD");
    let outlines = |svg: &str, colour: &str| {
        svg.matches(&format!(
            "<polyline fill=\"none\" opacity=\"1\" stroke=\"{colour}\""
        ))
        .count()
    };
    for (out, formats, with_block) in [("csv", "csv", false), ("deck", "csv,calculix", true)] {
        let o = peenflow(
            &[
                "export",
                "run/impacts.h5",
                "-f",
                formats,
                "--window",
                "-3,-3,3,3",
                "--target-material",
                "A5052",
                "-o",
                out,
            ],
            t,
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(stdout.contains("selection.png") && stdout.contains("selection.svg"));
        let dir = t.join(out);
        let selected = fs::read_to_string(dir.join("selected_impacts.csv"))
            .unwrap()
            .lines()
            .count()
            - 1;
        assert!(
            selected > 5 && (selected as u64) < all,
            "{selected} of {all}"
        );
        let svg = fs::read_to_string(dir.join("selection.svg")).unwrap();
        assert!(svg.contains(&format!(": {selected} of {all} impacts selected")));
        // Every selected impact in colour (the frame holds the window), every impact of
        // the run in grey behind them where the frame reaches.
        let coloured = circles(&svg, "3");
        assert_eq!(coloured.len(), selected);
        assert!(coloured.iter().all(|c| c.1 != "#000000"));
        let grey = circles(&svg, "2");
        assert!(
            grey.len() >= selected && grey.len() as u64 <= all + 1,
            "{}",
            grey.len()
        );
        // The window's outline (and its legend line); the target block's only with a deck.
        assert_eq!(outlines(&svg, window), 2);
        assert_eq!(outlines(&svg, block), if with_block { 2 } else { 0 });
        let png = fs::read(dir.join("selection.png")).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    }
    // Written with the other files: an existing picture is refused without --force.
    fs::remove_file(t.join("csv/selected_impacts.csv")).unwrap();
    let o = peenflow(&["export", "run/impacts.h5", "-f", "csv", "-o", "csv"], t);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("selection.png: exists"));
    assert!(!t.join("csv/selected_impacts.csv").exists());
}
