//! Reading an interchange folder into a session, one part of the layout
//! at a time: the template, the neutral scan, the captures, the tests and
//! the stream.

use super::*;

/// Reads an interchange folder (see the [module docs](super)) into a
/// session. Returns the session and warnings for the person: missing
/// template shapes, unused OBJ files.
pub fn import_folder(dir: &Path) -> Result<(Session, Vec<String>), InterchangeError> {
    let mut warnings = Vec::new();
    let (topology, template) = read_template(&dir.join("template"), &mut warnings)?;
    let neutral = read_mesh(&dir.join("neutral.obj"), &topology)?;
    let captures = read_captures(&dir.join("expressions"), &topology, &mut warnings)?;
    let tests = read_tests(&dir.join("test"), &topology, &mut warnings)?;
    let frames_csv = dir.join("frames.csv");
    let frames = if frames_csv.exists() {
        read_frames(&frames_csv)?
    } else {
        Vec::new()
    };
    let session = Session::new(SessionParts {
        device: DeviceInfo {
            model: IMPORTED_MODEL.to_string(),
            ..DeviceInfo::default()
        },
        frame_rate: frame_rate(&frames),
        topology,
        template,
        neutral,
        frames,
        captures,
        tests,
        truth: None,
    })
    .map_err(|source| InterchangeError::Session {
        path: dir.to_path_buf(),
        source,
    })?;
    Ok((session, warnings))
}

/// `template/`: the neutral, whose faces are the topology of every OBJ,
/// and one OBJ per ARKit name; a missing one is a zero delta, with a
/// warning.
fn read_template(
    template_dir: &Path,
    warnings: &mut Vec<String>,
) -> Result<(Topology, Template), InterchangeError> {
    let template_neutral_path = template_dir.join("neutral.obj");
    let template_mesh = read_storable_obj(&template_neutral_path)?;
    let topology =
        Topology::new(template_mesh.positions.len(), template_mesh.triangles).map_err(|e| {
            InterchangeError::Topology {
                path: template_neutral_path.clone(),
                message: e.to_string(),
            }
        })?;
    let template_neutral = template_mesh.positions;
    let template_files = obj_files(template_dir)?;
    let mut shapes = Vec::with_capacity(Blendshape::ALL.len());
    for shape in Blendshape::ALL {
        match shape_obj(template_dir, &template_files, shape) {
            Some(path) => shapes.push(read_mesh(&path, &topology)?),
            None => {
                warnings.push(format!(
                    "{}: missing; {shape} is taken as a zero delta",
                    template_dir.join(format!("{}.obj", shape.name())).display()
                ));
                shapes.push(template_neutral.clone());
            }
        }
    }
    let template =
        Template::new(template_neutral, shapes).map_err(|source| InterchangeError::Session {
            path: template_dir.to_path_buf(),
            source,
        })?;
    Ok((topology, template))
}

/// A key-cell error of `csv` at `row`.
fn key_error(csv: &Path, row: &WeightRow, message: String) -> InterchangeError {
    InterchangeError::Key {
        path: csv.to_path_buf(),
        line: row.line,
        column: row.key_column,
        message,
    }
}

/// Warns about each OBJ in the folder that no row of `csv` uses.
fn warn_unused(
    csv: &Path,
    files: &[ObjFile],
    used: impl Fn(&str) -> bool,
    warnings: &mut Vec<String>,
) {
    for file in files.iter().filter(|f| !used(&f.stem)) {
        warnings.push(format!(
            "{}: no row in {}; ignored",
            file.path.display(),
            csv.display()
        ));
    }
}

/// `expressions/`: one row of `weights.csv` per captured prompt, each with
/// its OBJ under any accepted spelling of the prompt.
fn read_captures(
    expr_dir: &Path,
    topology: &Topology,
    warnings: &mut Vec<String>,
) -> Result<Vec<CapturedExpression>, InterchangeError> {
    let expr_csv = expr_dir.join("weights.csv");
    let table = read_weight_table(&expr_csv, &["prompt"])?;
    let expr_files = obj_files(expr_dir)?;
    let mut captures: Vec<CapturedExpression> = Vec::with_capacity(table.rows.len());
    let mut capture_lines = Vec::with_capacity(table.rows.len());
    for row in &table.rows {
        let prompt = Blendshape::parse(&row.key).map_err(|_| {
            let message = format!(
                "{} is not one of ARKit's 52 names in any known spelling",
                Excerpt::of(&row.key)
            );
            key_error(&expr_csv, row, message)
        })?;
        if let Some((_, first)) = captures
            .iter()
            .zip(&capture_lines)
            .find(|(c, _)| c.prompt == prompt)
        {
            let message = format!("prompt {prompt} is captured twice (first on line {first})");
            return Err(key_error(&expr_csv, row, message));
        }
        let mesh =
            shape_obj(expr_dir, &expr_files, prompt).ok_or_else(|| InterchangeError::NoMesh {
                path: expr_csv.clone(),
                line: row.line,
                key: Excerpt::of(&row.key),
                mesh: expr_dir.join(format!("{}.obj", prompt.name())),
            })?;
        captures.push(CapturedExpression {
            prompt,
            frame: None,
            weights: row.weights,
            vertices: read_mesh(&mesh, topology)?,
        });
        capture_lines.push(row.line);
    }
    let used =
        |stem: &str| Blendshape::parse(stem).is_ok_and(|s| captures.iter().any(|c| c.prompt == s));
    warn_unused(&expr_csv, &expr_files, used, warnings);
    Ok(captures)
}

/// `test/` (optional): one row of `weights.csv` per test expression, each
/// with the OBJ named by its id.
fn read_tests(
    test_dir: &Path,
    topology: &Topology,
    warnings: &mut Vec<String>,
) -> Result<Vec<TestExpression>, InterchangeError> {
    let test_csv = test_dir.join("weights.csv");
    let test_files = obj_files(test_dir)?;
    let mut tests: Vec<TestExpression> = Vec::new();
    if !test_csv.exists() && test_files.is_empty() {
        return Ok(tests);
    }
    let table = read_weight_table(&test_csv, &["id"])?;
    let mut lines = Vec::new();
    for row in &table.rows {
        if let Some((_, first)) = tests.iter().zip(&lines).find(|(t, _)| t.id == row.key) {
            let message = format!(
                "id {} appears twice (first on line {first})",
                Excerpt::of(&row.key)
            );
            return Err(key_error(&test_csv, row, message));
        }
        check_id(&row.key).map_err(|e| key_error(&test_csv, row, e.to_string()))?;
        let Some(file) = test_files.iter().find(|f| f.stem == row.key) else {
            return Err(InterchangeError::NoMesh {
                path: test_csv.clone(),
                line: row.line,
                key: Excerpt::of(&row.key),
                mesh: test_dir.join(format!("{}.obj", row.key)),
            });
        };
        let mesh = file.path.clone();
        tests.push(TestExpression {
            id: row.key.clone(),
            frame: None,
            weights: row.weights,
            vertices: read_mesh(&mesh, topology)?,
        });
        lines.push(row.line);
    }
    let used = |stem: &str| tests.iter().any(|t| t.id == stem);
    warn_unused(&test_csv, &test_files, used, warnings);
    Ok(tests)
}
