//! `likeness avatar … --preview DIR`: a contact sheet for a person to look
//! at what the avatar step did, shape by shape. For the neutral pose and
//! each of [`tiles::POSES`] (shapes at weight one), the avatar's own shape and the
//! written one (the person's implanted shapes, or `A_j` with
//! `--retargeted`), each seen three ways: the face from the front, both
//! eyes close, the mouth close.
//!
//! | what | module |
//! |---|---|
//! | where each view looks: the face region, the eyes (eyeBlink), the mouth (jawOpen) | [`framing`](mod@framing) |
//! | the poses, the views, one tile drawn (the report's rasterizer, depth-darkened) | [`tiles`] |
//! | the grid of tiles as one picture, labelled | [`sheet`], [`font`] |
//! | what each cell is: `contact-sheet.txt`, `index.html` | [`legend`] |
//! | `likeness demo`'s faces side by side at rest | [`faces`] |
//!
//! The folder gets `contact-sheet.png`, `contact-sheet.txt`, `index.html`
//! and `tiles/POSE-SET-VIEW.png`, each file written atomically (a
//! temporary file renamed into place); other files in it are left alone.

mod faces;
mod font;
mod framing;
mod legend;
mod sheet;
mod tiles;

use framing::{Framing, FramingInput, framing, points_in_mask_frame, vectors_in_mask_frame};
use glam::{DVec3, Vec3};
use legend::{About, tile_name};
use likeness::Blendshape;
use likeness::avatar::glb::GlbAvatar;
use likeness::avatar::glb::look::{part_colours, srgb8};
use likeness::avatar::registration::FaceRegistration;
use likeness::avatar::{ArkitTargets, Avatar};
use likeness::io::atomic_write::write_atomically;
use sheet::{Layout, contact_sheet};
use std::path::Path;
use std::time::Instant;
use tiles::{Row, Scene, Set, View, missing_tile};

use crate::report::image::Image;

/// What the preview is drawn from: the avatar as read and what the avatar
/// step made of it.
pub struct PreviewInput<'a> {
    /// The avatar as read.
    pub avatar: &'a Avatar,
    /// Its name for the legend (its file, or "default avatar").
    pub avatar_name: &'a str,
    /// The face found on it.
    pub registration: &'a FaceRegistration,
    /// Which of its targets carry ARKit's shapes.
    pub found: &'a ArkitTargets,
    /// The written shapes: for each ARKit shape (Apple's order), the
    /// displacement of every avatar vertex.
    pub written: &'a [Vec<Vec3>],
    /// The written set's name (`personalized` or `retargeted`).
    pub written_name: &'static str,
    /// What the written shapes are, in a sentence.
    pub written_means: &'static str,
    /// The avatar's rigid parts other than eyeballs (teeth, gums,
    /// tongue), as indices into `avatar.parts()`.
    pub mouth_parts: &'a [usize],
    /// Each vertex's colour as the file gives it ([`vertex_colours`]).
    pub colours: &'a [Option<[u8; 3]>],
}

/// Each vertex of `glb` (its parts in order) in its own colour, sRGB, as
/// its materials and `COLOR_0` give it; `None` where the file does not say
/// (a texture, no material): the preview's colour for its role.
pub fn vertex_colours(glb: &GlbAvatar) -> Vec<Option<[u8; 3]>> {
    let parts = glb.avatar.parts().iter();
    parts
        .zip(part_colours(glb))
        .flat_map(|(part, colours)| match colours {
            Some(c) => c.iter().map(|v| Some(srgb8(*v))).collect(),
            None => vec![None; part.positions.len()],
        })
        .collect()
}

/// What was written.
#[derive(Clone, Debug, PartialEq)]
pub struct Preview {
    /// Files written.
    pub files: usize,
    /// Their total size in bytes.
    pub bytes: usize,
    /// The sheet's size in pixels.
    pub sheet_size: (u32, u32),
    /// Time taken to draw and write, seconds.
    pub seconds: f64,
}

/// Whether `dir` can take the preview: it does not exist yet (it will be
/// created) or is a folder. Checked before the avatar step runs, so that a
/// wrong path fails at once.
pub fn check_dir(dir: &Path) -> Result<(), String> {
    if dir.exists() && !dir.is_dir() {
        return Err(format!(
            "{}: exists and is not a folder (--preview needs a folder to write the contact sheet in)",
            dir.display()
        ));
    }
    Ok(())
}

/// How the PNG files are compressed: fast (the default level takes
/// several times as long, for files a fifth smaller).
const COMPRESSION: png::Compression = png::Compression::Fast;

/// A tile drawn, and its PNG file.
type Tile = (Image, Vec<u8>);

/// One pose's displacement in the mask's frame, or `None` when the set
/// lacks the shape (the avatar has no target for it).
type Pose = Option<Option<Vec<DVec3>>>;

/// `avatar` at rest wearing each face of `faces` (a label and the avatar
/// with that rest, as [`likeness::avatar::personal_avatar::PersonalAvatar::shaped`]
/// gives it), side by side from the front and the side
/// ([`faces::faces_picture`]), written to `out` as PNG; `registration` is
/// the face found on the stock avatar (its similarity frames every face
/// alike), `mouth_parts` the teeth, gums and tongue (indices into
/// `avatar.parts()`), `colours` its vertices' own ([`vertex_colours`]).
/// Returns the picture's size.
pub fn write_faces(
    avatar: &Avatar,
    registration: &FaceRegistration,
    mouth_parts: &[usize],
    colours: &[Option<[u8; 3]>],
    faces: &[(&str, &Avatar)],
    out: &Path,
) -> Result<(u32, u32), Box<dyn std::error::Error>> {
    let ranges = |parts: &[usize]| part_ranges(avatar, parts);
    let face: Vec<u32> = registration.map.face.iter().map(|f| f.vertex).collect();
    let triangles = avatar.triangles();
    let (eyeballs, mouth_parts) = (ranges(&registration.eyeball_parts()), ranges(mouth_parts));
    let meshes = faces::Meshes {
        triangles,
        eyeballs: &eyeballs,
        mouth_parts: &mouth_parts,
        face: &face,
        colours,
    };
    let columns: Vec<faces::Face<'_>> = faces
        .iter()
        .map(|(label, worn)| faces::Face {
            label,
            rest: points_in_mask_frame(registration, &worn.positions()),
        })
        .collect();
    let picture = faces::faces_picture(&columns, &meshes);
    write_atomically(out, &picture.png_compressed(COMPRESSION)?)?;
    Ok((picture.width, picture.height))
}

/// Draws the preview of `input` and writes it into `dir` (module docs).
pub fn write_preview(
    input: &PreviewInput<'_>,
    dir: &Path,
) -> Result<Preview, Box<dyn std::error::Error>> {
    let started = Instant::now();
    check_dir(dir)?;
    let avatar = input.avatar;
    let registration = input.registration;
    let ranges = |parts: &[usize]| part_ranges(avatar, parts);
    let eyeballs = ranges(&registration.eyeball_parts());
    let mouth_parts = ranges(input.mouth_parts);
    let face: Vec<u32> = registration.map.face.iter().map(|f| f.vertex).collect();
    let scene = Scene::new(
        points_in_mask_frame(registration, &avatar.positions()),
        avatar.triangles().to_vec(),
        &eyeballs,
        &mouth_parts,
        &face,
    )
    .painted(input.colours);

    let own = |shape: Blendshape| -> Option<Vec<DVec3>> {
        let targets = input.found.of(shape);
        (!targets.is_empty())
            .then(|| vectors_in_mask_frame(registration, &avatar.summed_displacement(targets)))
    };
    let written = |shape: Blendshape| -> Option<Vec<DVec3>> {
        let d = input.written.get(shape.index())?;
        (d.len() == scene.rest.len()).then(|| vectors_in_mask_frame(registration, d))
    };
    let rows = Row::all();
    // poses[row][set]: Some(None) is the rest pose.
    // A pose of several shapes is their displacements summed; missing if
    // the set lacks any of them.
    let summed = |row: Row, of: &dyn Fn(Blendshape) -> Option<Vec<DVec3>>| -> Pose {
        let fields = row
            .shapes()
            .into_iter()
            .map(of)
            .collect::<Option<Vec<_>>>()?;
        Some(fields.into_iter().reduce(|mut sum, d| {
            sum.iter_mut().zip(d).for_each(|(s, d)| *s += d);
            sum
        }))
    };
    let poses: Vec<[Pose; 2]> = rows
        .iter()
        .map(|row| [summed(*row, &own), summed(*row, &written)])
        .collect();

    let mut skin = vec![true; scene.rest.len()];
    for r in eyeballs.iter().chain(&mouth_parts) {
        if let Some(s) = skin.get_mut(r.clone()) {
            s.fill(false);
        }
    }
    let fields = |shapes: &[Blendshape]| -> Vec<Vec<DVec3>> {
        shapes
            .iter()
            .flat_map(|&s| [own(s), written(s)])
            .flatten()
            .collect()
    };
    let blinks = fields(&[Blendshape::EyeBlinkLeft, Blendshape::EyeBlinkRight]);
    let jaw = fields(&[Blendshape::JawOpen]);
    let (blinks, jaw) = (slices(&blinks), slices(&jaw));
    let framing = framing(&FramingInput {
        rest: &scene.rest,
        face: &face,
        skin: &skin,
        blinks: &blinks,
        jaw: &jaw,
    });

    let drawn = draw_tiles(&scene, &framing, &poses)?;
    let tile = |r: usize, set: Set, view: View| -> &Tile {
        // Both sets at rest are one picture, drawn once.
        let s = usize::from(set == Set::Written && poses[r][1] != Some(None));
        let v = View::ALL.iter().position(|x| *x == view).unwrap_or(0);
        &drawn[r * 2 + s].as_ref().expect("every tile drawn")[v]
    };

    let layout = Layout::new(&rows);
    let set_name = |set: Set| legend::set_name(set, input.written_name).to_string();
    let sheet = contact_sheet(&layout, &set_name, &|r, column| {
        tile(r, column.set, column.view).0.clone()
    });
    let has_own = |row: Row| row.shapes().iter().all(|s| !input.found.of(*s).is_empty());
    let about = About {
        avatar: input.avatar_name,
        written: input.written_name,
        written_means: input.written_means,
        has_own: &has_own,
    };

    let mut files: Vec<(String, Vec<u8>)> = Vec::new();
    for (r, row) in rows.iter().enumerate() {
        for set in sheet::SETS {
            for view in View::ALL {
                files.push((
                    tile_name(*row, set, view, input.written_name),
                    tile(r, set, view).1.clone(),
                ));
            }
        }
    }
    files.push((
        "contact-sheet.png".into(),
        sheet.png_compressed(COMPRESSION)?,
    ));
    files.push((
        "contact-sheet.txt".into(),
        legend::text(&layout, &about).into_bytes(),
    ));
    files.push((
        "index.html".into(),
        legend::html(&layout, &about).into_bytes(),
    ));

    write_files(dir, &files)?;
    Ok(Preview {
        files: files.len(),
        bytes: files.iter().map(|(_, b)| b.len()).sum(),
        sheet_size: layout.size,
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// Every tile of `poses` (`poses[row][set]`) in every view, drawn and
/// encoded on as many threads as there are cores, one job per pose and set
/// (both sets at rest drawn once, as the own set): `drawn[2 · row + set]`.
fn draw_tiles(
    scene: &Scene,
    framing: &Framing,
    poses: &[[Pose; 2]],
) -> Result<Vec<Option<[Tile; 3]>>, png::EncodingError> {
    let jobs: Vec<(usize, usize)> = (0..poses.len())
        .flat_map(|r| (0..2).map(move |s| (r, s)))
        .filter(|&(r, s)| s == 0 || poses[r][1] != Some(None))
        .collect();
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, jobs.len().max(1));
    let draw = |(r, s): (usize, usize)| -> Result<[Tile; 3], png::EncodingError> {
        let images = match &poses[r][s] {
            None => View::ALL.map(missing_tile),
            Some(d) => {
                let posed = scene.posed(d.as_deref());
                View::ALL.map(|v| scene.render(&posed, framing.of(v), v != View::Front))
            }
        };
        let [a, b, c] = images.map(|image| {
            let png = image.png_compressed(COMPRESSION);
            (image, png)
        });
        Ok([(a.0, a.1?), (b.0, b.1?), (c.0, c.1?)])
    };
    let mut drawn: Vec<Option<[Tile; 3]>> = vec![None; 2 * poses.len()];
    std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                let (jobs, draw) = (&jobs, &draw);
                scope.spawn(move || {
                    (t..jobs.len())
                        .step_by(threads)
                        .map(|j| (j, draw(jobs[j])))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        for handle in handles {
            for (j, tiles) in handle.join().expect("a tile thread panicked") {
                let (r, s) = jobs[j];
                drawn[2 * r + s] = Some(tiles?);
            }
        }
        Ok(drawn)
    })
}

/// Writes `files` (names relative to `dir`) into `dir`, each atomically,
/// creating `dir` and its `tiles/` folder if missing.
fn write_files(dir: &Path, files: &[(String, Vec<u8>)]) -> Result<(), String> {
    let tiles_dir = dir.join("tiles");
    std::fs::create_dir_all(&tiles_dir).map_err(|e| format!("{}: {e}", tiles_dir.display()))?;
    for (name, bytes) in files {
        let path = dir.join(name);
        write_atomically(&path, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}

/// The vertex ranges of `parts` (indices into `avatar.parts()`; unknown
/// ones left out).
fn part_ranges(avatar: &Avatar, parts: &[usize]) -> Vec<std::ops::Range<usize>> {
    let offsets = avatar.vertex_offsets();
    parts
        .iter()
        .filter_map(|&p| Some(*offsets.get(p)?..*offsets.get(p + 1)?))
        .collect()
}

/// Each field as a slice.
fn slices(fields: &[Vec<DVec3>]) -> Vec<&[DVec3]> {
    fields.iter().map(Vec::as_slice).collect()
}
