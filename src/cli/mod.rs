//! Command-line front end: parses arguments, runs a command, reports. The library does
//! the work; this module only wires files, progress and messages.

pub mod args;

use crate::export::{self, ExportRequest, deck::UnitSystem, select::Selection};
use crate::output;
use crate::scene::{DEFAULT_SCENE, Scene, material};
use crate::sim::Simulation;
use anyhow::{Context, Result, bail};
pub use args::{
    AccuracyArgs, Cli, Command, CoverageArgs, ExportArgs, InitArgs, MergeArgs, RunArgs, SweepArgs,
    ValidateArgs,
};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run(a) => run_scene(a),
        Command::Init(a) => init(a),
        Command::Export(a) => export(a),
        Command::Accuracy(a) => accuracy(a),
        Command::Validate(a) => validate(a),
        Command::Sweep(a) => sweep(a),
        Command::Merge(a) => merge(a),
        Command::Coverage(a) => coverage(a),
        Command::Materials => {
            println!(
                "{:<18} {:>8} {:>6} {:>9} {:>10}  note",
                "name", "E GPa", "nu", "kg/m^3", "yield MPa"
            );
            for m in material::LIBRARY {
                let y = m
                    .yield_strength_mpa
                    .map_or("-".to_string(), |v| format!("{v}"));
                println!(
                    "{:<18} {:>8} {:>6} {:>9} {y:>10}  {}",
                    m.name, m.youngs_modulus_gpa, m.poisson_ratio, m.density_kg_m3, m.note
                );
            }
            Ok(())
        }
    }
}

fn init(a: InitArgs) -> Result<()> {
    use crate::scene::examples;
    if a.list {
        for e in examples::EXAMPLES {
            println!("{:<18} {}", e.name, e.about);
        }
        println!("write one with: peenflow init --example NAME [PATH]");
        return Ok(());
    }
    let (text, what, command, default_path) = match &a.example {
        None => (
            DEFAULT_SCENE,
            "the paper's Table 2 scene",
            "run",
            "scene.toml".into(),
        ),
        Some(name) => {
            let Some(e) = examples::find(name) else {
                bail!(
                    "--example {name}: no such example; allowed: {}",
                    examples::names()
                );
            };
            let command = if e.sweep { "sweep" } else { "run" };
            (
                e.text,
                e.about,
                command,
                PathBuf::from(format!("{name}.toml")),
            )
        }
    };
    let path = a.path.unwrap_or(default_path);
    if path.as_os_str() == "-" {
        print!("{text}");
        return Ok(());
    }
    if path.exists() && !a.force {
        bail!(
            "{}: file exists; pass --force to overwrite it",
            path.display()
        );
    }
    output::write_atomic(&path, text.as_bytes())?;
    eprintln!(
        "wrote {} ({what}); run it with: peenflow {command} {}",
        path.display(),
        path.display()
    );
    // A sweep built on another example needs that one next to it.
    if let Some(base) = example_base(text) {
        let dir = path.parent().unwrap_or(Path::new(""));
        let to = dir.join(format!("{}.toml", base.name));
        if to.exists() {
            if std::fs::read(&to).ok().as_deref() != Some(base.text.as_bytes()) {
                eprintln!(
                    "note: {} exists and differs from the example it names; the sweep runs on it as it is",
                    to.display()
                );
            }
        } else {
            output::write_atomic(&to, base.text.as_bytes())?;
            eprintln!("wrote {} (its base scene: {})", to.display(), base.about);
        }
    }
    Ok(())
}

/// The embedded example a sweep file's `base = "NAME.toml"` names, if any.
fn example_base(text: &str) -> Option<&'static crate::scene::examples::Example> {
    let table: toml::Table = toml::from_str(text).ok()?;
    let base = table.get("base")?.as_str()?;
    crate::scene::examples::find(base.strip_suffix(".toml")?)
}

fn run_scene(a: RunArgs) -> Result<()> {
    let mut scene = match &a.scene {
        Some(p) => Scene::load(p)?,
        None => Scene::default_scene(),
    };
    if let Some(seed) = a.seed {
        scene.seed = seed;
    }
    set_threads(a.threads)?;
    // Everything that can reject the scene (incl. shot placement) runs before the output
    // directory is touched.
    let effects = scene.effects();
    let mut sim = Simulation::new(&scene, &effects)?;
    let formats = parse_formats(&a.export)?;
    if formats.iter().any(|f| matches!(f, export::Format::Deck(_))) {
        export::deck_target(&scene, a.target_material.as_deref())?;
    }
    if let Some(ms) = a.snapshots {
        if !(ms > 0.0 && ms.is_finite()) {
            bail!("--snapshots {ms}: allowed an interval > 0 ms");
        }
        let n = scene.duration / (ms * 1e-3);
        if n > 100_000.0 {
            bail!(
                "--snapshots {ms}: {n:.0} snapshots; allowed at most 100000 (use a longer interval)"
            );
        }
        sim.record_snapshots(ms * 1e-3);
    }
    output::prepare_dir(&a.out, a.force)?;
    let bar = progress_bar(
        a.quiet,
        1000,
        "{spinner} [{elapsed_precise}] {bar:40} {percent:>3}% (eta {eta})",
    );
    // Records go to the files as the run hands them over: the run holds the shots in
    // flight, not every impact and shot (see `Simulation::run_into`).
    let mut sink = (
        output::RunWriter::create(&a.out)?,
        (
            crate::summary::SummaryBuilder::on(scene.specimen_shape.clone()),
            crate::record::figure::ImpactFigure::on(scene.specimen_shape.clone()),
        ),
    );
    // A run redone on windows starts its progress again: say why at that moment.
    let live = bar.clone();
    let sim = sim.with_notice(Box::new(move |note| {
        live.println(format!(
            "scheduler: {note}; the progress bar starts again for the run on windows"
        ))
    }));
    let started = Instant::now();
    let out = sim.run_into(&mut sink, &|f| bar.set_position((f * 1000.0) as u64));
    bar.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();
    let (writer, (builder, figure)) = sink;
    let summary = builder.finish(
        &scene,
        &effects.decisions,
        &out,
        wall,
        rayon::current_num_threads(),
    );
    writer.finish(&scene, out.end_time, &summary)?;
    // Where the jet axis meets the specimen: marked when the jet acts on shots.
    let jet = effects.drag || effects.lateral_force;
    let foot = scene
        .specimen_shape
        .axis_foot(&scene.nozzle.exit(), &scene.nozzle.axis())
        .map(|(x, y)| (x * 1e3, y * 1e3));
    figure.write(&a.out.join("impacts"), &scene.title, foot.filter(|_| jet))?;
    if !out.snapshots.is_empty() {
        output::write_snapshots(&a.out.join("snapshots"), &out.snapshots)?;
    }
    let mut exported = Vec::new();
    if !formats.is_empty() {
        let req = ExportRequest {
            formats,
            template: None,
            units: UnitSystem::MmTonneS,
            selection: Selection {
                seed: scene.seed,
                shape: scene.specimen_shape.clone(),
                ..Selection::default()
            },
            rigid_shots: true,
            shot_cells: None,
            element_size: None,
            target_material: a.target_material.clone(),
            out: a.out.clone(),
            force: true,
        };
        let h5 = a.out.join(crate::export::hdf5::IMPACT_FILE);
        let impacts = crate::export::hdf5::read(&h5)?.impacts;
        exported = export::export(&impacts, &scene, &h5.display().to_string(), &req)?;
    }
    if !a.quiet {
        print!("{}", summary.text());
        println!(
            "wrote {}/impacts.csv, impacts.h5, shots.csv, summary.json, impacts.png, impacts.svg",
            a.out.display()
        );
        if !out.snapshots.is_empty() {
            println!(
                "wrote {} snapshots: {}/snapshots/shots.pvd (open in ParaView)",
                out.snapshots.len(),
                a.out.display()
            );
        }
        for p in exported {
            println!("wrote {}", p.display());
        }
    }
    if !out.events.is_empty() {
        // "Ran, but": the outputs are complete and finite, yet some shots were stopped.
        eprintln!(
            "peenflow: warning: {} shot(s) had to be stopped; see the events above and summary.json",
            out.events.len()
        );
        std::process::exit(1);
    }
    Ok(())
}

/// A progress bar on stderr, hidden when `quiet` or when stderr is not a terminal.
fn progress_bar(quiet: bool, len: u64, template: &str) -> ProgressBar {
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let b = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    b.set_style(ProgressStyle::with_template(template).expect("BUG: progress template"));
    b
}

fn parse_formats(names: &[String]) -> Result<Vec<export::Format>> {
    let mut v = Vec::new();
    for n in names {
        let f = export::Format::parse(n.trim()).with_context(|| {
            format!(
                "--format {n}: unknown format; allowed: {}",
                export::Format::NAMES
            )
        })?;
        if !v.contains(&f) {
            v.push(f);
        }
    }
    Ok(v)
}

fn export(a: ExportArgs) -> Result<()> {
    let formats = parse_formats(&a.format)?;
    let units = match a.units.as_str() {
        "si" => UnitSystem::Si,
        "mm-t-s" | "mm" => UnitSystem::MmTonneS,
        other => bail!("--units {other}: unknown unit system; allowed: si, mm-t-s"),
    };
    if let Some(n) = a.shot_cells
        && !(2..=16).contains(&n)
    {
        bail!("--shot-cells {n}: allowed 2 to 16");
    }
    // A floor of a micrometre: finer elements serve no shot (the default under a 0.1 mm
    // shot is 12.5 um), and grading the block's axes costs time per finest cell.
    if let Some(h) = a.element_size_mm
        && !(h.is_finite() && h >= 1e-3)
    {
        bail!("--element-size-mm {h}: allowed 0.001 mm or more");
    }
    if let Some(w) = &a.window
        && (w.len() != 4 || w.iter().any(|v| !v.is_finite()) || w[2] <= w[0] || w[3] <= w[1])
    {
        bail!(
            "--window {}: give x0,y0,x1,y1 in mm with x1 > x0 and y1 > y0",
            listed(w)
        );
    }
    if let Some(w) = &a.time_window
        && (w.len() != 2 || w.iter().any(|v| !v.is_finite()) || w[1] <= w[0])
    {
        bail!("--time-window {}: give t0,t1 in ms with t1 > t0", listed(w));
    }
    let (file, scene) = export::read_impact_file(&a.impacts)?;
    let selection = Selection {
        window: a
            .window
            .as_ref()
            .map(|w| [w[0] * 1e-3, w[1] * 1e-3, w[2] * 1e-3, w[3] * 1e-3]),
        time_window: a.time_window.as_ref().map(|w| [w[0] * 1e-3, w[1] * 1e-3]),
        first_hits_only: a.first_hits_only,
        first: a.first,
        sample: a.sample,
        seed: a.seed.unwrap_or(file.seed),
        shape: scene.specimen_shape.clone(),
    };
    let req = ExportRequest {
        formats,
        template: a.template,
        units,
        selection,
        rigid_shots: !a.elastic,
        shot_cells: a.shot_cells,
        element_size: a.element_size_mm.map(|h| h * 1e-3),
        target_material: a.target_material,
        out: a.out,
        force: a.force,
    };
    let written = export::export(
        &file.impacts,
        &scene,
        &a.impacts.display().to_string(),
        &req,
    )?;
    for p in written {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// The worker threads: `n` (default: one per core), this thread one of them. The run's
/// scheduler then works among them instead of waiting beside them: a pool of `n` workers
/// besides it put three threads on two cores whenever the scheduler's thread worked while
/// the idle workers looked for jobs.
fn set_threads(n: Option<usize>) -> Result<()> {
    if n == Some(0) {
        bail!("--threads 0: allowed 1 or more");
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(n.unwrap_or(0))
        .use_current_thread()
        .build_global()
        .context("cannot set up the worker threads")?;
    Ok(())
}

fn accuracy(a: AccuracyArgs) -> Result<()> {
    let scene = match &a.scene {
        Some(p) => Scene::load(p)?,
        None => Scene::default_scene(),
    };
    let target = match &a.target {
        Some(t) => Some(crate::accuracy::parse_target(t).with_context(|| {
            format!("--target {t}: give a positive fraction or percentage, e.g. 0.1% or 0.001")
        })?),
        None => None,
    };
    if a.seeds == 0 || a.seeds > 1000 {
        bail!("--seeds {}: allowed 1 to 1000", a.seeds);
    }
    let settings = crate::accuracy::ladder_for(&scene);
    set_threads(a.threads)?;
    output::prepare_dir(&a.out, a.force)?;
    let bar = if std::io::stderr().is_terminal() {
        ProgressBar::with_draw_target(Some(settings.len() as u64), ProgressDrawTarget::stderr())
    } else {
        ProgressBar::hidden()
    };
    let study = crate::accuracy::study(&scene, a.seeds, &settings, 0.05, &|k, _| {
        bar.set_position(k as u64)
    });
    bar.finish_and_clear();
    print!("{}", study.table());
    output::write_atomic(&a.out.join("accuracy.csv"), &study.csv())?;
    crate::plot::lines(
        &a.out.join("accuracy"),
        &format!("{}: error against cost", scene.title),
        ("wall time, s", "error (relative)"),
        &study.series(),
        true,
    )?;
    println!(
        "wrote {}/accuracy.csv, accuracy.png, accuracy.svg",
        a.out.display()
    );
    if let Some(t) = target {
        match study.recommend(t) {
            Some(r) => println!(
                "recommended for a {}% target: [integrator] {} ({} s, error {:.2e})",
                t * 100.0,
                if r.method == "adaptive" {
                    format!("tolerance = {:e}", r.setting)
                } else {
                    format!(
                        "method = \"{}\", fixed_step_ns = {}",
                        r.method,
                        (r.setting * 1e15).round() / 1e6
                    )
                },
                if r.wall_time_s >= 0.01 {
                    format!("{:.3}", r.wall_time_s)
                } else {
                    format!("{:.1e}", r.wall_time_s)
                },
                r.error
            ),
            None => bail!(
                "no setting of the ladder meets the {}% target; the best error was {:.2e}",
                t * 100.0,
                study
                    .rows
                    .iter()
                    .map(|r| r.error)
                    .fold(f64::INFINITY, f64::min)
            ),
        }
    }
    Ok(())
}

fn validate(a: ValidateArgs) -> Result<()> {
    if a.seeds == 0 || a.seeds > 1000 {
        bail!("--seeds {}: allowed 1 to 1000", a.seeds);
    }
    output::prepare_dir(&a.out, a.force)?;
    let md = crate::validate::run(&a.out, a.seeds, &|stage| eprintln!("validate: {stage}"))?;
    output::write_atomic(&a.out.join("validation.md"), md.as_bytes())?;
    print!("{md}");
    println!("wrote {}/validation.md and figures/", a.out.display());
    Ok(())
}

/// Parses `--shard K/N` (1-based).
pub fn parse_shard(s: &str) -> Result<(usize, usize)> {
    let (k, n) = s
        .split_once('/')
        .and_then(|(k, n)| {
            Some((
                k.trim().parse::<usize>().ok()?,
                n.trim().parse::<usize>().ok()?,
            ))
        })
        .with_context(|| format!("--shard {s}: expected K/N with whole numbers, e.g. 2/8"))?;
    if n == 0 {
        bail!("--shard {s}: N = 0; allowed N >= 1");
    }
    if k == 0 || k > n {
        bail!("--shard {s}: K = {k} is outside 1..={n} (shards are numbered from 1 to N)");
    }
    Ok((k, n))
}

fn sweep(a: SweepArgs) -> Result<()> {
    let shard = a.shard.as_deref().map(parse_shard).transpose()?;
    let plan = crate::sweep::Plan::load(&a.sweep)?;
    if a.list {
        println!(
            "{}: {} case(s) x {} seed(s) ({}), parameters: {}",
            plan.title,
            plan.cases.len(),
            plan.seeds.len(),
            plan.combine.name(),
            plan.parameters.join(", ")
        );
        let cases: Vec<&crate::sweep::Case> = match shard {
            Some((k, n)) => plan.shard(k, n),
            None => plan.cases.iter().collect(),
        };
        for c in cases {
            let values: Vec<String> = plan
                .parameters
                .iter()
                .zip(&c.values)
                .map(|(p, v)| format!("{p} = {}", crate::sweep::plan::show(v)))
                .collect();
            println!("{:>4}  {}  {}", c.index, c.name, values.join(", "));
        }
        return Ok(());
    }
    set_threads(a.threads)?;
    let bar = progress_bar(
        a.quiet,
        1,
        "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} cases (eta {eta}) {msg}",
    );
    let opts = crate::sweep::Options {
        out: a.out.clone(),
        shard,
        force: a.force,
    };
    let started = Instant::now();
    let report = crate::sweep::run::run(&plan, &opts, &|done, total, name| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(name.to_string());
    })?;
    bar.finish_and_clear();
    if !a.quiet {
        let which = match shard {
            Some((k, n)) => format!("shard {k}/{n}: "),
            None => String::new(),
        };
        println!(
            "{which}ran {} case(s), skipped {} finished, in {:.1} s",
            report.ran.len(),
            report.skipped.len(),
            started.elapsed().as_secs_f64()
        );
        if !report.replaced.is_empty() {
            println!(
                "re-ran {} case(s) whose scene or seeds changed: {}",
                report.replaced.len(),
                report.replaced.join(", ")
            );
        }
        if report.assembled {
            println!(
                "wrote {0}/sweep.h5, {0}/cases.csv, {0}/figures/ and one directory per case",
                a.out.display()
            );
        } else {
            println!(
                "when every shard is done: peenflow merge {} [other shard directories]",
                a.out.display()
            );
        }
    }
    if report.events > 0 {
        eprintln!(
            "peenflow: warning: {} shot(s) had to be stopped; see the cases' case.json and impacts.h5",
            report.events
        );
        std::process::exit(1);
    }
    Ok(())
}

fn merge(a: MergeArgs) -> Result<()> {
    let r = crate::sweep::merge::merge(&a.dirs, a.out.as_deref(), a.force)?;
    println!(
        "merged {} case(s) ({} copied in) into {}/sweep.h5",
        r.cases,
        r.copied,
        r.out.display()
    );
    Ok(())
}

/// An error as one line: the message, then each cause it does not already quote (the
/// errors of this crate name their cause in their own message; `{:#}` would repeat it:
/// "No such file or directory (os error 2): No such file or directory (os error 2)").
pub fn error_message(e: &anyhow::Error) -> String {
    let mut msg = e.to_string();
    for cause in e.chain().skip(1) {
        let c = cause.to_string();
        if !msg.contains(&c) {
            msg.push_str(": ");
            msg.push_str(&c);
        }
    }
    msg
}

/// Numbers as a user types them on the command line: `1,2,3`.
fn listed(w: &[f64]) -> String {
    w.iter().map(f64::to_string).collect::<Vec<_>>().join(",")
}

fn coverage(a: CoverageArgs) -> Result<()> {
    let window = match &a.window {
        Some(w)
            if w.len() == 4 && w.iter().all(|v| v.is_finite()) && w[2] > w[0] && w[3] > w[1] =>
        {
            Some([w[0] * 1e-3, w[1] * 1e-3, w[2] * 1e-3, w[3] * 1e-3])
        }
        Some(w) => bail!(
            "--window {}: give x0,y0,x1,y1 in mm with x1 > x0 and y1 > y0",
            listed(w)
        ),
        None => None,
    };
    if let Some(c) = a.cell_um
        && !(c > 0.0 && c.is_finite())
    {
        bail!("--cell-um {c}: allowed > 0");
    }
    let target = match &a.target_material {
        Some(name) => Some(material::builtin(name).with_context(|| {
            format!(
                "--target-material {name}: unknown material; known: {}",
                material::LIBRARY
                    .iter()
                    .map(|m| m.name)
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })?),
        None => None,
    };
    let gear = gear_of(&a)?;
    let traverse = if gear.is_some() {
        None
    } else {
        traverse_of(&a)?
    };
    let dent = match &a.dent_curve {
        Some(items) => {
            let shown = items.join(",");
            let points = items
                .iter()
                .map(|it| {
                    let (v, f) = it.split_once(':')?;
                    Some((v.trim().parse::<f64>().ok()?, f.trim().parse::<f64>().ok()?))
                })
                .collect::<Option<Vec<(f64, f64)>>>()
                .with_context(|| {
                    format!(
                        "--dent-curve {shown}: give SPEED:RATIO pairs separated by commas (normal impact speed in m/s, dent radius over shot radius), e.g. 20:0.36,70:0.52"
                    )
                })?;
            Some(
                crate::coverage::dent::DentModel::measured(&points)
                    .map_err(|e| anyhow::anyhow!("--dent-curve {shown}: {e}"))?,
            )
        }
        None => None,
    };
    for f in &a.impacts {
        if !f.is_file() {
            bail!("{}: no such impact file", f.display());
        }
    }
    if let Some(turning) = gear {
        let r = output::with_dir(&a.out, a.force, || {
            crate::coverage::output::run_gear(&crate::coverage::output::GearRequest {
                impacts: a.impacts.clone(),
                target,
                dent,
                out: a.out.clone(),
                turning,
                rpm: a.gear_rpm,
            })
        })?;
        print_gear(&r);
        return Ok(());
    }
    let impacts = match a.impacts.as_slice() {
        [one] => one.clone(),
        many => bail!(
            "{} impact files given: several only with --gear-teeth (a turning gear from runs at several offsets of one rack); otherwise give one",
            many.len()
        ),
    };
    let r = output::with_dir(&a.out, a.force, || {
        crate::coverage::output::run(&crate::coverage::output::Request {
            impacts,
            window,
            cell: a.cell_um.map(|c| c * 1e-6),
            target,
            out: a.out.clone(),
            update_h5: !a.no_h5,
            seed: a.seed,
            traverse,
            dent,
        })
    })?;
    let c = &r.coverage;
    if r.seed.1 > 1 {
        println!(
            "the file pools {} seeds (a sweep case); coverage of seed {} (choose with --seed)",
            r.seed.1, r.seed.0
        );
    }
    println!("target {}: {}", r.target, r.model.describe());
    if let Some(asked) = a.cell_um
        && c.cell > asked * 1e-6 * (1.0 + 1e-9)
    {
        println!(
            "note: --cell-um {asked} would need more than {} cells along the window; cells enlarged to {:.2} um",
            crate::coverage::MAX_CELLS,
            c.cell * 1e6
        );
    }
    println!(
        "{} dents, median diameter {:.3} mm; window {} {:.2}..{:.2} mm, {} {:.2}..{:.2} mm, {} x {} cells of {:.1} um",
        r.dents,
        r.median_dent_diameter * 1e3,
        r.axes.0,
        c.window[0] * 1e3,
        c.window[2] * 1e3,
        r.axes.1,
        c.window[1] * 1e3,
        c.window[3] * 1e3,
        c.nx,
        c.ny,
        c.cell * 1e6
    );
    if let Some([lo, mid, hi]) = r.dent_aspect {
        println!(
            "dents on the curved surface are ellipses: across / along {lo:.3} to {hi:.3} (median {mid:.3}); diameters are those of the disc of the same area"
        );
    }
    println!(
        "coverage {:.2} % after {:.3} ms of exposure (from the first impact, {} dents touch the window)",
        100.0 * c.final_coverage,
        c.exposure * 1e3,
        c.dents_in_window
    );
    if !r.zones.is_empty() {
        println!("coverage per zone of the groove inside the window (mm of arc across it):");
        for z in &r.zones {
            println!(
                "  {:<7} {:>8.2}..{:<8.2} {:>7.2} %",
                z.zone,
                z.across_m[0] * 1e3,
                z.across_m[1] * 1e3,
                100.0 * z.coverage
            );
        }
    }
    match c.fit {
        Some(f) => {
            println!(
                "Avrami fit C = 1 - exp(-k t^n): k = {:.4e} s^-n, n = {:.3} (R^2 {:.4}, {} points)",
                f.k, f.n, f.r_squared, f.points
            );
            let t98 = f.time_to(0.98);
            println!(
                "time to 98 % (full) coverage: {:.3} ms from the fit{}",
                t98 * 1e3,
                match c.t98_measured {
                    Some(t) => format!("; reached in the run at {:.3} ms", t * 1e3),
                    None if t98 > c.exposure => " (an extrapolation: the run ended before)".into(),
                    None => String::new(),
                }
            );
        }
        None => println!(
            "no Avrami fit: the curve has fewer than 3 points between 0.5 % and 99.5 % coverage (run longer, or choose a smaller --window)"
        ),
    }
    if let Some(t) = &r.track {
        print_track(t, r.steady_feed);
    }
    for p in &r.written {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// The turning gear asked with `--gear-teeth` (and the nozzle's speed along its axis,
/// `--traverse-mm-s`); the options that do not apply to it are refused.
fn gear_of(a: &CoverageArgs) -> Result<Option<crate::coverage::gear::Turning>> {
    let Some(z) = a.gear_teeth else {
        if let Some(r) = a.gear_rpm {
            bail!("--gear-rpm {r}: give the gear's teeth too (--gear-teeth)");
        }
        return Ok(None);
    };
    if let Some(r) = a.gear_rpm
        && !(r > 0.0 && r <= 1e5)
    {
        bail!("--gear-rpm {r}: allowed (0, 100000] revolutions per minute");
    }
    if !(2..=10_000).contains(&z) {
        bail!("--gear-teeth {z}: allowed 2 to 10000 teeth");
    }
    let Some(v) = a.traverse_mm_s else {
        bail!(
            "--gear-teeth {z}: give the nozzle's speed along the gear's axis too (--traverse-mm-s)"
        );
    };
    if !(v > 0.0 && v <= 1e5) {
        bail!("--traverse-mm-s {v}: allowed (0, 100000] mm/s");
    }
    let not_here = |flag: &str, why: &str| -> Result<()> {
        bail!("{flag} does not apply with --gear-teeth: {why}")
    };
    if a.traverse_deg.is_some() {
        not_here(
            "--traverse-deg",
            "the nozzle moves along the gear's axis (the teeth pass across it as the gear turns)",
        )?;
    }
    if a.pitch_mm.is_some() {
        not_here(
            "--pitch-mm",
            "one pass along the gear covers every tooth space; for more passes multiply the dents per point",
        )?;
    }
    if a.window.is_some() || a.cell_um.is_some() {
        not_here(
            if a.window.is_some() {
                "--window"
            } else {
                "--cell-um"
            },
            "the profile spans one period of the rack, with points a tenth of the median dent diameter apart",
        )?;
    }
    if a.seed.is_some() {
        not_here("--seed", "every file's seeds are pooled")?;
    }
    Ok(Some(crate::coverage::gear::Turning {
        teeth: z as u32,
        speed: v * 1e-3,
    }))
}

/// What a turning gear gives, as `peenflow coverage --gear-teeth` prints it.
fn print_gear(r: &crate::coverage::output::GearReport) {
    use crate::coverage::traverse::{FULL, coverage};
    let g = &r.profile;
    let v = g.turning.speed * 1e3;
    println!("target {}: {}", r.target, r.model.describe());
    println!(
        "turning gear, {} teeth (rack pitch {:.3} mm, pitch radius {:.1} mm), nozzle moving along its axis at {v} mm/s",
        g.turning.teeth,
        g.pitch * 1e3,
        f64::from(g.turning.teeth) * g.pitch / std::f64::consts::TAU * 1e3
    );
    println!(
        "{} dents of the still nozzle at {} offsets over one pitch (median diameter {:.3} mm):",
        r.dents,
        g.offsets.len(),
        r.median_dent_diameter * 1e3
    );
    for s in &g.offsets {
        println!(
            "  offset {:>8.3} mm: share {:.3} of the pitch, {} dents over {} seed{}, {:.0} per s",
            s.offset_m * 1e3,
            s.weight,
            s.dents,
            s.runs,
            if s.runs == 1 { "" } else { "s" },
            s.dent_rate_per_s
        );
    }
    println!(
        "one pass along the gear, zone by zone across a tooth space ({:.2} mm of arc per pitch, from the space's middle; +- is twice the standard error):",
        g.period * 1e3
    );
    println!(
        "  zone       across, mm        dents per point: least      mean   coverage: least    mean   full coverage at, mm/s"
    );
    for z in &r.zones {
        println!(
            "  {:<9} {:>7.2}..{:<7.2}   {:>9.3} +- {:<6.3} {:>7.3}   {:>14.1} % {:>6.1} %   {:>10.4}",
            format!("{}{}", z.zone, crate::coverage::output::side_word(z.side)),
            z.across_m[0] * 1e3,
            z.across_m[1] * 1e3,
            z.least_dents,
            2.0 * z.least_standard_error,
            z.mean_dents,
            100.0 * z.least_coverage,
            100.0 * z.mean_coverage,
            z.full_coverage_speed_m_s * 1e3
        );
    }
    let least = g.least();
    if let Some(b) = &r.banding {
        let show = |w: crate::coverage::output::Bandwidth| {
            if w.resolved() {
                format!("{:.1} %", 100.0 * w.rms)
            } else {
                format!("under {:.1} % (the runs' noise)", 100.0 * w.noise)
            }
        };
        let (zone, worst) = b.worst();
        println!(
            "at {} rev/min the nozzle moves {:.3} mm per revolution: dents per point vary along the axis in helical bands of rms amplitude (over their mean) {} over the profile, {} on the {zone}{}",
            b.rpm,
            b.feed_per_revolution_m * 1e3,
            show(b.rms),
            show(worst),
            if worst.resolved() && worst.rms > 0.1 {
                "; turn faster or move slower for an even finish (the numbers above are the means along the axis)"
            } else {
                ""
            }
        );
    }
    match g.full_coverage() {
        Some((speed, passes)) => println!(
            "full coverage (98 %, {FULL:.2} dents per point) everywhere: at most {:.4} mm/s in one pass, or {passes} pass{} at {v} mm/s (least covered: {} at {:.2} mm, {:.1} % after one pass)",
            speed * 1e3,
            if passes == 1 { "" } else { "es" },
            r.least_zone,
            least.offset * 1e3,
            100.0 * coverage(least.dents)
        ),
        None => println!(
            "a point of the profile gets no dent ({} at {:.2} mm): no speed covers it",
            r.least_zone,
            least.offset * 1e3
        ),
    }
    if !r.steady_feed {
        println!(
            "note: a run's feed is not a steady stream; the gear's coverage assumes one (each run's dents spread evenly over its span)"
        );
    }
    for p in &r.written {
        println!("wrote {}", p.display());
    }
}

/// The moving nozzle asked with `--traverse-mm-s`, `--traverse-deg`, `--pitch-mm`.
fn traverse_of(a: &CoverageArgs) -> Result<Option<crate::coverage::traverse::Traverse>> {
    let Some(v) = a.traverse_mm_s else {
        if let Some(d) = a.traverse_deg {
            bail!("--traverse-deg {d}: give the traverse speed too (--traverse-mm-s)");
        }
        if let Some(p) = a.pitch_mm {
            bail!("--pitch-mm {p}: give the traverse speed too (--traverse-mm-s)");
        }
        return Ok(None);
    };
    if !(v > 0.0 && v <= 1e5) {
        bail!("--traverse-mm-s {v}: allowed (0, 100000] mm/s");
    }
    let deg = a.traverse_deg.unwrap_or(0.0);
    if !(-360.0..=360.0).contains(&deg) {
        bail!("--traverse-deg {deg}: allowed [-360, 360] degrees from +x");
    }
    if let Some(p) = a.pitch_mm
        && !(p > 0.0 && p <= 1e4)
    {
        bail!("--pitch-mm {p}: allowed (0, 10000] mm");
    }
    Ok(Some(crate::coverage::traverse::Traverse {
        speed: v * 1e-3,
        direction: deg.to_radians(),
        pitch: a.pitch_mm.map(|p| p * 1e-3),
    }))
}

/// What a moving nozzle gives, as `peenflow coverage --traverse-mm-s` prints it.
fn print_track(t: &crate::coverage::traverse::Track, steady: bool) {
    use crate::coverage::traverse::{FULL, coverage};
    let v = t.traverse.speed * 1e3;
    println!(
        "nozzle moving at {v} mm/s towards {} deg ({} dents of the still nozzle{}, {:.0} per s; +- is twice the standard error):",
        t.traverse.direction_deg(),
        t.dents,
        match t.runs {
            1 => String::new(),
            k => format!(" over the file's {k} seeds"),
        },
        t.rate
    );
    let peak = t.peak();
    let strip = |c: f64| match t.width(c) {
        0.0 => "none".to_string(),
        x => format!("{:.2} mm wide", x * 1e3),
    };
    println!(
        "  one pass: up to {:.3} +- {:.3} dents per point ({:.1} % coverage) {:.2} mm from the jet axis' line; covered to 50 %: {}, to 98 %: {}",
        peak.dents,
        2.0 * peak.se,
        100.0 * coverage(peak.dents),
        peak.offset * 1e3,
        strip(0.5),
        strip(0.98)
    );
    if let (Some((least, mean)), Some(p)) = (t.raster_range(), t.traverse.pitch) {
        println!(
            "  raster, passes {} mm apart: {:.3} +- {:.3} dents per point where fewest, {mean:.3} on average ({:.1} % and {:.1} % coverage)",
            p * 1e3,
            least.dents,
            2.0 * least.se,
            100.0 * coverage(least.dents),
            100.0 * coverage(mean)
        );
    }
    let (what, one) = match t.raster {
        Some(_) => ("rasters", "raster"),
        None => ("passes over one line", "pass"),
    };
    let g = t.governing();
    match t.full_coverage() {
        Some((speed, passes)) => println!(
            "  full coverage (98 %, {FULL:.2} dents per point{}): at most {:.3} +- {:.3} mm/s in one {one}, or {passes} {} at {v} mm/s",
            if t.raster.is_some() {
                " everywhere"
            } else {
                " on the best line"
            },
            speed * 1e3,
            2.0 * speed * 1e3 * g.se / g.dents,
            if passes == 1 { one } else { what }
        ),
        None => println!("  no dent reaches the track"),
    }
    if !steady {
        println!(
            "  note: this run's feed is not a steady stream; the moving-nozzle figures assume one (docs/coverage.md)"
        );
    }
}
