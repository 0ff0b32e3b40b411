//! `likeness evaluate`: every method on every session's held-out test
//! expressions (§4.1), summed up as an [`EvaluationReport`]: each method's
//! means over the sessions, the λ study, the paper's ratios and the median
//! times. `--json` prints the report as it is; without it, a table is
//! printed from the same typed report, and the HTML report
//! (`likeness report`) reads it too.

use crate::CliResult;
use crate::info::read_session;
use crate::personalize::{STUDY_GRID, SessionEvaluation, TIMING_RUNS, evaluate_session};
use likeness::Session;
use likeness::personalize::Method;
use likeness::personalize::evaluation::{MeanErrors, mean_errors};
use likeness::personalize::lambda_selection::LambdaChoice;
use serde::Serialize;
use std::collections::BTreeMap;

/// What `evaluate --json` prints. Fields are in alphabetical order, as the
/// JSON has always listed them.
#[derive(Clone, Debug, Serialize)]
pub struct EvaluationReport {
    /// The paper's fit for each λ of [`STUDY_GRID`]: means over the
    /// sessions.
    pub lambda_curve: Vec<CurvePoint>,
    /// Each method's means over the sessions, by its name.
    pub methods: BTreeMap<String, MethodReport>,
    /// The ratios of the paper's §4.1.
    pub ratios: Ratios,
    /// The sessions evaluated, as named on the command line.
    pub sessions: Vec<String>,
    /// Each method's median time of one run (ms), by its name; `None` where
    /// one run is no measurement (the HTML report).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub timings_ms: Option<BTreeMap<String, f64>>,
}

/// One method's results over all sessions.
#[derive(Clone, Debug, Default, Serialize)]
pub struct MethodReport {
    /// The λ of each session (fits only).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub lambda: Vec<f64>,
    /// For each session, the end of the searched range the choice stopped
    /// at (`lower`, `upper`) or null (fits only).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub lambda_at_bound: Vec<Option<String>>,
    /// The range of λ searched (fits only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lambda_range: Option<[f64; 2]>,
    /// How λ was chosen (fits only): `fixed`, `gcv`, ….
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lambda_rule: Option<String>,
    /// Mean over the sessions of the largest error (mm).
    pub max_mm: f64,
    /// Mean over the sessions of the RMSE (Eq. 5, mm).
    pub rmse_mm: f64,
    /// As `max_mm`, against the true face (simulated sessions only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub truth_max_mm: Option<f64>,
    /// As `rmse_mm`, against the true face (simulated sessions only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub truth_rmse_mm: Option<f64>,
}

/// The paper's fit at one λ, means over the sessions (mm); `None` where a
/// session has no such figure.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct CurvePoint {
    /// λ.
    pub lambda: f64,
    /// Largest error.
    pub max_mm: Option<f64>,
    /// RMSE.
    pub rmse_mm: Option<f64>,
    /// Largest error against the true face.
    pub truth_max_mm: Option<f64>,
    /// RMSE against the true face.
    pub truth_rmse_mm: Option<f64>,
}

/// The ratios of the means that the paper's §4.1 reports (its fit: RMSE
/// 0.58 of EBFR's and 0.45 of DT's, maximum 0.50 and 0.38), for the
/// paper's fit and for `paper-cv`; NaN (`null` in JSON) without the means.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Ratios {
    /// Maximum error: `paper-cv` over DT.
    pub max_paper_cv_over_dt: f64,
    /// Maximum error: `paper-cv` over EBFR.
    pub max_paper_cv_over_ebfr: f64,
    /// Maximum error: the paper's fit over DT.
    pub max_paper_over_dt: f64,
    /// Maximum error: the paper's fit over EBFR.
    pub max_paper_over_ebfr: f64,
    /// RMSE: `paper-cv` over DT.
    pub rmse_paper_cv_over_dt: f64,
    /// RMSE: `paper-cv` over EBFR.
    pub rmse_paper_cv_over_ebfr: f64,
    /// RMSE: the paper's fit over DT.
    pub rmse_paper_over_dt: f64,
    /// RMSE: the paper's fit over EBFR.
    pub rmse_paper_over_ebfr: f64,
}

impl Ratios {
    /// Each ratio with its JSON name and words, in the paper's order.
    pub fn rows(&self) -> [(&'static str, &'static str, f64); 8] {
        [
            (
                "rmse_paper_over_ebfr",
                "RMSE: paper / EBFR",
                self.rmse_paper_over_ebfr,
            ),
            (
                "rmse_paper_over_dt",
                "RMSE: paper / DT",
                self.rmse_paper_over_dt,
            ),
            (
                "max_paper_over_ebfr",
                "maximum: paper / EBFR",
                self.max_paper_over_ebfr,
            ),
            (
                "max_paper_over_dt",
                "maximum: paper / DT",
                self.max_paper_over_dt,
            ),
            (
                "rmse_paper_cv_over_ebfr",
                "RMSE: paper-cv / EBFR",
                self.rmse_paper_cv_over_ebfr,
            ),
            (
                "rmse_paper_cv_over_dt",
                "RMSE: paper-cv / DT",
                self.rmse_paper_cv_over_dt,
            ),
            (
                "max_paper_cv_over_ebfr",
                "maximum: paper-cv / EBFR",
                self.max_paper_cv_over_ebfr,
            ),
            (
                "max_paper_cv_over_dt",
                "maximum: paper-cv / DT",
                self.max_paper_cv_over_dt,
            ),
        ]
    }
}

impl EvaluationReport {
    /// The report of the sessions `names` from their summaries: each
    /// method's means over the sessions, the λ study, the ratios and the
    /// median times.
    pub fn new(names: &[String], sessions: &[SessionSummary]) -> EvaluationReport {
        let mut methods = BTreeMap::new();
        let mut timings = BTreeMap::new();
        for (k, method) in Method::ALL.iter().enumerate() {
            let runs: Vec<&MethodSummary> =
                sessions.iter().filter_map(|s| s.methods.get(k)).collect();
            let n = runs.len() as f64;
            let avg =
                |f: &dyn Fn(&MeanErrors) -> f64| runs.iter().map(|r| f(&r.means)).sum::<f64>() / n;
            let truth = runs.iter().all(|r| r.means.truth_rmse_mm.is_some());
            let choices: Vec<&LambdaChoice> =
                runs.iter().filter_map(|r| r.choice.as_ref()).collect();
            methods.insert(
                method.to_string(),
                MethodReport {
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
                },
            );
            let mut times: Vec<f64> = runs.iter().map(|r| r.ms).collect();
            times.sort_by(f64::total_cmp);
            if let Some(median) = times.get(times.len() / 2) {
                timings.insert(method.to_string(), *median);
            }
        }
        let mean =
            |m: Method, f: fn(&MethodReport) -> f64| methods.get(m.name()).map_or(f64::NAN, f);
        let (rmse, max) = (|r: &MethodReport| r.rmse_mm, |r: &MethodReport| r.max_mm);
        let ratios = Ratios {
            rmse_paper_over_ebfr: mean(Method::Paper, rmse) / mean(Method::Ebfr, rmse),
            rmse_paper_over_dt: mean(Method::Paper, rmse) / mean(Method::Dt, rmse),
            max_paper_over_ebfr: mean(Method::Paper, max) / mean(Method::Ebfr, max),
            max_paper_over_dt: mean(Method::Paper, max) / mean(Method::Dt, max),
            rmse_paper_cv_over_ebfr: mean(Method::PaperCv, rmse) / mean(Method::Ebfr, rmse),
            rmse_paper_cv_over_dt: mean(Method::PaperCv, rmse) / mean(Method::Dt, rmse),
            max_paper_cv_over_ebfr: mean(Method::PaperCv, max) / mean(Method::Ebfr, max),
            max_paper_cv_over_dt: mean(Method::PaperCv, max) / mean(Method::Dt, max),
        };
        let lambda_curve = STUDY_GRID
            .iter()
            .enumerate()
            .map(|(k, &lambda)| {
                let means: Vec<&MeanErrors> =
                    sessions.iter().filter_map(|s| s.curve.get(k)).collect();
                let n = means.len() as f64;
                let avg = |f: &dyn Fn(&MeanErrors) -> Option<f64>| {
                    means
                        .iter()
                        .map(|m| f(m))
                        .sum::<Option<f64>>()
                        .map(|s| s / n)
                };
                CurvePoint {
                    lambda,
                    rmse_mm: avg(&|m| Some(m.rmse_mm)),
                    max_mm: avg(&|m| Some(m.max_mm)),
                    truth_rmse_mm: avg(&|m| m.truth_rmse_mm),
                    truth_max_mm: avg(&|m| m.truth_max_mm),
                }
            })
            .collect();
        EvaluationReport {
            lambda_curve,
            methods,
            ratios,
            sessions: names.to_vec(),
            timings_ms: Some(timings),
        }
    }

    /// The means of `method`.
    pub fn method(&self, method: Method) -> Option<&MethodReport> {
        self.methods.get(method.name())
    }
}

/// One method's part of a [`SessionSummary`].
pub struct MethodSummary {
    /// Its means over the session's test expressions.
    pub means: MeanErrors,
    /// The median time of one run (ms).
    pub ms: f64,
    /// How λ was chosen, for the fits.
    pub choice: Option<LambdaChoice>,
}

/// What the report of several sessions keeps of each: per method (in the
/// order of [`Method::ALL`]) the means, the time and the λ choice; the λ
/// study's means.
pub struct SessionSummary {
    methods: Vec<MethodSummary>,
    curve: Vec<MeanErrors>,
}

/// Keeps what [`EvaluationReport::new`] needs of a session's evaluation.
pub fn summarize_session(evaluation: &SessionEvaluation) -> SessionSummary {
    SessionSummary {
        methods: evaluation
            .runs
            .iter()
            .map(|r| MethodSummary {
                means: mean_errors(&r.errors),
                ms: r.ms,
                choice: r.personalized.lambda_choice.clone(),
            })
            .collect(),
        curve: evaluation.curve.clone(),
    }
}

/// Loads the `i`-th session of an evaluation.
pub type Loader<'a> = dyn Fn(usize) -> Result<Session, Box<dyn std::error::Error>> + 'a;

/// Runs every method on every session (`load(i)` for each of `names`) and
/// builds the report that `evaluate --json` prints.
pub fn evaluation_report(
    names: &[String],
    load: &Loader,
) -> Result<EvaluationReport, Box<dyn std::error::Error>> {
    let progress = crate::progress::bar("evaluating", (names.len() * Method::ALL.len()) as u64);
    let mut evaluations = Vec::with_capacity(names.len());
    for (i, name) in names.iter().enumerate() {
        let session = load(i)?;
        let evaluation = evaluate_session(name, &session, TIMING_RUNS, &|| progress.inc(1))?;
        evaluations.push(summarize_session(&evaluation));
    }
    progress.finish_and_clear();
    Ok(EvaluationReport::new(names, &evaluations))
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

/// `x` to `digits` decimals, or `-`.
fn figure(x: Option<f64>, digits: usize) -> String {
    x.filter(|x| x.is_finite())
        .map_or("-".to_string(), |x| format!("{x:.digits$}"))
}

/// The evaluation table for a person.
pub fn print_table(report: &EvaluationReport) {
    println!(
        "{:<10} {:>10} {:>10} {:>12} {:>12} {:>10}",
        "method", "RMSE mm", "max mm", "truth RMSE", "truth max", "time ms"
    );
    for method in Method::ALL {
        let m = report.method(method);
        println!(
            "{:<10} {:>10} {:>10} {:>12} {:>12} {:>10}",
            method.name(),
            figure(m.map(|m| m.rmse_mm), 3),
            figure(m.map(|m| m.max_mm), 3),
            figure(m.and_then(|m| m.truth_rmse_mm), 3),
            figure(m.and_then(|m| m.truth_max_mm), 3),
            figure(
                report
                    .timings_ms
                    .as_ref()
                    .and_then(|t| t.get(method.name()).copied()),
                3
            ),
        );
    }
    println!();
    for method in Method::ALL {
        let Some(m) = report.method(method) else {
            continue;
        };
        let Some(rule) = &m.lambda_rule else {
            continue;
        };
        let lambdas: Vec<String> = m.lambda.iter().map(|l| format!("{l:.1e}")).collect();
        let range = match m.lambda_range {
            Some([lo, hi]) if lo != hi => format!(" (searched {lo:e}…{hi:e})"),
            _ => String::new(),
        };
        println!(
            "{:<10} λ by {rule}{range}: {}",
            method.name(),
            lambdas.join(", ")
        );
        for (session, bound) in report.sessions.iter().zip(&m.lambda_at_bound) {
            if let Some(bound) = bound {
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
    for point in &report.lambda_curve {
        println!(
            "{:>8} {:>10} {:>10} {:>12} {:>12}",
            format!("{:e}", point.lambda),
            figure(point.rmse_mm, 3),
            figure(point.max_mm, 3),
            figure(point.truth_rmse_mm, 3),
            figure(point.truth_max_mm, 3),
        );
    }
    let r = &report.ratios;
    let f = |x: f64| figure(Some(x), 2);
    println!(
        "\npaper / EBFR: RMSE {}, max {}   (the paper reports 0.58 and 0.50)",
        f(r.rmse_paper_over_ebfr),
        f(r.max_paper_over_ebfr)
    );
    println!(
        "paper / DT:   RMSE {}, max {}   (the paper reports 0.45 and 0.38)",
        f(r.rmse_paper_over_dt),
        f(r.max_paper_over_dt)
    );
    println!(
        "paper-cv / EBFR: RMSE {}, max {};  paper-cv / DT: RMSE {}, max {}",
        f(r.rmse_paper_cv_over_ebfr),
        f(r.max_paper_cv_over_ebfr),
        f(r.rmse_paper_cv_over_dt),
        f(r.max_paper_cv_over_dt)
    );
}
