//! Full-size validation runs of the dlsm model (docs/validation.md): the paper's Table 3,
//! the two wave tests, tensile failure on random and regular samples, the Brazilian test
//! (flat and 20°; between flat platens, curved jaws, under an arc pressure), the rolling
//! ball, and the fabric of the sample methods. Writes a JSON
//! line per case to target/dlsm-validation/results.jsonl and SVG plots to docs/img/.
//!
//! ```sh
//! cargo run --release --example dlsm_validation -- fabric ball failure table3 waves brazilian platens
//! ```
//!
//! Each case is a shipped scene at its full size (the tests run them smaller). Cases run in
//! the order given; all of them take a few hours on two cores.

use std::io::Write;
use std::path::PathBuf;

use fractum::Run;
use fractum::Scene;
use fractum::models::dlsm::DlsmRun;
use fractum::sample::voronoi::{
    Domain, face_normal_fabric, noisy_grid_seeds, packing_seeds, tessellate,
};
use fractum::state::Vec3;
use plotters::prelude::*;
use rand::SeedableRng;
use serde_json::{Value, json};

/// The repository: `FRACTUM_REPO` when set (a copy elsewhere), else the one it was built in.
fn repo() -> PathBuf {
    std::env::var_os("FRACTUM_REPO")
        .map_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")), PathBuf::from)
}

fn run(file: &str, overrides: &[String]) -> (DlsmRun, Value) {
    try_run(file, overrides).expect("run")
}

/// As [`run`], or the sentence with which the scene was refused at build.
fn try_run(file: &str, overrides: &[String]) -> Result<(DlsmRun, Value), String> {
    let scene = Scene::load(&repo().join(file), overrides).map_err(|e| e.to_string())?;
    let started = std::time::Instant::now();
    let mut run = DlsmRun::new(scene, 2, &mut |m| eprintln!("  {m}")).map_err(|e| e.to_string())?;
    while !run.finished() {
        if let Err(e) = run.advance(20_000) {
            // An unstable run is a result too: say where it stopped.
            let mut s = run.summary();
            s["error"] = json!(e.to_string());
            return Ok((run, s));
        }
        eprintln!("  step {} of {}", run.clock.step, run.clock.end_step);
    }
    let mut s = run.summary();
    s["wall_seconds"] = json!(started.elapsed().as_secs_f64());
    Ok((run, s))
}

fn record(case: &str, value: Value) {
    let dir = repo().join("target/dlsm-validation");
    std::fs::create_dir_all(&dir).unwrap();
    let mut f = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(dir.join("results.jsonl"))
        .unwrap();
    writeln!(f, "{}", json!({ "case": case, "result": value })).unwrap();
    println!("{case}: {value}");
}

fn pick(s: &Value, keys: &[&str]) -> Value {
    let mut m = serde_json::Map::new();
    for k in keys {
        if let Some(v) = s.get(*k) {
            m.insert((*k).to_string(), v.clone());
        }
    }
    Value::Object(m)
}

/// Lines (label, points) on one chart.
fn plot(file: &str, title: &str, x: &str, y: &str, lines: &[(String, Vec<(f64, f64)>)]) {
    let path = repo().join("docs/img").join(file);
    let root = SVGBackend::new(&path, (720, 460)).into_drawing_area();
    root.fill(&WHITE).unwrap();
    let all = lines.iter().flat_map(|l| l.1.iter());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in all {
        x0 = x0.min(p.0);
        x1 = x1.max(p.0);
        y0 = y0.min(p.1);
        y1 = y1.max(p.1);
    }
    let pad = 0.05 * (y1 - y0).max(1e-30);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, (y0 - pad)..(y1 + pad))
        .unwrap();
    chart.configure_mesh().x_desc(x).y_desc(y).draw().unwrap();
    let colours = [BLUE, RED, GREEN, BLACK, MAGENTA, CYAN];
    for (k, (label, pts)) in lines.iter().enumerate() {
        let c = colours[k % colours.len()];
        chart
            .draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))
            .unwrap()
            .label(label.clone())
            .legend(move |(a, b)| PathElement::new(vec![(a, b), (a + 18, b)], c.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .unwrap();
    root.present().unwrap();
}

fn columns(run: &DlsmRun, x: &str, y: &str) -> Vec<(f64, f64)> {
    let xs = run.series.column(x).unwrap();
    let ys = run.series.column(y).unwrap();
    xs.into_iter().zip(ys).collect()
}

fn main() {
    fractum::output::figure::register_font();
    let cases: Vec<String> = std::env::args().skip(1).collect();
    if cases.first().map(String::as_str) == Some("uniform") {
        uniform(&cases[1..]);
        return;
    }
    if cases.first().map(String::as_str) == Some("ablate") {
        ablate(&cases[1..]);
        return;
    }
    for case in &cases {
        eprintln!("== {case}");
        match case.as_str() {
            "fabric" => {
                let d = Domain::Box {
                    lo: Vec3::zeros(),
                    hi: Vec3::repeat(1.0),
                };
                let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
                let mut out = Vec::new();
                for noise in [0.0, 0.5, 0.9, 1.0] {
                    let seeds = noisy_grid_seeds(&d, 11000, noise, &mut rng);
                    let f = face_normal_fabric(&tessellate(&seeds, &d).unwrap());
                    out.push(json!({"method": "noisy_grid", "noise": noise, "fabric": f}));
                }
                let seeds = packing_seeds(&d, 11000, 0.25, &mut rng).unwrap();
                let f = face_normal_fabric(&tessellate(&seeds, &d).unwrap());
                out.push(json!({"method": "packing", "radius_dispersion": 0.25, "fabric": f}));
                record("fabric", json!(out));
            }
            "ball" => {
                let (r, s) = run("scenes/rolling_ball.toml", &[]);
                record(
                    "rolling_ball",
                    pick(
                        &s,
                        &[
                            "elements",
                            "steps",
                            "dt",
                            "rotation_turns",
                            "max_energy_ratio",
                            "downslope_distance",
                            "downslope_sizes",
                            "bounces",
                            "wall_seconds",
                        ],
                    ),
                );
                plot(
                    "dlsm_rolling_ball.svg",
                    "Rolling ball: energies (J)",
                    "time (s)",
                    "energy (J)",
                    &[
                        ("total".into(), columns(&r, "time", "total_energy")),
                        ("kinetic".into(), columns(&r, "time", "kinetic_energy")),
                        ("gravity".into(), columns(&r, "time", "potential_energy")),
                        (
                            "lattice strain".into(),
                            columns(&r, "time", "strain_energy"),
                        ),
                    ],
                );
                plot(
                    "dlsm_rolling_ball_path.svg",
                    "Rolling ball: the centre's height above the ground and distance down the slope (m)",
                    "time (s)",
                    "m",
                    &[
                        ("height".into(), columns(&r, "time", "height")),
                        (
                            "down the slope / 10".into(),
                            columns(&r, "time", "downslope_distance")
                                .into_iter()
                                .map(|(t, d)| (t, d / 10.0))
                                .collect(),
                        ),
                        ("turns".into(), columns(&r, "time", "rotation_turns")),
                    ],
                );
            }
            "failure" => {
                let mut lines = Vec::new();
                for (label, sets) in [
                    ("random (packing)", vec![]),
                    ("regular grid", vec!["sample.method=grid".to_string()]),
                ] {
                    let (r, s) = run("scenes/dlsm_tensile_failure.toml", &sets);
                    record(
                        &format!("tensile_failure {label}"),
                        pick(
                            &s,
                            &[
                                "elements",
                                "steps",
                                "apparent_strength",
                                "local_strength",
                                "strength_ratio",
                                "apparent_young",
                                "broken_contacts",
                                "wall_seconds",
                            ],
                        ),
                    );
                    let pts = columns(&r, "strain", "stress")
                        .into_iter()
                        .map(|(e, s)| (e * 1e3, s / 1e6))
                        .collect();
                    lines.push((label.to_string(), pts));
                }
                plot(
                    "dlsm_tensile_failure.svg",
                    "Tensile failure, sigma_f = 10 MPa",
                    "strain (1e-3)",
                    "stress (MPa)",
                    &lines,
                );
            }
            "table3plot" => {
                // Table 3 again from results.jsonl (after a run that stopped early).
                let text =
                    std::fs::read_to_string(repo().join("target/dlsm-validation/results.jsonl"))
                        .unwrap_or_default();
                let (mut pts_e, mut pts_nu) = (Vec::new(), Vec::new());
                for line in text.lines() {
                    let v: Value = serde_json::from_str(line).unwrap();
                    let case = v["case"].as_str().unwrap_or("");
                    if let Some(nu) = case.strip_prefix("table3 nu=") {
                        let nu: f64 = nu.parse().unwrap();
                        if let (Some(e), Some(p)) = (
                            v["result"]["apparent_young"].as_f64(),
                            v["result"]["apparent_poisson"].as_f64(),
                        ) {
                            if v["result"].get("error").is_none() {
                                pts_e.push((nu, e / 1e9));
                                pts_nu.push((nu, p - nu));
                            }
                        }
                    }
                }
                pts_e.sort_by(|a, b| a.0.total_cmp(&b.0));
                pts_nu.sort_by(|a, b| a.0.total_cmp(&b.0));
                let paper = [
                    (0.49, 20.973),
                    (0.45, 20.267),
                    (0.4, 20.164),
                    (0.3, 20.141),
                    (0.2, 20.117),
                    (0.1, 20.095),
                    (0.0, 20.078),
                    (-0.1, 20.064),
                    (-0.2, 20.055),
                    (-0.3, 20.051),
                    (-0.4, 20.053),
                    (-0.5, 20.065),
                    (-0.6, 20.089),
                    (-0.7, 20.140),
                    (-0.8, 20.251),
                    (-0.95, 21.266),
                ];
                let mut paper: Vec<(f64, f64)> = paper.to_vec();
                paper.sort_by(|a, b| a.0.total_cmp(&b.0));
                plot(
                    "dlsm_table3_young.svg",
                    "Apparent E, input 20 GPa (Table 3)",
                    "input nu",
                    "E (GPa)",
                    &[
                        ("Fractum, 11,000 cells".into(), pts_e),
                        ("paper".into(), paper),
                    ],
                );
                plot(
                    "dlsm_table3_poisson.svg",
                    "Apparent nu minus input nu (Table 3)",
                    "input nu",
                    "error",
                    &[("Fractum, 11,000 cells".into(), pts_nu)],
                );
            }
            "table3x" => {
                // The extreme rows again with a shorter step: Eq. 39 scales with E, but the
                // lattice's stiffness grows like λ + 2μ as ν → 0.5 or −1.
                for nu in [0.49, -0.95, -0.99] {
                    let (_, s) = run(
                        "scenes/dlsm_tensile.toml",
                        &[
                            format!("material.poisson={nu}"),
                            "time.safety=0.05".to_string(),
                        ],
                    );
                    record(
                        &format!("table3x nu={nu} safety=0.05"),
                        pick(&s, TABLE3_KEYS),
                    );
                }
            }
            "table3" => {
                let mut pts_e = Vec::new();
                let mut pts_nu = Vec::new();
                for nu in [
                    0.49, 0.45, 0.4, 0.3, 0.2, 0.1, 0.0, -0.1, -0.2, -0.3, -0.4, -0.5, -0.6, -0.7,
                    -0.8, -0.95, -0.99,
                ] {
                    // Each row at half the shipped step and at it: what the step does.
                    let refused = |e: String| json!({ "refused": e });
                    let mut s = Value::Null;
                    for (label, sets) in [
                        (
                            format!("table3 nu={nu} safety=0.165"),
                            vec![
                                format!("material.poisson={nu}"),
                                "time.safety=0.165".to_string(),
                            ],
                        ),
                        (
                            format!("table3 nu={nu}"),
                            vec![format!("material.poisson={nu}")],
                        ),
                    ] {
                        s = try_run("scenes/dlsm_tensile.toml", &sets)
                            .map_or_else(refused, |(_, s)| s);
                        record(&label, pick(&s, TABLE3_KEYS));
                    }
                    if let (Some(e), Some(p)) =
                        (s["apparent_young"].as_f64(), s["apparent_poisson"].as_f64())
                    {
                        pts_e.push((nu, e / 1e9));
                        pts_nu.push((nu, p - nu));
                    }
                }
                plot(
                    "dlsm_table3_young.svg",
                    "Apparent E (input 20 GPa)",
                    "input nu",
                    "E (GPa)",
                    &[("Fractum".into(), pts_e)],
                );
                plot(
                    "dlsm_table3_poisson.svg",
                    "Apparent nu minus input nu",
                    "input nu",
                    "error",
                    &[("Fractum".into(), pts_nu)],
                );
            }
            "waves" => {
                let mut lines = Vec::new();
                for (mode, file, col) in [
                    (
                        "tension",
                        "scenes/dlsm_wave_tension.toml",
                        "free_face_displacement",
                    ),
                    (
                        "torsion",
                        "scenes/dlsm_wave_torsion.toml",
                        "free_face_rotation",
                    ),
                ] {
                    let (r, s) = run(file, &[]);
                    record(
                        &format!("wave {mode}"),
                        pick(
                            &s,
                            &[
                                "elements",
                                "steps",
                                "dt",
                                "frequency_measured",
                                "frequency_theory",
                                "frequency_error",
                                "wall_seconds",
                            ],
                        ),
                    );
                    let pts: Vec<(f64, f64)> = columns(&r, "time", col);
                    let top = pts.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
                    lines.push((
                        format!("{mode} (normalised)"),
                        pts.into_iter().map(|(t, v)| (t * 1e3, v / top)).collect(),
                    ));
                }
                plot(
                    "dlsm_waves.svg",
                    "Free face, clamped-free cylinder",
                    "time (ms)",
                    "signal / max",
                    &lines,
                );
            }
            "brazilian" => {
                let mut lines = Vec::new();
                for arc in [0.0, 20.0] {
                    let (r, s) = run(
                        "scenes/brazilian.toml",
                        &[
                            "loading.load_by=\"elements\"".to_string(),
                            format!("loading.arc_degrees={arc}"),
                        ],
                    );
                    record(&format!("brazilian arc={arc}"), pick(&s, BRAZILIAN_KEYS));
                    lines.push((format!("2 alpha = {arc} degrees"), force_curve(&r)));
                }
                plot(
                    "dlsm_brazilian.svg",
                    "Brazilian test",
                    "diametral strain (1e-3)",
                    "force (kN)",
                    &lines,
                );
            }
            "platens" => {
                // the disc between rigid flat platens and curved jaws of radius
                // 1.5 R, and under a uniform pressure over 20° arcs, at 3000 cells and at the
                // paper's size. The jaws go further (their contact softens the start).
                let loadings: [(&str, &[&str]); 3] = [
                    ("flat platens", &["loading.load_by=\"flat_platens\""]),
                    (
                        "curved jaws",
                        &[
                            "loading.load_by=\"curved_jaws\"",
                            "loading.end_strain=0.008",
                        ],
                    ),
                    (
                        "20 degree arc pressure",
                        &["loading.load_by=\"arc_pressure\"", "loading.arc_degrees=20"],
                    ),
                ];
                let mut lines = Vec::new();
                let mut cracks = Vec::new();
                for elements in [3000, 20000] {
                    for (label, sets) in loadings {
                        let mut sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
                        sets.push(format!("sample.elements={elements}"));
                        let (r, s) = run("scenes/brazilian.toml", &sets);
                        record(
                            &format!("brazilian {label}, {elements} elements"),
                            pick(&s, BRAZILIAN_KEYS),
                        );
                        let name = format!("{label}, {} elements", s["elements"]);
                        lines.push((name.clone(), force_curve(&r)));
                        cracks.push((
                            name,
                            r.model
                                .state
                                .break_log
                                .iter()
                                .map(|(_, p)| (p.x, p.y))
                                .collect::<Vec<_>>(),
                        ));
                    }
                }
                plot(
                    "dlsm_brazilian_platens.svg",
                    "Brazilian test: platens, jaws (Eq. 46: 62.83 kN), 20° pressure (Eq. 48: 65.43 kN)",
                    "diametral strain (1e-3: platen or jaw travel, the arcs' closure)",
                    "force (kN)",
                    &lines,
                );
                crack_map("dlsm_brazilian_platens_cracks.svg", &cracks, loadings.len());
            }
            other => eprintln!("unknown case {other}"),
        }
    }
}

/// What a Table 3 run records.
const TABLE3_KEYS: &[&str] = &[
    "elements",
    "steps",
    "dt",
    "apparent_young",
    "apparent_poisson",
    "wall_seconds",
    "error",
    "refused",
];

/// What a Brazilian run records.
const BRAZILIAN_KEYS: &[&str] = &[
    "elements",
    "steps",
    "dt",
    "peak_force",
    "theory_force",
    "force_ratio",
    "first_break_time",
    "first_break_position",
    "crack_start_offset",
    "main_crack_start_offset",
    "crack_band_fraction",
    "broken_contacts",
    "load_by",
    "contact_arc_degrees",
    "theory_force_arc",
    "force_ratio_arc",
    "servo_stiffness",
    "held_moment_ratio",
    "wall_seconds",
];

/// Force (kN) against diametral strain (1e-3) of a Brazilian run.
fn force_curve(r: &DlsmRun) -> Vec<(f64, f64)> {
    columns(r, "diametral_strain", "force")
        .into_iter()
        .map(|(e, f)| (e * 1e3, f / 1e3))
        .collect()
}

/// Where the contacts broke, in the disc's plane (x to the right, y up), one panel per run,
/// `columns` panels a row: the first tenth of the breaks in red, the rest in grey, a 2-pixel
/// square per pixel reached. Written by hand: as plotters' circles, the six Brazilian runs'
/// 97,000 breaks made a 9 MB file.
fn crack_map(file: &str, runs: &[(String, Vec<(f64, f64)>)], columns: usize) {
    use std::collections::BTreeSet;
    use std::fmt::Write as _;
    // A panel: 440 x 460 px, the square [-0.105, 0.105] m² on 400 px.
    let (width, height, side, half) = (440usize, 460usize, 400.0, 0.105);
    let rows = runs.len().div_ceil(columns);
    let mut svg = String::new();
    let _ = write!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n<rect width=\"{w}\" height=\"{h}\" fill=\"white\"/>\n",
        w = width * columns,
        h = height * rows
    );
    for (k, (label, pts)) in runs.iter().enumerate() {
        let (ox, oy) = (
            (k % columns * width) as f64 + 20.0,
            (k / columns * height) as f64 + 45.0,
        );
        let px = |x: f64, y: f64| {
            (
                (ox + (x + half) / (2.0 * half) * side).round() as i64,
                (oy + (half - y) / (2.0 * half) * side).round() as i64,
            )
        };
        let (cx, cy) = px(0.0, 0.0);
        let r = 0.1 / (2.0 * half) * side;
        let _ = write!(
            svg,
            "<text x=\"{}\" y=\"{}\" font-family=\"sans-serif\" font-size=\"15\" text-anchor=\"middle\">{label}: {} broken contacts</text>\n<circle cx=\"{cx}\" cy=\"{cy}\" r=\"{r:.1}\" fill=\"none\" stroke=\"black\"/>\n<line x1=\"{cx}\" y1=\"{}\" x2=\"{cx}\" y2=\"{}\" stroke=\"#bbbbbb\" stroke-dasharray=\"4 4\"/>\n",
            ox + side / 2.0,
            oy - 20.0,
            pts.len(),
            cy as f64 - r,
            cy as f64 + r,
        );
        // A 50 mm scale bar under the disc.
        let (x0, y0) = px(-0.1, -0.103);
        let (x1, _) = px(-0.05, -0.103);
        let _ = write!(
            svg,
            "<line x1=\"{x0}\" y1=\"{y0}\" x2=\"{x1}\" y2=\"{y0}\" stroke=\"black\" stroke-width=\"2\"/>\n<text x=\"{x0}\" y=\"{}\" font-family=\"sans-serif\" font-size=\"12\">50 mm</text>\n",
            y0 + 14
        );
        let first = pts.len().div_ceil(10);
        for (set, colour) in [(&pts[first..], "#969696"), (&pts[..first], "red")] {
            let pixels: BTreeSet<(i64, i64)> = set.iter().map(|&(x, y)| px(x, y)).collect();
            let _ = write!(svg, "<path fill=\"{colour}\" d=\"");
            for (x, y) in pixels {
                let _ = write!(svg, "M{x} {y}h2v2h-2z");
            }
            svg.push_str("\"/>\n");
        }
    }
    svg.push_str("</svg>\n");
    std::fs::write(repo().join("docs/img").join(file), svg).unwrap();
}

/// `ablate LABEL SCENE KEY=VALUE...`: one tension run with the given overrides, recorded
/// with the summary's fitted readings and the paper's (Section 8.2.1: ⟨E⟩ is the stress of
/// Eq. 41 over the imposed elongation, here read at the end of the run from the face sets),
/// and the largest kinetic energy of the run.
fn ablate(args: &[String]) {
    let (label, file, sets) = (&args[0], &args[1], &args[2..]);
    let s = match try_run(file, sets) {
        Ok((r, mut s)) => {
            let col = |c: &str| r.series.column(c).unwrap_or_default();
            if let Ok(dir) = std::env::var("ABLATE_SERIES") {
                let mut out = r.series.columns.join(",") + "\n";
                for row in &r.series.rows {
                    let cells: Vec<String> = row.iter().map(|v| format!("{v:e}")).collect();
                    out += &(cells.join(",") + "\n");
                }
                std::fs::write(format!("{dir}/{label}.csv"), out).unwrap();
            }
            let (stress, faces, lat_faces, strain, ly, lz, ke) = (
                col("stress"),
                col("strain_faces"),
                col("lateral_strain_faces"),
                col("strain"),
                col("lateral_strain_y"),
                col("lateral_strain_z"),
                col("kinetic_energy"),
            );
            if let (Some(&sg), Some(&ef), Some(&lf), Some(&ex), Some(&y), Some(&z)) = (
                stress.last(),
                faces.last(),
                lat_faces.last(),
                strain.last(),
                ly.last(),
                lz.last(),
            ) {
                s["young_secant_faces"] = json!(sg / ef);
                s["poisson_secant_faces"] = json!(-lf / ef);
                s["young_secant_gauge"] = json!(sg / ex);
                s["poisson_secant_gauge"] = json!(-0.5 * (y + z) / ex);
                s["strain_faces_final"] = json!(ef);
            }
            s["kinetic_energy_max"] = json!(ke.iter().copied().fold(0.0, f64::max));
            // Free vibration: the total energy's largest rise over its start, and when it
            // first doubled (the scheme can only take energy out).
            let (t, total) = (col("time"), col("total_energy"));
            if let Some(&e0) = total.first() {
                let top = total.iter().copied().fold(f64::MIN, f64::max);
                s["energy_ratio_max"] = json!(top / e0);
                s["energy_ratio_final"] = json!(total.last().unwrap() / e0);
                s["time_final"] = json!(t.last());
                if let Some(k) = total.iter().position(|&e| e > 2.0 * e0) {
                    s["energy_doubled_at"] = json!(t[k]);
                }
            }
            s
        }
        Err(e) => json!({ "refused": e }),
    };
    record(
        label,
        pick(
            &s,
            &[
                "elements",
                "steps",
                "dt",
                "dt_critical",
                "dt_rotational",
                "phi",
                "apparent_young",
                "apparent_poisson",
                "young_secant_faces",
                "poisson_secant_faces",
                "young_secant_gauge",
                "poisson_secant_gauge",
                "strain_faces_final",
                "kinetic_energy_max",
                "kinetic_energy_final",
                "energy_ratio_max",
                "energy_ratio_final",
                "energy_doubled_at",
                "time_final",
                "frequency_measured",
                "frequency_theory",
                "wall_seconds",
                "error",
                "refused",
            ],
        ),
    );
}

/// `uniform SCENE KEY=VALUE...`: the tension scene's lattice under the exact uniaxial-stress
/// field (ε_xx = e, ε_yy = ε_zz = −ν e on every seed, rotations none): the largest residual
/// force on an element that is not driven, over the force S E e of a mean contact, and the
/// stress of Eq. 41 that field gives over E e. Uniform strain is reproduced exactly by the
/// least squares, so the field is an equilibrium when the contact law is consistent.
fn uniform(args: &[String]) {
    use fractum::models::dlsm::loading::DlsmLoading;
    use fractum::state::Forces;
    let (file, sets) = (&args[0], &args[1..]);
    let scene = Scene::load(&repo().join(file), sets).expect("scene");
    let run = DlsmRun::new(scene, 2, &mut |_| {}).expect("build");
    let m = &run.model;
    let DlsmLoading::Tension(t) = &m.state.loading else {
        panic!("a tension scene")
    };
    let (e, nu, young) = (1e-6, m.bonds.poisson, m.bonds.young);
    let centre: Vec3 = m.reference.iter().sum::<Vec3>() / m.reference.len() as f64;
    let mut b = m.state.bodies.clone();
    for (p, r) in b.pos.iter_mut().zip(&m.reference) {
        let d = r - centre;
        *p = r + Vec3::new(e * d.x, -nu * e * d.y, -nu * e * d.z);
    }
    let mut bonds = m.bonds.clone();
    let mut f = Forces::new(b.len());
    bonds.evaluate(&b, &mut f, None);
    let mut driven = vec![false; b.len()];
    for k in 0..2 {
        for &i in &t.faces[k] {
            driven[i as usize] = true;
        }
    }
    let mean_area = bonds.area.iter().sum::<f64>() / bonds.area.len() as f64;
    let unit = mean_area * young * e;
    let (mut worst, mut rms, mut count) = (0.0f64, 0.0, 0);
    for (force, _) in f.force.iter().zip(&driven).filter(|(_, d)| !**d) {
        let r = force.norm() / unit;
        worst = worst.max(r);
        rms += r * r;
        count += 1;
    }
    let mut reaction = 0.0;
    for (k, sign) in [(0usize, 1.0), (1, -1.0)] {
        for &i in &t.faces[k] {
            reaction += sign * f.force[i as usize].x;
        }
    }
    let stress = reaction / (2.0 * t.section);
    record(
        &format!("uniform {}", sets.join(" ")),
        json!({
            "elements": b.len(),
            "residual_max": worst,
            "residual_rms": (rms / count.max(1) as f64).sqrt(),
            "stress_over_E_e": stress / (young * e),
        }),
    );
}
