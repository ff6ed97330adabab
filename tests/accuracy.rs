//! `fractum bench accuracy --quick` (docs/accuracy.md): every case at a reduced size writes its
//! rows, each with a finite error and a positive wall time, and the figure in SVG and PNG.
//! Takes about 70 s on the project's shared 2-core machine; the full sweep is a benchmark
//! (`cargo bench --bench accuracy`).

mod common;

use std::collections::BTreeMap;

/// One parsed row of accuracy_cost.csv: case, role, threads, error, wall seconds, setting.
struct Row {
    case: String,
    role: String,
    setting: String,
    threads: usize,
    error: f64,
    wall_seconds: f64,
}

fn rows(csv: &str) -> Vec<Row> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(
        header,
        [
            "case",
            "role",
            "resolution_key",
            "resolution",
            "step_key",
            "step",
            "elements",
            "runs",
            "threads",
            "error",
            "wall_seconds",
            "pareto",
            "measured",
            "reference",
            "note"
        ]
    );
    lines
        .map(|l| {
            // The note, last, is quoted and may hold commas; the other fields hold none.
            let f: Vec<&str> = l.splitn(15, ',').collect();
            Row {
                case: f[0].into(),
                role: f[1].into(),
                setting: format!("{} {}", f[3], f[5]),
                threads: f[8].parse().unwrap(),
                error: f[9]
                    .parse()
                    .unwrap_or_else(|_| panic!("no error in row `{l}`")),
                wall_seconds: f[10].parse().unwrap(),
            }
        })
        .collect()
}

#[test]
fn quick_sweep_writes_every_case_with_finite_errors_and_the_figure() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("accuracy");
    let started = std::time::Instant::now();
    let o = common::fractum(
        dir.path(),
        &[
            "bench",
            "accuracy",
            "--quick",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    eprintln!("quick sweep: {:.1} s", started.elapsed().as_secs_f64());
    let csv = std::fs::read_to_string(out.join("accuracy_cost.csv")).unwrap();
    let rows = rows(&csv);
    let cases = fractum::models::accuracy_cases();
    let mut by_case: BTreeMap<&str, Vec<&Row>> = BTreeMap::new();
    for r in &rows {
        by_case.entry(r.case.as_str()).or_default().push(r);
    }
    for case in &cases {
        let ours = by_case
            .get(case.name)
            .unwrap_or_else(|| panic!("no rows for {}: {csv}", case.name));
        // The reference run (if any), every setting on one thread and the first on two too.
        let plan = case.plan(true);
        let reference = matches!(plan.reference, fractum::accuracy::Reference::Run(_));
        assert_eq!(
            ours.len(),
            usize::from(reference) + plan.settings.len() + 1,
            "{}: {csv}",
            case.name
        );
        for r in ours {
            assert!(
                r.error.is_finite() && r.error >= 0.0,
                "{}: error {}",
                r.case,
                r.error
            );
            assert!(r.wall_seconds > 0.0, "{}: {} s", r.case, r.wall_seconds);
            if r.role == "reference" {
                assert_eq!(r.error, 0.0);
            }
        }
    }
    assert_eq!(by_case.len(), cases.len(), "{csv}");
    // dlsm and beam2d give the same numbers on any thread count, and so do two spheres: the
    // two-thread run of the first setting repeats the one-thread error exactly.
    for name in [
        "hertz_impact",
        "dlsm_tensile",
        "dlsm_wave_tension",
        "dlsm_brazilian",
        "beam2d_moduli",
        "beam2d_beta",
    ] {
        let two = by_case[name].iter().find(|r| r.threads == 2).unwrap();
        let one = by_case[name]
            .iter()
            .find(|r| r.threads == 1 && r.setting == two.setting && r.role == "sweep")
            .unwrap();
        assert_eq!(one.error, two.error, "{name}");
    }
    // The report: one line per case.
    let report = std::fs::read_to_string(out.join("accuracy_report.md")).unwrap();
    for case in &cases {
        assert!(report.contains(&format!("- **{}**", case.name)), "{report}");
    }
    let svg = std::fs::read_to_string(out.join("accuracy_cost.svg")).unwrap();
    assert!(
        svg.starts_with("<svg") && svg.contains("hertz_impact"),
        "{svg}"
    );
    let png = std::fs::read(out.join("accuracy_cost.png")).unwrap();
    assert!(png.len() > 1000 && &png[1..4] == b"PNG");
    // Nothing half-written is left behind.
    for e in std::fs::read_dir(&out).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().to_string();
        assert!(!name.ends_with(".tmp"), "{name}");
    }
}

#[test]
fn an_unknown_case_is_refused_in_one_sentence_with_exit_code_2() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("accuracy");
    let o = common::fractum(
        dir.path(),
        &[
            "bench",
            "accuracy",
            "hertz_impact",
            "brazilain",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("CASE = \"brazilain\"") && err.contains("allowed values: hertz_impact,"),
        "{err}"
    );
    assert!(
        err.contains("dlsm_brazilian") && err.contains("beam2d_beta"),
        "{err}"
    );
    assert!(!out.exists(), "no output folder for bad input");
    let o = common::fractum(dir.path(), &["bench", "accuracy", "--threads", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--threads"));
}
