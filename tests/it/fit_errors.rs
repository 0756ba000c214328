//! Data that cannot be used, requests that make no sense and fits that do not converge each give
//! their own typed error.

use activemuscle::active::ActiveCurve;
use activemuscle::energy::GiantesioMusesti;
use activemuscle::fit::{
    fit_active_curve, fit_damage, fit_passive, Bounds, Data, Direction, FitError, FitOptions,
    FitSetup,
};

fn csv(text: &str) -> Result<Data, FitError> {
    Data::from_csv_reader(text.as_bytes(), "test.csv")
}

#[test]
fn a_good_csv_file_is_read() {
    let d = csv("lambda,P\n1.0, 0.0\n1.1,0.5\n1.2,2.0\n").unwrap();
    assert_eq!(d.lambda(), &[1.0, 1.1, 1.2]);
    assert_eq!(d.stress(), &[0.0, 0.5, 2.0]);
    assert_eq!(csv(&d.to_csv()).unwrap(), d);
}

#[test]
fn text_in_the_csv_is_reported_with_its_line() {
    match csv("lambda,P\n1.0,0.0\n1.1,abc\n") {
        Err(FitError::Csv {
            line: 3, message, ..
        }) => assert!(message.contains("abc")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn nan_in_the_csv_is_reported_with_its_line() {
    match csv("lambda,P\n1.0,0.0\n1.1,0.2\n1.2,NaN\n") {
        Err(FitError::NonFiniteData {
            location,
            column: "P",
            ..
        }) => {
            assert!(location.contains("line 4"), "{location}")
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_wrong_header_is_refused() {
    assert!(matches!(
        csv("stretch,stress\n1.0,0.0\n"),
        Err(FitError::Csv { line: 1, .. })
    ));
}

#[test]
fn a_missing_column_is_refused() {
    assert!(matches!(
        csv("lambda,P\n1.0,0.0\n1.1\n"),
        Err(FitError::Csv { line: 3, .. })
    ));
}

#[test]
fn non_positive_stretch_is_refused() {
    assert!(matches!(
        csv("lambda,P\n0.0,0.0\n1.1,0.2\n"),
        Err(FitError::NonPositiveStretch { .. })
    ));
    assert!(matches!(
        Data::new(vec![-1.0, 1.0], vec![0.0, 0.0]),
        Err(FitError::NonPositiveStretch { .. })
    ));
}

#[test]
fn decreasing_and_duplicate_stretches_are_refused() {
    match csv("lambda,P\n1.0,0.0\n1.2,0.2\n1.1,0.3\n") {
        Err(FitError::DecreasingStretch {
            location,
            lambda,
            previous,
        }) => {
            assert!(location.contains("line 4"));
            assert_eq!((lambda, previous), (1.1, 1.2));
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        Data::new(vec![1.0, 1.1, 1.1], vec![0.0, 0.1, 0.2]),
        Err(FitError::DuplicateStretch { .. })
    ));
}

#[test]
fn mismatched_columns_are_refused() {
    assert!(matches!(
        Data::new(vec![1.0, 1.1], vec![0.0]),
        Err(FitError::LengthMismatch {
            stretches: 2,
            stresses: 1
        })
    ));
}

#[test]
fn fewer_points_than_parameters_are_refused() {
    let data = Data::new(vec![1.1, 1.2], vec![0.1, 0.3]).unwrap();
    let e = GiantesioMusesti::paper();
    match fit_passive(&e, &[(Direction::Along, &data)], &FitSetup::new()) {
        Err(FitError::TooFewPoints {
            points: 2,
            parameters: 2,
        }) => {}
        other => panic!("{other:?}"),
    }
}

#[test]
fn unknown_parameters_and_starts_outside_the_bounds_are_refused() {
    let data = Data::new(vec![1.1, 1.2, 1.3], vec![0.1, 0.3, 0.8]).unwrap();
    let e = GiantesioMusesti::paper();
    let sets = [(Direction::Along, &data)];
    assert!(matches!(
        fit_passive(&e, &sets, &FitSetup::new().free(&["beta"])),
        Err(FitError::UnknownParameter { .. })
    ));
    assert!(matches!(
        fit_passive(&e, &sets, &FitSetup::new().free(&["alpha", "alpha"])),
        Err(FitError::UnknownParameter { .. })
    ));
    assert!(matches!(
        fit_passive(&e, &sets, &FitSetup::new().start("w0", 1.5)),
        Err(FitError::StartOutOfBounds { .. })
    ));
    assert!(matches!(
        fit_passive(
            &e,
            &sets,
            &FitSetup::new().bounds("alpha", Bounds::new(30.0, 40.0))
        ),
        Err(FitError::StartOutOfBounds { .. })
    ));
}

/// One iteration from a far start cannot converge: the error says so and carries the best point,
/// which is not marked converged.
#[test]
fn a_fit_that_does_not_converge_is_an_error_with_the_best_point() {
    let truth = ActiveCurve::paper();
    let lambda: Vec<f64> = (0..30).map(|i| 0.7 + i as f64 * 0.03).collect();
    let data = Data::sampled(lambda, |l| Ok(truth.value(l))).unwrap();
    let start = ActiveCurve::chapter(0.5, 1.0, 0.8, truth.parameter("p_opt").unwrap()).unwrap();
    let options = FitOptions {
        max_iterations: 1,
        ..FitOptions::default()
    };
    match fit_active_curve(&start, &data, &FitSetup::new().options(options)) {
        Err(FitError::NotConverged { best, reason, .. }) => {
            assert!(!best.converged);
            assert_eq!(best.values.len(), 3);
            assert!(best.residual_norm.is_finite());
            println!("{reason}");
        }
        other => panic!("{other:?}"),
    }
}

/// A best damage outside [0, 1] (a muscle stronger than the reference) is not reported as a plain
/// d = 0: it is held at its bound 0, and the report says where the minimum lies (d = −0.2).
#[test]
fn a_minimum_outside_the_bounds_is_reported_at_its_bound() {
    let (energy, curve) = (GiantesioMusesti::paper(), ActiveCurve::paper());
    let lambda: Vec<f64> = (0..20).map(|i| 0.8 + i as f64 * 0.03).collect();
    // 1.2 × the active stress: best d = −0.2.
    let muscle = activemuscle::Muscle::passive(energy);
    let data = Data::sampled(lambda, |l| {
        Ok(activemuscle::uniaxial::along_fibres(&muscle, l)?.stress + 1.2 * curve.value(l))
    })
    .unwrap();
    let report = fit_damage(&energy, &curve, &data, &FitSetup::new())
        .unwrap()
        .report;
    println!("{report}");
    let held = report.at_bound[0].expect("d at its bound");
    assert_eq!((held.bound, report.values[0]), (0.0, 0.0));
    assert!((held.beyond + 0.2).abs() < 1e-9, "{held:?}");
    assert!(report.standard_errors[0].is_nan());
    assert!(report.to_string().contains("at its bound 0"));
}
