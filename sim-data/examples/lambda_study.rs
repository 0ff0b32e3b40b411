//! How well each rule for the weight λ of `E_reg` does against the best λ
//! in hindsight, on simulated subjects, in both forms a session can take:
//! as recorded (with stream meshes) and exported to an OBJ + CSV folder and
//! imported back (no stream meshes, no frame indices).
//!
//! ```text
//! cargo run --release -p likeness-sim --example lambda_study               # committed subjects 1–4
//! cargo run --release -p likeness-sim --example lambda_study -- 100 119    # fresh seeds 100–119
//! cargo run --release -p likeness-sim --example lambda_study -- 300 319 --sittings 4
//! ```
//!
//! For each subject and form it prints the λ `paper-cv` chose (by GCV;
//! `*` if at a bound of its range), the oracle λ (of a grid
//! of ten points per decade from 10⁻⁸ to 10¹, the one of least mean RMSE
//! against the simulator's noise-free test faces), the mean RMSE and mean
//! maximum error of each (mm, over the test expressions), and the ratio of
//! the chosen RMSE to the oracle's, and the time `personalize` took. The
//! imported session has no ground truth: its shapes are evaluated against
//! the original session's truth (the test weights come back bit for bit).
//! For comparison the same ratio is printed for λ chosen by the evidence
//! (`evid`) and by held-out stream frames (`hold`, sessions with stream
//! meshes only), and for `multi` with its λ (against the same oracle of the
//! captures-only fit, and against the oracle of its own fit, `m/own`),
//! then a summary per form.
//!
//! Two columns ask what any rule that sees only the captures could do.
//! `capt` is the ratio for the *capture oracle*: the λ whose fit is truest
//! at the captures themselves (least mean RMSE of `B₀ + Σ w_j B_j`, at each
//! capture's tracked weights, against the simulator's noise-free face of
//! that capture). GCV, Mallows' Cp and every cross-validation of the
//! captures estimate that error, so a rule that sees only the captures can
//! at best choose this λ. With `--sittings K` (simulated subjects), the
//! same person is simulated on K other sittings
//! ([`SimulationOptions::performance`]) and `new` is the chosen λ's RMSE on
//! their test expressions against the best λ on them, `o→new` the same for
//! the λ that was best on the session's own tests: whether the oracle is a
//! property of the person or of the 20–30 test expressions drawn.

use likeness::Session;
use likeness::personalize::evaluation::{evaluate, mean_errors, mesh_error};
use likeness::personalize::lambda_selection::LambdaRule;
use likeness::personalize::personalization::{lambda_fit, lambda_sweep};
use likeness::personalize::{FitFrames, Method, personalize};
use likeness::session::interchange::{export_folder, import_folder};
use likeness_sim::capture_session::{SAMPLE_GEOMETRY_WINDOW, SimulationOptions};
use likeness_sim::simulate_session_with;
use std::path::PathBuf;
use std::time::Instant;

/// Mean RMSE and mean maximum error (mm) of `shapes` against the truth of
/// `reference`'s test expressions.
fn truth_errors(shapes: &likeness::Blendshapes, reference: &Session) -> (f64, f64) {
    let m = mean_errors(&evaluate(shapes, reference));
    (
        m.truth_rmse_mm
            .expect("simulated sessions carry their truth"),
        m.truth_max_mm
            .expect("simulated sessions carry their truth"),
    )
}

/// One row of the study.
struct Row {
    subject: String,
    form: &'static str,
    chosen: f64,
    at_bound: bool,
    chosen_err: (f64, f64),
    oracle: f64,
    oracle_err: (f64, f64),
    evidence_ratio: f64,
    holdout_ratio: Option<f64>,
    multi_ratio: f64,
    multi_lambda: f64,
    multi_own: f64,
    capture_ratio: f64,
    new_sittings: Option<(f64, f64)>,
    ms: f64,
}

/// Mean truth RMSE (mm) of `shapes` at the captures of `reference`: each
/// capture's tracked weights against the noise-free face of that capture.
fn capture_error(shapes: &likeness::Blendshapes, reference: &Session) -> f64 {
    let truth = reference
        .truth
        .as_ref()
        .expect("simulated sessions carry their truth");
    let errors: Vec<f64> = reference
        .captures
        .iter()
        .zip(&truth.captures)
        .map(|(c, face)| mesh_error(&shapes.reconstruct(&c.weights), face).rmse_mm)
        .collect();
    errors.iter().sum::<f64>() / errors.len().max(1) as f64
}

/// Mean truth RMSE (mm) of `shapes` over the test expressions of all
/// `sittings`.
fn sittings_error(shapes: &likeness::Blendshapes, sittings: &[Session]) -> f64 {
    let errors: Vec<_> = sittings.iter().flat_map(|s| evaluate(shapes, s)).collect();
    mean_errors(&errors)
        .truth_rmse_mm
        .expect("simulated sessions carry their truth")
}

/// The index of the least value.
fn argmin(values: &[f64]) -> usize {
    (0..values.len())
        .min_by(|a, b| values[*a].total_cmp(&values[*b]))
        .unwrap_or(0)
}

/// The fine grid of the oracle: ten points per decade, 10⁻⁸ … 10¹.
fn oracle_grid() -> Vec<f64> {
    (0..=90)
        .map(|i| 10f64.powf(-8.0 + i as f64 / 10.0))
        .collect()
}

fn study(
    subject: &str,
    form: &'static str,
    session: &Session,
    reference: &Session,
    sittings: &[Session],
) -> Row {
    let started = Instant::now();
    let chosen = personalize(session, Method::PaperCv).expect("personalizes");
    let ms = started.elapsed().as_secs_f64() * 1e3;
    let choice = chosen.lambda_choice.clone().expect("a fit reports its λ");
    let chosen_err = truth_errors(&chosen.shapes, reference);
    let sweep = lambda_sweep(session, FitFrames::Captures, &oracle_grid()).expect("fits");
    let on_tests: Vec<(f64, f64)> = sweep
        .iter()
        .map(|f| truth_errors(&f.shapes, reference))
        .collect();
    let best = argmin(&on_tests.iter().map(|e| e.0).collect::<Vec<_>>());
    let (oracle, oracle_err) = (sweep[best].lambda, on_tests[best]);
    let at_captures: Vec<f64> = sweep
        .iter()
        .map(|f| capture_error(&f.shapes, reference))
        .collect();
    let capture_ratio = on_tests[argmin(&at_captures)].0 / oracle_err.0;
    let new_sittings = (!sittings.is_empty()).then(|| {
        let on_new: Vec<f64> = sweep
            .iter()
            .map(|f| sittings_error(&f.shapes, sittings))
            .collect();
        let best_new = on_new[argmin(&on_new)];
        (
            sittings_error(&chosen.shapes, sittings) / best_new,
            on_new[best] / best_new,
        )
    });
    let ratio_of = |rule: LambdaRule| {
        let (c, shapes) = lambda_fit(session, FitFrames::Captures, rule).expect("fits");
        (c.rule != LambdaRule::Fixed).then(|| truth_errors(&shapes, reference).0 / oracle_err.0)
    };
    let evidence_ratio = ratio_of(LambdaRule::Evidence).unwrap_or(f64::NAN);
    let holdout_ratio = ratio_of(LambdaRule::Holdout);
    let multi = personalize(session, Method::Multi).expect("personalizes");
    let multi_rmse = truth_errors(&multi.shapes, reference).0;
    let multi_ratio = multi_rmse / oracle_err.0;
    let multi_oracle = lambda_sweep(session, FitFrames::AroundPeaks, &oracle_grid())
        .expect("fits")
        .iter()
        .map(|f| truth_errors(&f.shapes, reference).0)
        .fold(f64::INFINITY, f64::min);
    Row {
        subject: subject.to_string(),
        form,
        chosen: choice.lambda,
        at_bound: choice.at_bound.is_some(),
        chosen_err,
        oracle,
        oracle_err,
        evidence_ratio,
        holdout_ratio,
        multi_ratio,
        multi_lambda: multi.lambda.unwrap_or(f64::NAN),
        multi_own: multi_rmse / multi_oracle,
        capture_ratio,
        new_sittings,
        ms,
    }
}

/// The session exported to a temporary folder and imported back.
fn round_trip(session: &Session, name: &str) -> Session {
    let dir: PathBuf = std::env::temp_dir().join(format!(
        "likeness-lambda-study-{}-{name}",
        std::process::id()
    ));
    export_folder(session, &dir).expect("exports");
    let (imported, _) = import_folder(&dir).expect("imports");
    let _ = std::fs::remove_dir_all(&dir);
    imported
}

fn print_row(r: &Row) {
    let f = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{x:.3}"));
    println!(
        "{:<10} {:<8} {:>9.2e}{} {:>6.3} {:>6.3} {:>9.2e} {:>6.3} {:>6.3} {:>6.3} | {:>6} {:>6} {:>6} {:>9.2e} {:>6.3} | {:>6.3} {:>6} {:>6} | {:>6.0}",
        r.subject,
        r.form,
        r.chosen,
        if r.at_bound { "*" } else { " " },
        r.chosen_err.0,
        r.chosen_err.1,
        r.oracle,
        r.oracle_err.0,
        r.oracle_err.1,
        r.chosen_err.0 / r.oracle_err.0,
        f(Some(r.evidence_ratio)),
        f(r.holdout_ratio),
        f(Some(r.multi_ratio)),
        r.multi_lambda,
        r.multi_own,
        r.capture_ratio,
        f(r.new_sittings.map(|n| n.0)),
        f(r.new_sittings.map(|n| n.1)),
        r.ms,
    );
}

fn summary(rows: &[Row], form: &str) {
    let mut ratios: Vec<f64> = rows
        .iter()
        .filter(|r| r.form == form)
        .map(|r| r.chosen_err.0 / r.oracle_err.0)
        .collect();
    if ratios.is_empty() {
        return;
    }
    ratios.sort_by(f64::total_cmp);
    let median = ratios[ratios.len() / 2];
    let worst = ratios[ratios.len() - 1];
    let within = ratios.iter().filter(|r| **r <= 1.05).count();
    let count = |f: &dyn Fn(&Row) -> Option<f64>| {
        rows.iter()
            .filter(|r| r.form == form)
            .filter_map(f)
            .filter(|x| *x <= 1.05)
            .count()
    };
    let capture_within = count(&|r| Some(r.capture_ratio));
    let new_within = count(&|r| r.new_sittings.map(|n| n.0));
    let transfer_within = count(&|r| r.new_sittings.map(|n| n.1));
    let bounds = rows.iter().filter(|r| r.form == form && r.at_bound).count();
    let mean = |f: &dyn Fn(&Row) -> f64| {
        rows.iter().filter(|r| r.form == form).map(f).sum::<f64>() / ratios.len() as f64
    };
    println!(
        "{form}: {} subjects, chosen/oracle RMSE median {median:.4}, worst {worst:.4}, {within} within 5%, {bounds} at a bound",
        ratios.len()
    );
    println!(
        "{form}: within 5% of the oracle: the capture oracle on {capture_within}; on new sittings, the chosen λ on {new_within} and the own-tests oracle on {transfer_within}"
    );
    for r in rows.iter().filter(|r| r.form == form) {
        let ratio = r.chosen_err.0 / r.oracle_err.0;
        if ratio > 1.05 {
            println!("{form}: {} is {ratio:.4} of its oracle", r.subject);
        }
    }
    println!(
        "{form}: mean truth RMSE mm: paper-cv {:.4}, oracle {:.4}, multi {:.4}; mean max mm: paper-cv {:.3}, oracle {:.3}",
        mean(&|r| r.chosen_err.0),
        mean(&|r| r.oracle_err.0),
        mean(&|r| r.multi_ratio * r.oracle_err.0),
        mean(&|r| r.chosen_err.1),
        mean(&|r| r.oracle_err.1),
    );
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut sittings = 0u64;
    if let Some(i) = args.iter().position(|a| a == "--sittings") {
        sittings = args
            .get(i + 1)
            .and_then(|k| k.parse().ok())
            .expect("--sittings K");
        args.drain(i..i + 2);
    }
    let args: Vec<u64> = args
        .iter()
        .map(|a| a.parse().expect("a seed number"))
        .collect();
    let simulate = |seed: u64, performance: Option<u64>| {
        let options = SimulationOptions {
            geometry_window: Some(SAMPLE_GEOMETRY_WINDOW),
            performance,
            ..SimulationOptions::default()
        };
        simulate_session_with(seed, options, &mut |_, _| {})
    };
    let subjects: Vec<(String, Session, u64)> = match args.as_slice() {
        [] => (1..=4)
            .map(|i| {
                let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                    .join(format!("sessions/subject-{i}.likeness"));
                let session =
                    likeness::session::file::read(&path).expect("the committed session reads");
                let seed = session.truth.as_ref().map_or(i, |t| t.seed);
                (format!("subject-{i}"), session, seed)
            })
            .collect(),
        [first, last] => (*first..=*last)
            .map(|seed| (format!("seed-{seed}"), simulate(seed, None), seed))
            .collect(),
        _ => panic!("usage: lambda_study [FIRST LAST] [--sittings K]"),
    };
    println!(
        "{:<10} {:<8} {:>10} {:>6} {:>6} {:>9} {:>6} {:>6} {:>6} | {:>6} {:>6} {:>6} {:>9} {:>6} | {:>6} {:>6} {:>6} | {:>6}",
        "subject",
        "form",
        "chosen λ",
        "RMSE",
        "max",
        "oracle λ",
        "RMSE",
        "max",
        "ratio",
        "evid",
        "hold",
        "multi",
        "multi λ",
        "m/own",
        "capt",
        "new",
        "o→new",
        "ms"
    );
    let mut rows = Vec::new();
    for (name, session, seed) in &subjects {
        // Other sittings of the same person (the committed subjects were
        // simulated from their seed too).
        let others: Vec<Session> = (1..=sittings)
            .map(|k| simulate(*seed, Some(seed * 1000 + k)))
            .collect();
        let row = study(name, "session", session, session, &others);
        print_row(&row);
        rows.push(row);
        let imported = round_trip(session, name);
        let row = study(name, "imported", &imported, session, &others);
        print_row(&row);
        rows.push(row);
    }
    println!();
    summary(&rows, "session");
    summary(&rows, "imported");
}
