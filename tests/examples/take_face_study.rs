//! Taking the person's face on the default avatar, whatever the crease
//! check would decide (`person_face::take_face` alone), for people
//! simulated on either mask: how far the scan lies from the new skin, how
//! many head edges the new rest turns past `rest_check::REST_CREASE_ANGLE`,
//! and how many of those by more than the scan itself bends the mask
//! there plus 22.5° (the check's rule, `rest_check::rest_creases`).
//!
//! ```text
//! cargo run --release -p likeness-tests --example take_face_study -- [SEEDS…]
//! ```
//!
//! The figures behind issue 41's point 3 (`docs/avatar.md`). `AVATAR=name`
//! takes the face on a generated variant instead of the default avatar,
//! `AVATAR=path.glb` on that file (`../shared/avatars/ict-facekit.glb`);
//! `DUMP=dir` writes, per person, the new head, the stock one, the scan,
//! the mask as registered, the creased edges, the points left out and
//! each scanned point's distance from the new skin, to look at.
//!
//! Beside the product's figure (`TakenFace::surface_p95_mm`, over every
//! mask vertex on the skin), the same figure away from the rims of the
//! mask's holes (the eyes' and the mouth's; the outline kept): where the
//! mask is the person's surface, not the edge of a hole the avatar keeps
//! its own lids and lips in.

use glam::DVec3;
use likeness::avatar::Avatar;
use likeness::avatar::glb::read_avatar_bytes;
use likeness::avatar::implant_check::head_triangles;
use likeness::avatar::own_shapes::{face_part_triangles, skin_points};
use likeness::avatar::person_face::{TakenFace, mean_and_p95, take_face};
use likeness::avatar::registration::find_face::FACE_TOLERANCE_MM;
use likeness::avatar::registration::{FaceRegistration, find_face};
use likeness::avatar::rest_check::{creased_edges, scan_bend};
use likeness::geometry::closest_point::TriangleTree;
use likeness::geometry::mesh_boundary::{BoundaryError, boundary_loops};
use likeness::geometry::topology::Topology;
use likeness_sim::arkit_face::shared_arkit_face;
use likeness_sim::face_basis::FaceBasis;
use likeness_tests::arkit_people::{ArkitPerson, study_seeds};

/// The scan's distance from the new skin (mm at the mask's scale), mean
/// and 95th percentile as the product takes them
/// ([`likeness::avatar::person_face::mean_and_p95`]), over the mask
/// vertices on the skin that are on no hole's rim: every boundary loop of
/// `mask` but the longest (the outline).
fn away_from_holes(
    avatar: &Avatar,
    found: &FaceRegistration,
    (taken, neutral): (&TakenFace, &[DVec3]),
    mask: &Topology,
) -> Result<(f64, f64), BoundaryError> {
    let stock: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let new: Vec<DVec3> = stock
        .iter()
        .zip(&taken.moved)
        .map(|(p, u)| *p + *u)
        .collect();
    let triangles = face_part_triangles(avatar, found);
    let to_avatar = found.similarity.scale / 1e3;
    let on_skin = skin_points(found, &stock, &triangles, FACE_TOLERANCE_MM * to_avatar);
    let mut loops = boundary_loops(mask)?;
    loops.sort_by_key(Vec::len);
    loops.pop();
    let mut on_hole = vec![false; neutral.len()];
    for &v in loops.iter().flatten() {
        on_hole[v as usize] = true;
    }
    let skin = TriangleTree::new(&new, &triangles);
    let far: Vec<f64> = (0..neutral.len())
        .filter(|&i| on_skin[i].is_some() && !on_hole[i])
        .filter_map(|i| {
            Some(skin.closest(found.similarity.apply(neutral[i]))?.distance / to_avatar)
        })
        .collect();
    Ok(mean_and_p95(far))
}

/// How many head edges the new rest turns past
/// `rest_check::REST_CREASE_ANGLE` (the scan's bend aside), how many of
/// them also past the scan's own bend there (the check's rule), and the
/// first count's edges.
fn creases(
    avatar: &Avatar,
    found: &FaceRegistration,
    taken: &TakenFace,
    bend: &[f64],
) -> (usize, usize, Vec<(u32, u32)>) {
    let flat = vec![0.0; avatar.vertex_count()];
    let creased = creased_edges(avatar, found, &taken.moved, &flat);
    let beyond = creased_edges(avatar, found, &taken.moved, bend).len();
    let edges = creased.iter().map(|(_, e)| *e).collect();
    (creased.len(), beyond, edges)
}

/// Writes into `dir`, to look at: the taken head (`head.obj`) and the
/// stock one (`stock.obj`), its creased edges (`creases.txt`, one vertex
/// pair a line), the scanned places of the points left out
/// (`left_out.txt`, avatar frame), the scan (`scan.obj`), the mask as
/// registered (`registered.obj`), and each scanned point's distance from
/// the new head and whether it is on the skin (`scan_to_skin.txt`, mm).
fn dump(
    dir: &std::path::Path,
    avatar: &Avatar,
    found: &FaceRegistration,
    taken: &TakenFace,
    neutral: &[DVec3],
    creased: &[(u32, u32)],
) -> std::io::Result<()> {
    use std::fmt::Write as _;
    std::fs::create_dir_all(dir)?;
    let head = head_triangles(avatar, found);
    for (name, scale) in [("head.obj", 1.0), ("stock.obj", 0.0)] {
        let mut obj = String::new();
        for (p, u) in avatar.positions().iter().zip(&taken.moved) {
            let q = p.as_dvec3() + *u * scale;
            let _ = writeln!(obj, "v {} {} {}", q.x, q.y, q.z);
        }
        for t in &head {
            let _ = writeln!(obj, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        std::fs::write(dir.join(name), obj)?;
    }
    let scanned: Vec<DVec3> = neutral.iter().map(|p| found.similarity.apply(*p)).collect();
    for (name, points) in [
        ("scan.obj", &scanned),
        ("registered.obj", &found.mask_on_avatar),
    ] {
        let mut obj = String::new();
        for q in points {
            let _ = writeln!(obj, "v {} {} {}", q.x, q.y, q.z);
        }
        for t in &found.map.mask_triangles {
            let _ = writeln!(obj, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        std::fs::write(dir.join(name), obj)?;
    }
    let lines: String = creased.iter().map(|(a, b)| format!("{a} {b}\n")).collect();
    std::fs::write(dir.join("creases.txt"), lines)?;
    let left: String = taken
        .points_left_out
        .iter()
        .map(|&i| {
            let q = found.similarity.apply(neutral[i as usize]);
            format!("{i} {} {} {}\n", q.x, q.y, q.z)
        })
        .collect();
    std::fs::write(dir.join("left_out.txt"), left)?;
    let new: Vec<DVec3> = avatar
        .positions()
        .iter()
        .zip(&taken.moved)
        .map(|(p, u)| p.as_dvec3() + *u)
        .collect();
    let skin = likeness::geometry::closest_point::TriangleTree::new(&new, &head);
    let to_mm = 1e3 / found.similarity.scale;
    let stock: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let on_skin = likeness::avatar::own_shapes::skin_points(
        found,
        &stock,
        &likeness::avatar::own_shapes::face_part_triangles(avatar, found),
        likeness::avatar::registration::find_face::FACE_TOLERANCE_MM / to_mm,
    );
    let far: String = scanned
        .iter()
        .zip(&on_skin)
        .map(|(q, s)| {
            let d = skin.closest(*q).map_or(f64::NAN, |c| c.distance * to_mm);
            format!("{d} {}\n", u8::from(s.is_some()))
        })
        .collect();
    std::fs::write(dir.join("scan_to_skin.txt"), far)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let seeds = study_seeds()?;
    // AVATAR=name: one of the generated variants instead of the default.
    let glb = match std::env::var("AVATAR") {
        Ok(name) if name.ends_with(".glb") => read_avatar_bytes(&std::fs::read(&name)?, &name)?,
        Ok(name) => {
            let variant = likeness_sim::avatar_variants::avatar_variants()
                .into_iter()
                .find(|v| v.name == name)
                .ok_or(format!("no generated avatar '{name}'"))?;
            read_avatar_bytes(&variant.glb, variant.name)?
        }
        Err(_) => read_avatar_bytes(
            &likeness_sim::default_avatar::default_avatar_glb()?,
            "default",
        )?,
    };
    let mut bases = vec![FaceBasis::Simulator];
    if let Some(face) = shared_arkit_face() {
        bases.push(FaceBasis::Arkit(face));
    }
    for basis in &bases {
        for &seed in &seeds {
            let person = ArkitPerson::simulate(*basis, seed);
            let (session, rig) = (&person.session, &person.rig);
            let neutral = person.personalized.neutral();
            let found = find_face(&glb.avatar, &session.topology, rig)?;
            let taken = take_face(&glb.avatar, &found, neutral)?;
            let bend = scan_bend(&glb.avatar, &found, neutral);
            let (creased, beyond, edges) = creases(&glb.avatar, &found, &taken, &bend);
            if let Ok(dir) = std::env::var("DUMP") {
                let dir = std::path::Path::new(&dir).join(format!("{}-{seed}", basis.name()));
                dump(&dir, &glb.avatar, &found, &taken, neutral, &edges)?;
            }
            let (away_mean, away_p95) =
                away_from_holes(&glb.avatar, &found, (&taken, neutral), &session.topology)?;
            println!(
                "{} {seed}: eyes {:?}; scan to skin {:.3} mm mean, {:.2} mm p95 ({away_mean:.3}, {away_p95:.2} away from the holes' rims); points {:.3} mm mean, {:.2} mm max, {} left out; largest change {:.1} mm; {:.2} s; creased edges {creased}, {beyond} past the scan's own bend",
                basis.name(),
                taken.eyeballs,
                taken.surface_mean_mm,
                taken.surface_p95_mm,
                taken.fit_mean_mm,
                taken.fit_max_mm,
                taken.points_left_out.len(),
                taken.largest_mm,
                taken.seconds,
            );
        }
    }
    Ok(())
}
