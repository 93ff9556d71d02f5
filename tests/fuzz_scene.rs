//! Fuzzing the scene loader: arbitrary text, and the default scene with values replaced by
//! hostile ones, must load or be refused with an error, never panic; scenes that load
//! must also place their shots without panicking.
//! CI runs PROPTEST_CASES (default 20000 strings, 5000 mutations here); run longer with
//! `PROPTEST_CASES=1000000 cargo test --release --test suite fuzz_scene::` (see docs/errors.md).

use peenflow::scene::{DEFAULT_SCENE, Scene};
use proptest::prelude::*;

fn cases(default: u32) -> u32 {
    std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn load_and_place(text: &str) {
    if let Ok(scene) = Scene::from_toml(text, "fuzz") {
        if scene.feed.expected_count() <= 200.0 {
            let _ = peenflow::feed::initial_shots(&scene);
        }
        let _ = scene.effects();
    }
}

const HOSTILE: &[&str] = &[
    "nan",
    "-nan",
    "inf",
    "-inf",
    "0",
    "-0.0",
    "-1",
    "1e308",
    "1e-320",
    "-1e308",
    "\"\"",
    "\"x\"",
    "[]",
    "[1, 2]",
    "{}",
    "{ a = 1 }",
    "true",
    "4294967296",
    "-9223372036854775808",
    "18446744073709551615",
    "\"auto\"",
    "\"rho_0\"",
    "\"consistent\"",
    "[0.0, 0.0, 0.0]",
    "[1e9, -1e9, 0]",
    "\"stream\"",
    "\"list\"",
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(20000)))]

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,400}") {
        load_and_place(&text);
    }

    #[test]
    fn toml_like_text_never_panics(text in "(\\[[a-z_.]{1,20}\\]\n|[a-z_]{1,20} = [-0-9.e\"a-z\\[\\], ]{0,20}\n){0,12}") {
        load_and_place(&text);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases(5000)))]

    #[test]
    fn default_scene_with_hostile_values_never_panics(
        edits in prop::collection::vec((0usize..200, 0usize..HOSTILE.len()), 1..4),
        drop_line in prop::option::of(0usize..200),
    ) {
        let mut lines: Vec<String> = DEFAULT_SCENE.lines().map(str::to_string).collect();
        for (k, h) in edits {
            let k = k % lines.len();
            if let Some((key, _)) = lines[k].split_once('=') {
                lines[k] = format!("{key}= {}", HOSTILE[h]);
            }
        }
        if let Some(k) = drop_line {
            let k = k % lines.len();
            lines.remove(k);
        }
        load_and_place(&lines.join("\n"));
    }
}
