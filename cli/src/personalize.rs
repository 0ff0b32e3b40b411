//! `likeness personalize`, and every method run on one session for
//! `likeness evaluate` ([`crate::evaluate`]) and the report.

use crate::CliResult;
use crate::info::read_session;
use likeness::io::obj_writer::write_obj;
use likeness::personalize::evaluation::{ExpressionError, MeanErrors, evaluate, mean_errors};
use likeness::personalize::lambda_selection::LambdaChoice;
use likeness::personalize::personalization::lambda_sweep;
use likeness::personalize::{FitFrames, Method, personalize};
use likeness::{Blendshape, Session};
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
pub const TIMING_RUNS: usize = 5;

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
