//! What `likeness avatar` reports: the summary `--json` prints, and the
//! same read aloud on the terminal.

use likeness::avatar::target_names::PassedOver;
use serde::Serialize;
use std::path::Path;

/// A target passed over for another of the same ARKit shape.
#[derive(Serialize)]
pub(crate) struct PassedOverSummary {
    pub(crate) mesh: usize,
    pub(crate) target: usize,
    pub(crate) name: String,
    pub(crate) shape: &'static str,
    /// The target taken instead (index within the mesh) and its name.
    pub(crate) taken_target: usize,
    pub(crate) taken_name: String,
    pub(crate) why: String,
}

impl From<&PassedOver> for PassedOverSummary {
    fn from(p: &PassedOver) -> Self {
        PassedOverSummary {
            mesh: p.mesh,
            target: p.target.0,
            name: p.target.1.clone(),
            shape: p.shape.name(),
            taken_target: p.taken.0,
            taken_name: p.taken.1.clone(),
            why: p.why.to_string(),
        }
    }
}

/// The summary `--json` prints.
#[derive(Serialize)]
pub(crate) struct Summary {
    pub(crate) avatar: String,
    pub(crate) out: String,
    /// What the shapes in `out` are.
    pub(crate) shapes: &'static str,
    pub(crate) method: String,
    pub(crate) vertices: usize,
    pub(crate) morph_targets: usize,
    pub(crate) arkit_found: usize,
    pub(crate) arkit_missing: Vec<&'static str>,
    /// Targets whose names read as an ARKit shape that another target on
    /// their mesh carries instead, and why (`target_names::PassedOver`).
    pub(crate) arkit_passed_over: Vec<PassedOverSummary>,
    pub(crate) face_vertices: usize,
    /// Each part of the avatar and what it was found to be.
    pub(crate) parts: Vec<PartSummary>,
    /// Whose face the avatar has at rest: "person" (the scanned neutral
    /// taken) or "stock".
    pub(crate) rest_face: &'static str,
    /// With the person's face: how far the new rest passes from the scanned
    /// neutral at the mask's vertices, mean and largest (mm), and the
    /// largest change of the rest (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) face_fit_mm: Option<[f64; 2]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) face_largest_change_mm: Option<f64>,
    /// With the person's face: how far the scanned neutral lies from the
    /// new skin over the mask's vertices on it, mean and 95th percentile
    /// (mm), and how many mask vertices asked nothing of the skin (off it,
    /// or lying folded on it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) face_surface_mm: Option<[f64; 2]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) face_points_left_out: Option<usize>,
    pub(crate) registration_residual_mean_mm: f64,
    pub(crate) registration_residual_max_mm: f64,
    /// The avatar's shapes that move elsewhere on the face than ARKit's of
    /// the same name, left out of placing the mask, with how far off each
    /// was (share of the eye distance).
    pub(crate) features_left_out: Vec<(String, f64)>,
    pub(crate) registration_cached: bool,
    pub(crate) registration_seconds: f64,
    pub(crate) retarget_weight_min: f64,
    pub(crate) retarget_weight_max: f64,
    /// `‖G w̃_j − M B_j‖ / ‖M B_j‖` at its largest: huge where a shape
    /// hardly moves the person's face (tongueOut) but the avatar's own
    /// target of that name moves its skin a little.
    pub(crate) retarget_worst_relative_residual: f64,
    /// The same with the person's motion floored at 1 mm RMS: what the
    /// check compares with its limit, and the CLI prints.
    pub(crate) retarget_worst_floored_residual: f64,
    /// The shape of that worst floored residual.
    pub(crate) retarget_worst_shape: String,
    /// Shapes past a limit of the check of the output (each also a
    /// warning).
    pub(crate) checked_faults: usize,
    /// Vertices set by the face step and the adjacent step, and lid
    /// vertices put back out of an eyeball (0 when writing `A_j`).
    pub(crate) implant_face_vertices: usize,
    pub(crate) implant_adjacent_vertices: usize,
    pub(crate) lids_repaired: usize,
    /// Vertices from behind the skin put back behind it, over the 52
    /// shapes (`partial_transfer::inside_follows`; 0 when writing `A_j`).
    pub(crate) inside_put_back: usize,
    /// Skin edges creased where the avatar's own shape keeps them smooth,
    /// over the 52 shapes, before the creases finer than the mask were
    /// smoothed out and after (`partial_transfer::crease_smoothing`; 0
    /// when writing `A_j`).
    pub(crate) creases_found: usize,
    pub(crate) creases_left: usize,
    /// Steps skipped or limited because the avatar lacked something, and
    /// each shape past a limit of the check of the output.
    pub(crate) warnings: Vec<String>,
    pub(crate) seconds: Timings,
    pub(crate) out_bytes: u64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) retarget_map: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) preview: Option<PreviewSummary>,
}

/// One part of the avatar: its name and its role (`skin`, `eyeball`,
/// `upper teeth`, `lower teeth`, `teeth`, `tongue` or `other`).
#[derive(Serialize)]
pub(crate) struct PartSummary {
    pub(crate) name: String,
    pub(crate) role: &'static str,
}

/// What `--preview` wrote.
#[derive(Serialize)]
pub(crate) struct PreviewSummary {
    pub(crate) dir: String,
    pub(crate) files: usize,
    pub(crate) bytes: usize,
    pub(crate) sheet_width: u32,
    pub(crate) sheet_height: u32,
}

#[derive(Serialize, Default)]
pub(crate) struct Timings {
    /// The whole command from its start to the file written (before any
    /// preview): the avatar is read, and its face found, while the session
    /// is read and personalized, so this is less than the sum of the
    /// steps.
    pub(crate) total: f64,
    pub(crate) read_session: f64,
    pub(crate) personalize: f64,
    pub(crate) read_avatar: f64,
    pub(crate) registration: f64,
    pub(crate) take_face: f64,
    pub(crate) retargeting: f64,
    pub(crate) implant: f64,
    pub(crate) write: f64,
    pub(crate) preview: f64,
}

/// The ARKit name of the shape whose residual is largest (Apple's order),
/// empty for no shapes.
pub(crate) fn worst_shape(residuals: &[f64]) -> String {
    residuals
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .and_then(|(j, _)| likeness::arkit::Blendshape::ALL.get(j))
        .map_or(String::new(), |b| b.name().to_string())
}

/// The parts by role, in the order roles first appear: `skin: head;
/// eyeball: eyeLeft, eyeRight; …`, a name repeated as often as it has
/// parts of that role (`eyeLeft ×3`).
fn parts_line(parts: &[PartSummary]) -> String {
    let mut roles: Vec<(&str, Vec<(&str, usize)>)> = Vec::new();
    for p in parts {
        let at = match roles.iter().position(|(r, _)| *r == p.role) {
            Some(at) => at,
            None => {
                roles.push((p.role, Vec::new()));
                roles.len() - 1
            }
        };
        let names = &mut roles[at].1;
        match names.iter_mut().find(|(n, _)| *n == p.name) {
            Some((_, count)) => *count += 1,
            None => names.push((&p.name, 1)),
        }
    }
    roles
        .iter()
        .map(|(role, names)| {
            let names: Vec<String> = names
                .iter()
                .map(|(n, c)| match c {
                    1 => n.to_string(),
                    c => format!("{n} ×{c}"),
                })
                .collect();
            format!("{role}: {}", names.join(", "))
        })
        .collect::<Vec<_>>()
        .join("; ")
}

pub(crate) fn print_summary(s: &Summary) {
    println!(
        "Avatar: {} ({} vertices, {} morph targets)",
        s.avatar, s.vertices, s.morph_targets
    );
    println!(
        "ARKit shapes on the avatar: {} of 52{}",
        s.arkit_found,
        if s.arkit_missing.is_empty() {
            String::new()
        } else {
            format!(" (missing: {})", s.arkit_missing.join(", "))
        }
    );
    for p in &s.arkit_passed_over {
        println!(
            "  Not taken: mesh {} target {} {:?} reads as {}, but {:?} (target {}) is: {}",
            p.mesh, p.target, p.name, p.shape, p.taken_name, p.taken_target, p.why
        );
    }
    println!(
        "Face found: {} face vertices, registration residual mean {:.3} mm, max {:.3} mm{}",
        s.face_vertices,
        s.registration_residual_mean_mm,
        s.registration_residual_max_mm,
        if s.registration_cached {
            " (cached)".to_string()
        } else {
            format!(" ({:.2} s)", s.registration_seconds)
        }
    );
    if !s.features_left_out.is_empty() {
        println!(
            "Not used to place the face (the avatar moves them elsewhere than ARKit does): {}",
            s.features_left_out
                .iter()
                .map(|(name, off)| format!("{name} ({:.0}% of the eye distance off)", 100.0 * off))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    println!("Parts: {}", parts_line(&s.parts));
    println!(
        "Retargeting (Eq. 4, weights bounded to [0, 1]): {:.3} … {:.3}; worst residual {:.2} of the person's motion ({}; motion under 1 mm counted as 1 mm)",
        s.retarget_weight_min,
        s.retarget_weight_max,
        s.retarget_worst_floored_residual,
        s.retarget_worst_shape
    );
    println!(
        "Wrote {} ({:.1} MB): {}",
        s.out,
        s.out_bytes as f64 / 1e6,
        s.shapes
    );
    match (s.face_surface_mm, s.face_fit_mm) {
        (Some([mean, p95]), Some([fit_mean, fit_max])) => {
            println!(
                "Rest face: the person's scanned face, lying {mean:.3} mm (mean), {p95:.2} mm (95%) from the new skin; the rest moved by up to {:.1} mm",
                s.face_largest_change_mm.unwrap_or(0.0)
            );
            println!(
                "  the registration's points {fit_mean:.3} mm (mean), {fit_max:.2} mm (largest) from their scanned places; {} mask vertices asked nothing of the skin (off it, or folded on it)",
                s.face_points_left_out.unwrap_or(0)
            );
        }
        _ => println!("Rest face: the avatar's own"),
    }
    if s.implant_face_vertices > 0 {
        println!(
            "Implanted: {} face vertices (step 1), {} next to them (step 2), {} lid vertices put back out of an eyeball, {} vertices from behind the skin put back behind it; {} skin edges creased finer than the mask, {} after smoothing",
            s.implant_face_vertices,
            s.implant_adjacent_vertices,
            s.lids_repaired,
            s.inside_put_back,
            s.creases_found,
            s.creases_left
        );
    }
    match s.checked_faults {
        0 => println!(
            "Checked: every shape within the limits (torn edges, folds, blinks, lids in the eyes, the inside through the skin, Eq. (4)'s residual)"
        ),
        n => println!("Checked: {n} shape(s) past a limit, each named in a warning above"),
    }
    if let Some(map) = &s.retarget_map {
        println!("Wrote the retarget map {map}");
    }
    if let Some(p) = &s.preview {
        println!(
            "Wrote the preview {} ({} files, {:.1} MB; a {} × {} contact sheet): open {}",
            p.dir,
            p.files,
            p.bytes as f64 / 1e6,
            p.sheet_width,
            p.sheet_height,
            Path::new(&p.dir).join("index.html").display()
        );
    }
    let t = &s.seconds;
    println!(
        "Time: {:.2} s in all; session {:.2} s, personalize ({}) {:.2} s, avatar {:.2} s and registration {:.2} s (while the session is read), face {:.2} s, retargeting {:.3} s, implant {:.2} s, write {:.2} s",
        t.total,
        t.read_session,
        s.method,
        t.personalize,
        t.read_avatar,
        t.registration,
        t.take_face,
        t.retargeting,
        t.implant,
        t.write
    );
    if s.preview.is_some() {
        println!("Preview: {:.2} s", t.preview);
    }
}
