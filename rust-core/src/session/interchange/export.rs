//! Writing a session as an interchange folder.

use super::*;

/// Writes `session` as an interchange folder (see the [module docs](crate::session::interchange)),
/// creating `dir` and its subfolders if needed. Every file is written
/// atomically. `frames.csv` is written only if the session has frames, and
/// `test/` only if it has test expressions.
pub fn export_folder(session: &Session, dir: &Path) -> Result<(), InterchangeError> {
    for test in &session.tests {
        check_id(&test.id)?;
    }
    let topo = &session.topology;
    let obj = |path: PathBuf, mesh: &[Vec3], comment: &str| {
        let positions: Vec<DVec3> = mesh.iter().map(|p| p.as_dvec3()).collect();
        write_obj(&path, topo, &positions, comment).map_err(io_error(&path))
    };
    let text = |path: PathBuf, text: String| {
        write_atomically(&path, text.as_bytes()).map_err(io_error(&path))
    };
    let mkdir = |path: &Path| std::fs::create_dir_all(path).map_err(io_error(path));

    let template_dir = dir.join("template");
    mkdir(&template_dir)?;
    obj(
        template_dir.join("neutral.obj"),
        &session.template.neutral,
        "template neutral",
    )?;
    for (shape, mesh) in Blendshape::ALL.iter().zip(&session.template.shapes) {
        obj(
            template_dir.join(format!("{}.obj", shape.name())),
            mesh,
            &format!("template {shape}"),
        )?;
    }
    obj(dir.join("neutral.obj"), &session.neutral, "neutral scan")?;

    let expr_dir = dir.join("expressions");
    mkdir(&expr_dir)?;
    for c in &session.captures {
        obj(
            expr_dir.join(format!("{}.obj", c.prompt.name())),
            &c.vertices,
            &format!("captured expression {}", c.prompt),
        )?;
    }
    text(
        expr_dir.join("weights.csv"),
        weights_csv::weight_table_text(
            "prompt",
            session
                .captures
                .iter()
                .map(|c| (c.prompt.name().to_string(), &c.weights)),
        ),
    )?;

    if !session.tests.is_empty() {
        let test_dir = dir.join("test");
        mkdir(&test_dir)?;
        for t in &session.tests {
            obj(
                test_dir.join(format!("{}.obj", t.id)),
                &t.vertices,
                &format!("test expression {}", t.id),
            )?;
        }
        text(
            test_dir.join("weights.csv"),
            weights_csv::weight_table_text(
                "id",
                session.tests.iter().map(|t| (t.id.clone(), &t.weights)),
            ),
        )?;
    }

    if !session.frames.is_empty() {
        text(
            dir.join("frames.csv"),
            weights_csv::weight_table_text(
                "timestamp",
                session
                    .frames
                    .iter()
                    .map(|f| (format!("{:?}", f.timestamp), &f.weights)),
            ),
        )?;
    }
    Ok(())
}
