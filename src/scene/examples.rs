//! The scenes of `examples/`, embedded, so `peenflow init --example NAME` can write them
//! wherever the binary runs (an installed binary has no repository next to it).

/// One embedded example.
#[derive(Debug, Clone, Copy)]
pub struct Example {
    /// Name: the file's stem in `examples/`.
    pub name: &'static str,
    /// What it shows, one line.
    pub about: &'static str,
    /// Run with `peenflow sweep` (a sweep file), not `peenflow run`.
    pub sweep: bool,
    /// The file's text.
    pub text: &'static str,
}

macro_rules! example {
    ($name:literal, $sweep:literal, $about:literal) => {
        Example {
            name: $name,
            about: $about,
            sweep: $sweep,
            text: include_str!(concat!("../../examples/", $name, ".toml")),
        }
    };
}

/// Every file of `examples/` (a test keeps the two in step).
pub const EXAMPLES: &[Example] = &[
    example!(
        "single_shot",
        false,
        "one shot from rest on the jet axis, drag only: the accuracy reference"
    ),
    example!(
        "angle_45",
        false,
        "the Table 2 scene with the nozzle at a 45 degree peening angle"
    ),
    example!(
        "angle_60",
        false,
        "the Table 2 scene with the nozzle at a 60 degree peening angle"
    ),
    example!(
        "table1_test1",
        false,
        "the paper's Table 1, test 1: 0.8 mm, 0.6 MPa, 30 shots"
    ),
    example!(
        "table1_test2",
        false,
        "the paper's Table 1, test 2: 40 shots"
    ),
    example!(
        "table1_test3",
        false,
        "the paper's Table 1, test 3: 0.3 MPa"
    ),
    example!(
        "table1_test4",
        false,
        "the paper's Table 1, test 4: 0.5 mm shots"
    ),
    example!(
        "table1_test5",
        false,
        "the paper's Table 1, test 5: one shot"
    ),
    example!(
        "table1_sweep",
        true,
        "the paper's Table 1, all five tests over 5 seeds (a sweep)"
    ),
    example!(
        "friction_spin",
        false,
        "the Table 2 scene with Coulomb friction and shot spin"
    ),
    example!(
        "friction_history",
        false,
        "friction with LIGGGHTS' tangential spring (hybrid method)"
    ),
    example!(
        "s330_stream",
        false,
        "S330 sieve-graded shot streaming at 3 kg/min for 20 ms"
    ),
    example!(
        "coverage_stream",
        false,
        "a 150 ms stream at 1.5 kg/min onto A5052: input for `peenflow coverage`"
    ),
    example!(
        "a5052_restitution_curve",
        false,
        "a stream onto A5052 with the restitution against impact speed CalculiX measures"
    ),
    example!(
        "spring_wire",
        false,
        "S230 onto a spring's 8 mm wire: a cylindrical specimen (beyond the paper)"
    ),
    example!(
        "gear_root",
        false,
        "S230 into the tooth spaces of a module 4 rack: a grooved specimen (beyond the paper)"
    ),
    example!(
        "gear_turning_sweep",
        true,
        "gear_root's rack at 12 offsets over a pitch: a turning gear's coverage (a sweep)"
    ),
    example!(
        "spur_gear",
        false,
        "S230 onto a 30-tooth module 4 spur gear, the gear gear_root's rack cuts (beyond the paper)"
    ),
    example!(
        "spur_gear_turning_sweep",
        true,
        "spur_gear turned over one pitch at 12 offsets: a turning gear's coverage on the gear itself (a sweep)"
    ),
];

/// The example called `name`.
pub fn find(name: &str) -> Option<&'static Example> {
    EXAMPLES.iter().find(|e| e.name == name)
}

/// The examples' names, comma-separated (for messages).
pub fn names() -> String {
    EXAMPLES
        .iter()
        .map(|e| e.name)
        .collect::<Vec<_>>()
        .join(", ")
}
