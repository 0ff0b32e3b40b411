//! `likeness avatar`: a session's personalized shapes onto an avatar
//! (§3.3): the face found (cached), Eq. (4), then the seamless partial
//! deformation transfer and eyelid repair; `--retargeted` writes the
//! automatic retargeting `A_j` of Eq. (4) instead.

use crate::CliResult;
use crate::avatar_preview::PreviewInput;
use crate::info::read_session_template_first;
use likeness::avatar::glb::{GlbAvatar, new_avatar_glb, read_avatar, read_avatar_bytes};
use likeness::avatar::personal_avatar::{
    AvatarShapes, AvatarStep, PersonInput, PersonalAvatar, RestFace, mask_glb, personal_avatar,
    retarget_map_json,
};
use likeness::avatar::registration::FaceRegistration;
use likeness::avatar::registration::cache;
use likeness::avatar::registration::find_face::{cache_key, find_face};
use likeness::geometry::topology::Topology;
use likeness::io::atomic_write::write_atomically;
use likeness::personalize::{Method, personalize};
use likeness::session::{Session, Template};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::mpsc::Receiver;
use std::time::Instant;

/// What `likeness avatar` was asked to do.
pub struct AvatarArgs {
    /// The session file.
    pub session: PathBuf,
    /// The avatar, or the default one.
    pub avatar: Option<PathBuf>,
    /// Where to write the avatar GLB.
    pub out: PathBuf,
    /// The personalization method.
    pub method: Method,
    /// Where to write the 52 × k retarget map, if asked.
    pub retarget_map: Option<PathBuf>,
    /// Where registrations are cached.
    pub cache_dir: Option<PathBuf>,
    /// Write the automatic retargeting `A_j` instead of the person's shapes.
    pub retargeted: bool,
    /// Whose face the avatar gets at rest, if asked (`--keep-face`,
    /// `--take-face`); [`RestFace::chosen`] decides otherwise.
    pub face: Option<RestFace>,
    /// Write the personalized face mask alone.
    pub mask_only: bool,
    /// Where to write the contact sheet, if asked.
    pub preview: Option<PathBuf>,
    /// Print JSON instead of text.
    pub json: bool,
}

/// The summary `--json` prints.
#[derive(Serialize)]
struct Summary {
    avatar: String,
    out: String,
    /// What the shapes in `out` are.
    shapes: &'static str,
    method: String,
    vertices: usize,
    morph_targets: usize,
    arkit_found: usize,
    arkit_missing: Vec<&'static str>,
    face_vertices: usize,
    /// Each part of the avatar and what it was found to be.
    parts: Vec<PartSummary>,
    /// Whose face the avatar has at rest: "person" (the scanned neutral
    /// taken) or "stock".
    rest_face: &'static str,
    /// With the person's face: how far the new rest passes from the scanned
    /// neutral at the mask's vertices, mean and largest (mm), and the
    /// largest change of the rest (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    face_fit_mm: Option<[f64; 2]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    face_largest_change_mm: Option<f64>,
    /// With the person's face: how far the scanned neutral lies from the
    /// new skin over the mask's vertices on it, mean and 95th percentile
    /// (mm), and how many mask vertices asked nothing of the skin (off it,
    /// or lying folded on it).
    #[serde(skip_serializing_if = "Option::is_none")]
    face_surface_mm: Option<[f64; 2]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    face_points_left_out: Option<usize>,
    registration_residual_mean_mm: f64,
    registration_residual_max_mm: f64,
    /// The avatar's shapes that move elsewhere on the face than ARKit's of
    /// the same name, left out of placing the mask, with how far off each
    /// was (share of the eye distance).
    features_left_out: Vec<(String, f64)>,
    registration_cached: bool,
    registration_seconds: f64,
    retarget_weight_min: f64,
    retarget_weight_max: f64,
    /// `‖G w̃_j − M B_j‖ / ‖M B_j‖` at its largest: huge where a shape
    /// hardly moves the person's face (tongueOut) but the avatar's own
    /// target of that name moves its skin a little.
    retarget_worst_relative_residual: f64,
    /// The same with the person's motion floored at 1 mm RMS: what the
    /// check compares with its limit, and the CLI prints.
    retarget_worst_floored_residual: f64,
    /// The shape of that worst floored residual.
    retarget_worst_shape: String,
    /// Shapes past a limit of the check of the output (each also a
    /// warning).
    checked_faults: usize,
    /// Vertices set by the face step and the adjacent step, and lid
    /// vertices put back out of an eyeball (0 when writing `A_j`).
    implant_face_vertices: usize,
    implant_adjacent_vertices: usize,
    lids_repaired: usize,
    /// Skin edges creased where the avatar's own shape keeps them smooth,
    /// over the 52 shapes, before the creases finer than the mask were
    /// smoothed out and after (`partial_transfer::crease_smoothing`; 0
    /// when writing `A_j`).
    creases_found: usize,
    creases_left: usize,
    /// Steps skipped or limited because the avatar lacked something, and
    /// each shape past a limit of the check of the output.
    warnings: Vec<String>,
    seconds: Timings,
    out_bytes: u64,
    #[serde(skip_serializing_if = "Option::is_none")]
    retarget_map: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    preview: Option<PreviewSummary>,
}

/// One part of the avatar: its name and its role (`skin`, `eyeball`,
/// `upper teeth`, `lower teeth`, `teeth`, `tongue` or `other`).
#[derive(Serialize)]
struct PartSummary {
    name: String,
    role: &'static str,
}

/// What `--preview` wrote.
#[derive(Serialize)]
struct PreviewSummary {
    dir: String,
    files: usize,
    bytes: usize,
    sheet_width: u32,
    sheet_height: u32,
}

#[derive(Serialize, Default)]
struct Timings {
    /// The whole command from its start to the file written (before any
    /// preview): the avatar is read, and its face found, while the session
    /// is read and personalized, so this is less than the sum of the
    /// steps.
    total: f64,
    read_session: f64,
    personalize: f64,
    read_avatar: f64,
    registration: f64,
    take_face: f64,
    retargeting: f64,
    implant: f64,
    write: f64,
    preview: f64,
}

/// The default avatar as GLB bytes.
fn default_glb_bytes(name: &Path) -> Result<Vec<u8>, Box<dyn std::error::Error>> {
    let built = likeness_sim::default_avatar::default_avatar();
    let options = likeness_sim::default_avatar::glb_options(built);
    Ok(new_avatar_glb(&built.avatar, &options, name)?)
}

/// The default avatar as a GLB read: the prebuilt bytes the phone ships
/// (`likeness-assets`, what [`default_glb_bytes`] builds, checked by
/// `tests/tests/assets.rs`), so it takes the same path as a user's file
/// and the app's.
pub fn default_glb() -> Result<GlbAvatar, Box<dyn std::error::Error>> {
    Ok(read_avatar_bytes(
        likeness_assets::DEFAULT_AVATAR_GLB,
        "default avatar",
    )?)
}

/// `likeness avatar … --mask-only`: the person's personalized face mask
/// alone (their neutral and 52 shapes, ARKit's face coordinates, metres)
/// as a GLB.
fn write_mask(session: &Session, shapes: &likeness::Blendshapes, out: &Path) -> CliResult {
    let bytes = mask_glb(&session.topology, shapes, out)?;
    write_atomically(out, &bytes).map_err(|e| format!("{}: {e}", out.display()))?;
    println!(
        "Wrote {} ({:.1} MB): the personalized face mask, {} vertices, 52 shapes",
        out.display(),
        bytes.len() as f64 / 1e6,
        shapes.vertex_count()
    );
    Ok(())
}

/// `likeness default-avatar --out FILE`: writes the project's own default
/// avatar (with its 52 generic ARKit shapes) as GLB.
pub fn default_avatar_command(out: &Path) -> CliResult {
    let started = Instant::now();
    let bytes = default_glb_bytes(out)?;
    write_atomically(out, &bytes).map_err(|e| format!("{}: {e}", out.display()))?;
    let built = likeness_sim::default_avatar::default_avatar();
    println!(
        "Wrote {} ({:.1} MB): the default avatar, {} vertices in {} meshes, 52 ARKit shapes ({:.2} s)",
        out.display(),
        bytes.len() as f64 / 1e6,
        built.avatar.vertex_count(),
        built.avatar.meshes().len(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Where registrations are cached unless `--cache-dir` says otherwise:
/// `$XDG_CACHE_HOME/likeness`, else `~/.cache/likeness`, else a folder in
/// the system's temporary directory.
fn default_cache_dir() -> PathBuf {
    std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
        .unwrap_or_else(std::env::temp_dir)
        .join("likeness")
}

/// The ARKit name of the shape whose residual is largest (Apple's order),
/// empty for no shapes.
fn worst_shape(residuals: &[f64]) -> String {
    residuals
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .and_then(|(j, _)| likeness::arkit::Blendshape::ALL.get(j))
        .map_or(String::new(), |b| b.name().to_string())
}

/// What the avatar's thread prepares while the session is read: the avatar,
/// how long reading it took, and the face found on it for the session's
/// template, if it could be.
struct Prepared {
    glb: GlbAvatar,
    read_seconds: f64,
    face: Option<EarlyFace>,
}

/// A face found on the avatar before the person is known.
struct EarlyFace {
    registration: FaceRegistration,
    /// Read from the cache, not found anew.
    cached: bool,
    /// The key it is cached under ([`cache_key`]).
    key: String,
}

/// The face on `glb` for a session of mask `mask` and template `template`:
/// from the cache in `dir` if it holds it, else found now; `None` where it
/// cannot be found (the avatar stage then looks again and says why).
fn early_face(
    glb: &GlbAvatar,
    mask: &Topology,
    template: &Template,
    dir: &Path,
) -> Option<EarlyFace> {
    let rig = template.blendshapes().ok()?;
    let key = cache_key(&glb.avatar, &rig);
    if let Some(registration) = cache::load(dir, &key, &glb.avatar, mask.vertex_count()) {
        return Some(EarlyFace {
            registration,
            cached: true,
            key,
        });
    }
    let registration = find_face(&glb.avatar, mask, &rig).ok()?;
    Some(EarlyFace {
        registration,
        cached: false,
        key,
    })
}

/// Runs `likeness avatar`.
pub fn avatar_command(args: &AvatarArgs) -> CliResult {
    let started = Instant::now();
    let mut t = Timings::default();
    if let Some(dir) = &args.preview {
        crate::avatar_preview::check_dir(dir)?;
    }
    let steps = crate::progress::bar("avatar", 5);
    let dir = args.cache_dir.clone().unwrap_or_else(default_cache_dir);
    // The avatar is read (or the default one built) on its own thread
    // while the session is read and personalized; as soon as the session's
    // template is decoded, the same thread finds the face on the avatar
    // (or reads it from the cache). Neither needs the person.
    let prepare = |template: Receiver<(Topology, Template)>| -> Result<Prepared, String> {
        let clock = Instant::now();
        let glb = match &args.avatar {
            Some(path) => read_avatar(path).map_err(|e| e.to_string())?,
            None => default_glb().map_err(|e| e.to_string())?,
        };
        let read_seconds = clock.elapsed().as_secs_f64();
        // No template (the session failed before it): nothing to find.
        // A face not found here is looked for again by `personal_avatar`,
        // which reports why.
        let face = template
            .recv()
            .ok()
            .and_then(|(mask, template)| early_face(&glb, &mask, &template, &dir));
        Ok(Prepared {
            glb,
            read_seconds,
            face,
        })
    };
    let (session, personalized, prepared) =
        std::thread::scope(|scope| -> Result<_, Box<dyn std::error::Error>> {
            let (send_template, template) = std::sync::mpsc::channel();
            let reading = (!args.mask_only).then(|| scope.spawn(move || prepare(template)));
            let clock = Instant::now();
            let session = read_session_template_first(&args.session, |mask, template| {
                // The thread may have ended (an avatar that cannot be
                // read): it then has no use for the template.
                let _ = send_template.send((mask.clone(), template.clone()));
            });
            // The thread waits for the template until this sender goes.
            drop(send_template);
            let session = session?;
            t.read_session = clock.elapsed().as_secs_f64();
            steps.inc(1);
            let clock = Instant::now();
            let personalized = personalize(&session, args.method)?;
            t.personalize = clock.elapsed().as_secs_f64();
            steps.inc(1);
            let prepared = match reading {
                Some(reading) => {
                    let prepared = reading
                        .join()
                        .unwrap_or_else(|e| std::panic::resume_unwind(e))?;
                    t.read_avatar = prepared.read_seconds;
                    Some(prepared)
                }
                None => None,
            };
            Ok((session, personalized, prepared))
        })?;
    let Some(Prepared { glb, face, .. }) = prepared else {
        steps.finish_and_clear();
        return write_mask(&session, &personalized.shapes, &args.out);
    };
    steps.inc(1);

    let clock = Instant::now();
    let rig = session.template.blendshapes()?;
    let was_cached = face.as_ref().is_some_and(|f| f.cached);
    // Found (not read from the cache) while the session was read.
    let found_early = face
        .as_ref()
        .filter(|f| !f.cached)
        .map(|f| f.registration.seconds);
    let (key, cached) = match face {
        Some(f) => (f.key, Some(f.registration)),
        None => (cache_key(&glb.avatar, &rig), None),
    };
    let person = PersonInput {
        mask: &session.topology,
        rig: &rig,
        personalized: &personalized.shapes,
    };
    let shapes = if args.retargeted {
        AvatarShapes::Retargeted
    } else {
        AvatarShapes::Personalized
    };
    // Time each step as it starts.
    let mut marks: Vec<(AvatarStep, Instant)> = Vec::new();
    let mut progress = |step: AvatarStep| {
        marks.push((step, Instant::now()));
        true
    };
    let face = RestFace::chosen(args.avatar.is_none(), args.face);
    let made = personal_avatar(&glb, &person, cached, shapes, face, &mut progress)?;
    let ended = Instant::now();
    let step_seconds = |step: AvatarStep| {
        marks.iter().position(|m| m.0 == step).map_or(0.0, |i| {
            let next = marks.get(i + 1).map_or(ended, |m| m.1);
            (next - marks[i].1).as_secs_f64()
        })
    };
    t.registration = found_early.unwrap_or_else(|| step_seconds(AvatarStep::FindingFace));
    t.take_face = step_seconds(AvatarStep::TakingFace);
    t.retargeting = step_seconds(AvatarStep::Retargeting);
    t.implant = step_seconds(AvatarStep::Implanting);
    if !was_cached && let Err(e) = cache::store(&dir, &key, &made.registration) {
        eprintln!(
            "note: the registration could not be cached in {}: {e}",
            dir.display()
        );
    }
    steps.inc(1);
    let _ = clock;

    let clock = Instant::now();
    write_atomically(&args.out, &made.glb).map_err(|e| format!("{}: {e}", args.out.display()))?;
    if let Some(map) = &args.retarget_map {
        let text = retarget_map_json(&glb, &made.retargeting);
        write_atomically(map, text.as_bytes()).map_err(|e| format!("{}: {e}", map.display()))?;
    }
    t.write = clock.elapsed().as_secs_f64() + step_seconds(AvatarStep::Writing);
    t.total = started.elapsed().as_secs_f64();
    let avatar_name = args
        .avatar
        .as_ref()
        .map_or("default avatar".to_string(), |p| p.display().to_string());
    let preview = match &args.preview {
        Some(dir) => {
            steps.set_message("preview");
            let made = write_preview(&glb, &made, &avatar_name, args.retargeted, dir)?;
            t.preview = made.seconds;
            Some(PreviewSummary {
                dir: dir.display().to_string(),
                files: made.files,
                bytes: made.bytes,
                sheet_width: made.sheet_size.0,
                sheet_height: made.sheet_size.1,
            })
        }
        None => None,
    };
    steps.finish_and_clear();
    for warning in &made.warnings {
        eprintln!("warning: {}: {warning}", glb.file.display());
    }

    let (registration, retargeting, implanted) =
        (&made.registration, &made.retargeting, &made.implanted);
    let avatar = &glb.avatar;
    let (lo, hi) = retargeting.weight_range();
    let summary = Summary {
        avatar: avatar_name,
        out: args.out.display().to_string(),
        shapes: if args.retargeted {
            "automatic retargeting (Eq. 4): the avatar's own blendshapes combined"
        } else {
            "personalized: the person's shapes implanted by seamless partial deformation transfer (§3.3)"
        },
        method: args.method.to_string(),
        vertices: avatar.vertex_count(),
        morph_targets: retargeting.targets.len(),
        arkit_found: made.found.found(),
        arkit_missing: made.found.missing().iter().map(|b| b.name()).collect(),
        face_vertices: registration.map.face.len(),
        parts: avatar
            .parts()
            .iter()
            .zip(&registration.roles)
            .map(|(p, r)| PartSummary {
                name: p.name.clone(),
                role: r.name(),
            })
            .collect(),
        rest_face: if made.taken_face.is_some() {
            "person"
        } else {
            "stock"
        },
        face_fit_mm: made
            .taken_face
            .as_ref()
            .map(|t| [t.fit_mean_mm, t.fit_max_mm]),
        face_largest_change_mm: made.taken_face.as_ref().map(|t| t.largest_mm),
        face_surface_mm: made
            .taken_face
            .as_ref()
            .map(|t| [t.surface_mean_mm, t.surface_p95_mm]),
        face_points_left_out: made.taken_face.as_ref().map(|t| t.points_left_out.len()),
        registration_residual_mean_mm: registration.residual_mean_mm,
        registration_residual_max_mm: registration.residual_max_mm,
        features_left_out: registration
            .features_left_out
            .iter()
            .map(|(b, off)| (b.name().to_string(), *off))
            .collect(),
        registration_cached: was_cached,
        registration_seconds: registration.seconds,
        retarget_weight_min: lo,
        retarget_weight_max: hi,
        retarget_worst_relative_residual: retargeting
            .relative_residual
            .iter()
            .copied()
            .fold(0.0, f64::max),
        retarget_worst_floored_residual: retargeting
            .floored_residual
            .iter()
            .copied()
            .fold(0.0, f64::max),
        retarget_worst_shape: worst_shape(&retargeting.floored_residual),
        checked_faults: made.faults().count(),
        implant_face_vertices: implanted.as_ref().map_or(0, |i| i.face_vertices),
        implant_adjacent_vertices: implanted.as_ref().map_or(0, |i| i.adjacent_vertices),
        lids_repaired: implanted.as_ref().map_or(0, |i| i.lids_repaired),
        creases_found: implanted.as_ref().map_or(0, |i| i.creases_found),
        creases_left: implanted.as_ref().map_or(0, |i| i.creases_left),
        warnings: made.warnings.iter().map(|w| w.to_string()).collect(),
        seconds: t,
        out_bytes: made.glb.len() as u64,
        retarget_map: args.retarget_map.as_ref().map(|p| p.display().to_string()),
        preview,
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        print_summary(&summary);
    }
    Ok(())
}

/// `--preview DIR`: the contact sheet of what `made` wrote into `glb`.
fn write_preview(
    glb: &GlbAvatar,
    made: &PersonalAvatar,
    avatar_name: &str,
    retargeted: bool,
    dir: &Path,
) -> Result<crate::avatar_preview::Preview, Box<dyn std::error::Error>> {
    let retargeted_shapes;
    let avatar = made.shaped(&glb.avatar);
    let (written, mouth_parts): (&[Vec<glam::Vec3>], Vec<usize>) = match &made.implanted {
        Some(implanted) => (
            &implanted.shapes,
            implanted
                .rigid_parts
                .iter()
                .copied()
                .filter(|p| !made.registration.eyeball_parts().contains(p))
                .collect(),
        ),
        None => {
            retargeted_shapes = made.retargeting.displacements(avatar);
            (&retargeted_shapes, Vec::new())
        }
    };
    let input = PreviewInput {
        avatar,
        avatar_name,
        registration: made.shaped_registration(),
        found: &made.found,
        written,
        written_name: if retargeted {
            "retargeted"
        } else {
            "personalized"
        },
        written_means: if retargeted {
            "the automatic retargeting of Eq. (4), the avatar's own shapes combined"
        } else {
            "the person's shapes implanted by the seamless partial deformation transfer"
        },
        mouth_parts: &mouth_parts,
        colours: &crate::avatar_preview::vertex_colours(glb),
    };
    crate::avatar_preview::write_preview(&input, dir)
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

fn print_summary(s: &Summary) {
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
            "Implanted: {} face vertices (step 1), {} next to them (step 2), {} lid vertices put back out of an eyeball; {} skin edges creased finer than the mask, {} after smoothing",
            s.implant_face_vertices,
            s.implant_adjacent_vertices,
            s.lids_repaired,
            s.creases_found,
            s.creases_left
        );
    }
    match s.checked_faults {
        0 => println!(
            "Checked: every shape within the limits (torn edges, folds, blinks, lids in the eyes, Eq. (4)'s residual)"
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
