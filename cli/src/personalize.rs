//! `likeness personalize` and `likeness evaluate`.

use crate::CliResult;
use crate::info::read_session;
use likeness::io::obj_writer::write_obj;
use likeness::personalize::evaluation::{ExpressionError, MeanErrors, evaluate, mean_errors};
use likeness::personalize::lambda_selection::LambdaChoice;
use likeness::personalize::personalization::lambda_sweep;
use likeness::personalize::{FitFrames, Method, personalize};
use likeness::{Blendshape, Session};
use serde::Serialize;
use serde_json::{Map, Value, json};
use std::path::Path;
use std::time::Instant;

/// Writes the personalized neutral and the 52 shapes as OBJ files named
/// after ARKit's names (`neutral.obj`, `eyeBlinkLeft.obj`, …) into `out`.
pub fn personalize_command(file: &Path, method: Method, out: &Path) -> CliResult {
    let session = read_session(file)?;
    let started = Instant::now();
    let result = personalize(&session, method)?;
    let elapsed = started.elapsed();
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let comment = format!("Likeness {} personalization of {}", method, file.display());
    let write = |name: &str, positions: &[glam::DVec3]| {
        let path = out.join(format!("{name}.obj"));
        write_obj(&path, &session.topology, positions, &comment)
            .map_err(|e| format!("{}: {e}", path.display()))
    };
    write("neutral", result.shapes.neutral())?;
    for shape in Blendshape::ALL {
        write(shape.name(), &result.shapes.shape(shape))?;
    }
    eprintln!(
        "wrote 53 OBJ files to {} ({} method, {:.1} ms)",
        out.display(),
        method,
        elapsed.as_secs_f64() * 1e3
    );
    if !result.generic_fallback.is_empty() {
        let names: Vec<_> = result.generic_fallback.iter().map(|s| s.name()).collect();
        eprintln!("not captured, generic shape used: {}", names.join(", "));
    }
    if let Some(choice) = &result.lambda_choice {
        eprintln!("regularization {}", describe_choice(choice));
    }
    Ok(())
}

/// `λ = 2.2e-5 (gcv)`, with the bound it stopped at, if any.
fn describe_choice(choice: &LambdaChoice) -> String {
    let bound = match choice.at_bound {
        Some(bound) => format!(
            ", at the {} bound of {:e}…{:e}",
            bound.name(),
            choice.range[0],
            choice.range[1]
        ),
        None => String::new(),
    };
    format!("λ = {:.3e} ({}{bound})", choice.lambda, choice.rule)
}

/// One method's results over the sessions evaluated.
struct MethodRuns {
    method: Method,
    means: Vec<MeanErrors>,
    times: Vec<f64>,
    choices: Vec<LambdaChoice>,
}

impl MethodRuns {
    fn new(method: Method) -> MethodRuns {
        MethodRuns {
            method,
            means: Vec::new(),
            times: Vec::new(),
            choices: Vec::new(),
        }
    }
}

/// Per-method results over all sessions.
#[derive(Default, Serialize)]
struct MethodReport {
    rmse_mm: f64,
    max_mm: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    truth_rmse_mm: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    truth_max_mm: Option<f64>,
    /// The λ of each session (fits only).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    lambda: Vec<f64>,
    /// How λ was chosen (fits only): `fixed`, `gcv`, ….
    #[serde(skip_serializing_if = "Option::is_none")]
    lambda_rule: Option<String>,
    /// The range of λ searched (fits only).
    #[serde(skip_serializing_if = "Option::is_none")]
    lambda_range: Option<[f64; 2]>,
    /// For each session, the end of the searched range the choice stopped
    /// at (`lower`, `upper`) or null (fits only).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    lambda_at_bound: Vec<Option<String>>,
}

/// λ values of the accuracy study: the paper's 1 down to 10⁻⁶ (two decades
/// past `paper-cv`'s grid, to show where the optimum lies).
pub const STUDY_GRID: [f64; 7] = [1.0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6];

/// One method run on one session: its blendshapes, its errors on each test
/// expression and the median time of the runs.
pub struct MethodRun {
    /// The method.
    pub method: Method,
    /// What it computed.
    pub personalized: likeness::personalize::personalization::Personalized,
    /// Its errors on each test expression (§4.1).
    pub errors: Vec<ExpressionError>,
    /// Median wall time of one run (ms).
    pub ms: f64,
}

/// Every method and the λ study on one session.
pub struct SessionEvaluation {
    /// One run per method, in the order of [`Method::ALL`].
    pub runs: Vec<MethodRun>,
    /// The paper's fit (captures) for each λ of [`STUDY_GRID`]: the means
    /// over the test expressions.
    pub curve: Vec<MeanErrors>,
}

/// How often each method is run to take the median time.
const TIMING_RUNS: usize = 5;

fn timed(
    session: &Session,
    method: Method,
    runs: usize,
) -> Result<(likeness::personalize::personalization::Personalized, f64), Box<dyn std::error::Error>>
{
    let mut times = Vec::with_capacity(runs);
    let mut result = None;
    for _ in 0..runs.max(1) {
        let started = Instant::now();
        let r = personalize(session, method)?;
        times.push(started.elapsed().as_secs_f64() * 1e3);
        result = Some(r);
    }
    times.sort_by(f64::total_cmp);
    let result = result.ok_or("no run")?;
    Ok((result, times[times.len() / 2]))
}

/// Runs every method (each `timing_runs` times, for the median time) and
/// the λ study on `session` (`name` in messages); `step` is called after
/// each method.
pub fn evaluate_session(
    name: &str,
    session: &Session,
    timing_runs: usize,
    step: &dyn Fn(),
) -> Result<SessionEvaluation, Box<dyn std::error::Error>> {
    if session.tests.is_empty() {
        return Err(format!("{name}: the session has no test expressions to evaluate on").into());
    }
    let mut runs = Vec::with_capacity(Method::ALL.len());
    for method in Method::ALL {
        let (personalized, ms) = timed(session, method, timing_runs)?;
        runs.push(MethodRun {
            method,
            errors: evaluate(&personalized.shapes, session),
            personalized,
            ms,
        });
        step();
    }
    let sweep = lambda_sweep(session, FitFrames::Captures, &STUDY_GRID)?;
    let curve = sweep
        .iter()
        .map(|fit| mean_errors(&evaluate(&fit.shapes, session)))
        .collect();
    Ok(SessionEvaluation { runs, curve })
}

/// Evaluates every method on every session's test expressions (§4.1).
pub fn evaluate_command(files: &[std::path::PathBuf], json_out: bool) -> CliResult {
    if files.is_empty() {
        return Err("evaluate needs at least one session file".into());
    }
    let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    let report = evaluation_report(&names, &|i| read_session(&files[i]))?;
    if json_out {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_table(&report);
    }
    Ok(())
}

/// Loads the `i`-th session of an evaluation.
pub type Loader<'a> = dyn Fn(usize) -> Result<Session, Box<dyn std::error::Error>> + 'a;

/// Runs every method on every session (`load(i)` for each of `names`) and
/// builds the report that `evaluate --json` prints.
pub fn evaluation_report(
    names: &[String],
    load: &Loader,
) -> Result<Value, Box<dyn std::error::Error>> {
    let progress = crate::progress::bar("evaluating", (names.len() * Method::ALL.len()) as u64);
    let mut evaluations = Vec::with_capacity(names.len());
    for (i, name) in names.iter().enumerate() {
        let session = load(i)?;
        let evaluation = evaluate_session(name, &session, TIMING_RUNS, &|| progress.inc(1))?;
        evaluations.push(summarize_session(&evaluation));
    }
    progress.finish_and_clear();
    Ok(report_json(names, &evaluations)?)
}

/// What the report of several sessions keeps of each: per method the means,
/// the time and the λ choice; the λ study's means.
pub struct SessionSummary {
    methods: Vec<(Method, MeanErrors, f64, Option<LambdaChoice>)>,
    curve: Vec<MeanErrors>,
}

/// Keeps what [`report_json`] needs of a session's evaluation.
pub fn summarize_session(evaluation: &SessionEvaluation) -> SessionSummary {
    SessionSummary {
        methods: evaluation
            .runs
            .iter()
            .map(|r| {
                (
                    r.method,
                    mean_errors(&r.errors),
                    r.ms,
                    r.personalized.lambda_choice.clone(),
                )
            })
            .collect(),
        curve: evaluation.curve.clone(),
    }
}

/// The object `evaluate --json` prints for the sessions `names`, from their
/// summaries: each method's means over the sessions, the λ study, the
/// ratios of the paper's §4.1 and the median times.
pub fn report_json(
    names: &[String],
    sessions: &[SessionSummary],
) -> Result<Value, serde_json::Error> {
    let mut per_method: Vec<MethodRuns> = Method::ALL.iter().map(|m| MethodRuns::new(*m)).collect();
    let mut curve: Vec<Vec<MeanErrors>> = vec![Vec::new(); STUDY_GRID.len()];
    for session in sessions {
        for (runs, (method, means, ms, choice)) in per_method.iter_mut().zip(&session.methods) {
            debug_assert_eq!(runs.method, *method);
            runs.means.push(*means);
            runs.times.push(*ms);
            runs.choices.extend(choice.clone());
        }
        for (k, means) in session.curve.iter().enumerate() {
            curve[k].push(*means);
        }
    }
    let mut methods = Map::new();
    let mut timings = Map::new();
    for MethodRuns {
        method,
        means,
        times,
        choices,
    } in &per_method
    {
        let n = means.len() as f64;
        let avg = |f: &dyn Fn(&MeanErrors) -> f64| means.iter().map(f).sum::<f64>() / n;
        let truth = means.iter().all(|m| m.truth_rmse_mm.is_some());
        let report = MethodReport {
            rmse_mm: avg(&|m| m.rmse_mm),
            max_mm: avg(&|m| m.max_mm),
            truth_rmse_mm: truth.then(|| avg(&|m| m.truth_rmse_mm.unwrap_or(0.0))),
            truth_max_mm: truth.then(|| avg(&|m| m.truth_max_mm.unwrap_or(0.0))),
            lambda: choices.iter().map(|c| c.lambda).collect(),
            lambda_rule: choices.first().map(|c| c.rule.to_string()),
            lambda_range: choices.first().map(|c| c.range),
            lambda_at_bound: choices
                .iter()
                .map(|c| c.at_bound.map(|b| b.name().to_string()))
                .collect(),
        };
        methods.insert(method.to_string(), serde_json::to_value(report)?);
        let mut sorted = times.clone();
        sorted.sort_by(f64::total_cmp);
        timings.insert(method.to_string(), json!(sorted[sorted.len() / 2]));
    }
    let get = |m: &str, k: &str| {
        methods
            .get(m)
            .and_then(|v| v.get(k))
            .and_then(Value::as_f64)
            .unwrap_or(f64::NAN)
    };
    let ratios = json!({
        "rmse_paper_over_ebfr": get("paper", "rmse_mm") / get("ebfr", "rmse_mm"),
        "rmse_paper_over_dt": get("paper", "rmse_mm") / get("dt", "rmse_mm"),
        "max_paper_over_ebfr": get("paper", "max_mm") / get("ebfr", "max_mm"),
        "max_paper_over_dt": get("paper", "max_mm") / get("dt", "max_mm"),
        "rmse_paper_cv_over_ebfr": get("paper-cv", "rmse_mm") / get("ebfr", "rmse_mm"),
        "rmse_paper_cv_over_dt": get("paper-cv", "rmse_mm") / get("dt", "rmse_mm"),
        "max_paper_cv_over_ebfr": get("paper-cv", "max_mm") / get("ebfr", "max_mm"),
        "max_paper_cv_over_dt": get("paper-cv", "max_mm") / get("dt", "max_mm"),
    });
    let lambda_curve: Vec<Value> = STUDY_GRID
        .iter()
        .zip(&curve)
        .map(|(lambda, means)| {
            let n = means.len() as f64;
            let avg = |f: &dyn Fn(&MeanErrors) -> Option<f64>| {
                means.iter().map(f).sum::<Option<f64>>().map(|s| s / n)
            };
            json!({
                "lambda": lambda,
                "rmse_mm": avg(&|m| Some(m.rmse_mm)),
                "max_mm": avg(&|m| Some(m.max_mm)),
                "truth_rmse_mm": avg(&|m| m.truth_rmse_mm),
                "truth_max_mm": avg(&|m| m.truth_max_mm),
            })
        })
        .collect();
    Ok(json!({
        "sessions": names,
        "methods": methods,
        "lambda_curve": lambda_curve,
        "ratios": ratios,
        "timings_ms": timings,
    }))
}

/// The evaluation table for a person.
pub fn print_table(report: &Value) {
    println!(
        "{:<10} {:>10} {:>10} {:>12} {:>12} {:>10}",
        "method", "RMSE mm", "max mm", "truth RMSE", "truth max", "time ms"
    );
    for method in Method::ALL {
        let name = method.to_string();
        let m = &report["methods"][&name];
        let f = |v: &Value| v.as_f64().map_or("-".to_string(), |x| format!("{x:.3}"));
        println!(
            "{:<10} {:>10} {:>10} {:>12} {:>12} {:>10}",
            name,
            f(&m["rmse_mm"]),
            f(&m["max_mm"]),
            f(&m["truth_rmse_mm"]),
            f(&m["truth_max_mm"]),
            f(&report["timings_ms"][&name]),
        );
    }
    let sessions: Vec<&str> = report["sessions"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(Value::as_str)
        .collect();
    println!();
    for method in Method::ALL {
        let m = &report["methods"][method.name()];
        let Some(rule) = m["lambda_rule"].as_str() else {
            continue;
        };
        let lambdas: Vec<String> = m["lambda"]
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(Value::as_f64)
            .map(|l| format!("{l:.1e}"))
            .collect();
        let range = match m["lambda_range"].as_array().map(Vec::as_slice) {
            Some([lo, hi]) if lo != hi => format!(
                " (searched {:e}…{:e})",
                lo.as_f64().unwrap_or(f64::NAN),
                hi.as_f64().unwrap_or(f64::NAN)
            ),
            _ => String::new(),
        };
        println!(
            "{:<10} λ by {rule}{range}: {}",
            method.name(),
            lambdas.join(", ")
        );
        let bounds = m["lambda_at_bound"].as_array().into_iter().flatten();
        for (session, bound) in sessions.iter().zip(bounds) {
            if let Some(bound) = bound.as_str() {
                println!(
                    "           {session}: stopped at the {bound} bound of the range searched"
                );
            }
        }
    }
    println!("\nthe paper's fit for fixed λ (mean over test expressions and sessions, mm):");
    println!(
        "{:>8} {:>10} {:>10} {:>12} {:>12}",
        "λ", "RMSE", "max", "truth RMSE", "truth max"
    );
    for point in report["lambda_curve"].as_array().into_iter().flatten() {
        let f = |v: &Value| v.as_f64().map_or("-".to_string(), |x| format!("{x:.3}"));
        println!(
            "{:>8} {:>10} {:>10} {:>12} {:>12}",
            format!("{:e}", point["lambda"].as_f64().unwrap_or(f64::NAN)),
            f(&point["rmse_mm"]),
            f(&point["max_mm"]),
            f(&point["truth_rmse_mm"]),
            f(&point["truth_max_mm"]),
        );
    }
    let r = &report["ratios"];
    let f = |k: &str| r[k].as_f64().map_or("-".to_string(), |x| format!("{x:.2}"));
    println!(
        "\npaper / EBFR: RMSE {}, max {}   (the paper reports 0.58 and 0.50)",
        f("rmse_paper_over_ebfr"),
        f("max_paper_over_ebfr")
    );
    println!(
        "paper / DT:   RMSE {}, max {}   (the paper reports 0.45 and 0.38)",
        f("rmse_paper_over_dt"),
        f("max_paper_over_dt")
    );
    println!(
        "paper-cv / EBFR: RMSE {}, max {};  paper-cv / DT: RMSE {}, max {}",
        f("rmse_paper_cv_over_ebfr"),
        f("max_paper_cv_over_ebfr"),
        f("rmse_paper_cv_over_dt"),
        f("max_paper_cv_over_dt")
    );
}
