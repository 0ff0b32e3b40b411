//! `likeness avatar`: a session's personalized shapes onto an avatar
//! (§3.3): the face found (cached), Eq. (4), then the seamless partial
//! deformation transfer and eyelid repair; `--retargeted` writes the
//! automatic retargeting `A_j` of Eq. (4) instead.

use crate::CliResult;
use crate::avatar_preview::PreviewInput;
use crate::avatar_summary::{
    PartSummary, PreviewSummary, Summary, Timings, print_summary, worst_shape,
};
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
        arkit_passed_over: made.found.passed_over().iter().map(Into::into).collect(),
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
        inside_put_back: implanted.as_ref().map_or(0, |i| i.put_back_behind_skin),
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
