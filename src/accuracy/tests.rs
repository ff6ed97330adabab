use super::*;

fn row(case: &'static str, error: Option<f64>, wall: f64) -> Row {
    Row {
        case,
        is_reference: false,
        resolution_key: None,
        step_key: "time.safety",
        setting: Setting::step(0.1),
        threads: 1,
        elements: 2,
        runs: 1,
        values: vec![("x", 1.0, 1.0)],
        error,
        wall_seconds: wall,
        pareto: false,
        note: String::new(),
    }
}

#[test]
fn the_figure_drawn_again_from_the_csv_has_the_points_of_its_rows() {
    let mut rows = vec![
        row("a", Some(0.1), 1.0),
        row("b", Some(0.5), 10.0),
        row("a", Some(0.01), 3.0),
        row("a", None, 0.5),
    ];
    rows[1].threads = 2;
    rows[3].note = "stopped, at a step too long".to_string();
    let mut reference = row("b", Some(0.0), 20.0);
    reference.is_reference = true;
    rows.push(reference);
    mark_pareto(&mut rows);
    let again = figure::curves_from_csv(&csv(&rows)).unwrap();
    let labels: Vec<&str> = again.iter().map(|c| c.label.as_str()).collect();
    assert_eq!(labels, ["a", "b"]);
    assert_eq!(again[0].points, [(1.0, 0.1, 1, true), (3.0, 0.01, 1, true)]);
    assert_eq!(again[1].points, [(10.0, 0.5, 2, true)]);
}

#[test]
fn pareto_points_are_those_no_other_row_of_the_case_beats_in_both() {
    let mut rows = vec![
        row("a", Some(0.1), 1.0),  // cheapest: Pareto
        row("a", Some(0.01), 3.0), // more accurate: Pareto
        row("a", Some(0.05), 4.0), // beaten by the second in both
        row("a", Some(0.01), 3.0), // a tie with the second: neither beats the other
        row("a", None, 0.5),       // failed: takes no part
        row("b", Some(0.5), 10.0), // another case: alone, so Pareto
    ];
    mark_pareto(&mut rows);
    let marks: Vec<bool> = rows.iter().map(|r| r.pareto).collect();
    assert_eq!(marks, [true, true, false, true, false, true]);
}

#[test]
fn the_error_is_the_worst_quantity_and_not_finite_is_none() {
    let e = relative_error(&[("a", 1.02, 1.0), ("b", 0.9, 1.0)]).unwrap();
    assert!((e - 0.1).abs() < 1e-12);
    assert_eq!(relative_error(&[("a", f64::NAN, 1.0)]), None);
    assert_eq!(relative_error(&[("a", 1.0, 0.0)]), None);
}

#[test]
fn an_unknown_case_is_refused_naming_the_allowed_values() {
    let case = |name| Case {
        name,
        title: "",
        resolution_key: None,
        step_key: "time.safety",
        target: 0.01,
        full: Plan {
            settings: vec![],
            reference: Reference::Known(""),
        },
        quick: Plan {
            settings: vec![],
            reference: Reference::Known(""),
        },
        measure: Box::new(|_, _, _| Err(Error::run("unused"))),
    };
    let cases = [case("one"), case("two")];
    let e = select(&cases, &["three".into()]).err().unwrap().to_string();
    assert_eq!(
        e,
        "command line: bench accuracy: CASE = \"three\" is not a case; allowed values: one, two"
    );
    assert_eq!(select(&cases, &[]).unwrap().len(), 2);
    assert_eq!(select(&cases, &["two".into()]).unwrap()[0].name, "two");
}

#[test]
fn quick_mode_runs_the_first_setting_on_every_thread_count_and_the_rest_on_one() {
    let case = Case {
        name: "c",
        title: "",
        resolution_key: None,
        step_key: "time.safety",
        target: 0.01,
        full: Plan {
            settings: vec![Setting::step(0.4), Setting::step(0.2)],
            reference: Reference::Run(Setting::step(0.05)),
        },
        quick: Plan {
            settings: vec![Setting::step(0.4), Setting::step(0.2)],
            reference: Reference::Run(Setting::step(0.1)),
        },
        measure: Box::new(|s, _, _| {
            Ok(Measured {
                elements: 1,
                runs: 1,
                quantities: vec![Quantity::measured("x", 1.0 + s.step)],
            })
        }),
    };
    let mut options = Options {
        quick: true,
        threads: vec![1, 2],
    };
    let count = |o: &Options| runs(&[&case], o).len();
    assert_eq!(count(&options), 1 + 2 + 1);
    options.quick = false;
    assert_eq!(count(&options), 1 + 2 * 2);
    // The errors are against the reference run: (1 + s) / 1.05 - 1.
    let rows = sweep(&[&case], &options, &mut |_| {}, &mut |_| Ok(())).unwrap();
    assert!(rows[0].is_reference && rows[0].error == Some(0.0));
    let e = rows[1].error.unwrap();
    assert!((e - (1.4 / 1.05 - 1.0)).abs() < 1e-12, "{e}");
}
