//! What [`personal_avatar`](super::personal_avatar::personal_avatar) made,
//! in a few sentences for the person who asked for it (the app shows it
//! under the avatar; the command line prints its own, longer table).

use super::glb::GlbAvatar;
use super::personal_avatar::PersonalAvatar;

/// The figures the summary reports.
#[derive(Clone, Debug, PartialEq)]
struct Facts {
    avatar: String,
    vertices: usize,
    meshes: usize,
    arkit_found: usize,
    face_vertices: usize,
    residual_mean_mm: f64,
    residual_max_mm: f64,
    /// Face vertices, adjacent vertices and lid vertices repaired, when
    /// the person's shapes were implanted.
    implanted: Option<(usize, usize, usize)>,
    /// How closely the rest face follows the person's scanned neutral (mm,
    /// mean and largest), when the avatar took the person's face.
    own_face: Option<(f64, f64)>,
    /// Targets whose names read as an ARKit shape another target carries
    /// (`target_names::PassedOver`, in words).
    passed_over: Vec<String>,
    glb_bytes: usize,
}

/// A few sentences on `made` from `glb`: the avatar, the face found, what
/// was written.
pub fn avatar_summary(glb: &GlbAvatar, made: &PersonalAvatar) -> String {
    let facts = Facts {
        avatar: glb.file.display().to_string(),
        vertices: glb.avatar.vertex_count(),
        meshes: glb.avatar.meshes().len(),
        arkit_found: made.found.found(),
        face_vertices: made.registration.map.face.len(),
        residual_mean_mm: made.registration.residual_mean_mm,
        residual_max_mm: made.registration.residual_max_mm,
        implanted: made
            .implanted
            .as_ref()
            .map(|i| (i.face_vertices, i.adjacent_vertices, i.lids_repaired)),
        own_face: made
            .taken_face
            .as_ref()
            .map(|t| (t.surface_mean_mm, t.surface_p95_mm)),
        passed_over: made
            .found
            .passed_over()
            .iter()
            .map(|p| p.to_string())
            .collect(),
        glb_bytes: made.glb.len(),
    };
    describe(&facts)
}

fn describe(f: &Facts) -> String {
    let shapes = match f.implanted {
        Some((face, adjacent, lids)) => format!(
            "Your 52 shapes were implanted into {face} face vertices and blended into {adjacent} next to them{}.",
            match lids {
                0 => String::new(),
                1 => "; 1 eyelid vertex was moved out of the eyeball".to_string(),
                n => format!("; {n} eyelid vertices were moved out of the eyeballs"),
            }
        ),
        None => {
            "The avatar's own shapes were combined to approximate yours (automatic retargeting)."
                .to_string()
        }
    };
    let face = match f.own_face {
        Some((mean, p95)) => format!(
            "It has your face at rest, taken from your neutral scan (within {mean:.2} mm on average, {p95:.2} mm for 95% of it). "
        ),
        None => "It keeps its own face at rest. ".to_string(),
    };
    let names = match f.passed_over.as_slice() {
        [] => String::new(),
        passed => format!(
            " Not taken, though named for an ARKit shape: {}.",
            passed.join("; ")
        ),
    };
    format!(
        "{}: {} vertices in {} meshes, {} of ARKit's 52 shapes.{names} Face found on {} vertices (fit within {:.2} mm on average, {:.2} mm at most). {face}{shapes} GLB: {:.1} MB.",
        f.avatar,
        f.vertices,
        f.meshes,
        f.arkit_found,
        f.face_vertices,
        f.residual_mean_mm,
        f.residual_max_mm,
        f.glb_bytes as f64 / 1e6
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_summary_names_the_avatar_and_what_was_written() {
        let mut facts = Facts {
            avatar: "default avatar".into(),
            vertices: 22077,
            meshes: 6,
            arkit_found: 52,
            face_vertices: 9000,
            residual_mean_mm: 0.0412,
            residual_max_mm: 0.3,
            implanted: Some((9000, 1200, 0)),
            own_face: None,
            passed_over: Vec::new(),
            glb_bytes: 10_631_692,
        };
        let text = describe(&facts);
        assert!(text.starts_with("default avatar: 22077 vertices in 6 meshes, 52 of"));
        assert!(text.contains("(fit within 0.04 mm on average, 0.30 mm at most)"));
        assert!(text.contains("implanted into 9000 face vertices and blended into 1200 next"));
        assert!(!text.contains("eyelid"));
        assert!(!text.contains("Not taken"));
        assert!(text.contains("It keeps its own face at rest."));
        facts.own_face = Some((0.004, 0.0191));
        assert!(describe(&facts).contains("It has your face at rest, taken from your neutral scan (within 0.00 mm on average, 0.02 mm for 95% of it)."));
        assert!(text.ends_with("GLB: 10.6 MB."));
        facts.implanted = Some((9000, 1200, 3));
        assert!(describe(&facts).contains("; 3 eyelid vertices were moved"));
        facts.implanted = None;
        assert!(describe(&facts).contains("automatic retargeting"));
        facts.passed_over = vec!["mesh 0 target 3 \"AK_25_JawOpen\" reads as jawOpen".into()];
        assert!(describe(&facts).contains(
            "52 shapes. Not taken, though named for an ARKit shape: mesh 0 target 3 \"AK_25_JawOpen\" reads as jawOpen. Face found"
        ));
    }
}
