//! `teeth-gums-one-mesh`: upper and lower teeth and gums in one primitive,
//! as many exported characters have them ("Teeth" with the gums modelled
//! on), where jawOpen moves only the lower half, rigidly.
//!
//! The default avatar's four parts (upper and lower teeth, upper and lower
//! gums) merged into one mesh `TeethAndGums` of one primitive, its vertices
//! ordered from right to left (by x) so the lower half is not a contiguous
//! block, as an exporter's vertex order seldom is. Its targets are the
//! parts': the lower row follows the mandible (a rotation about the jaw's
//! hinge, or a translation), the upper row never moves.

use super::parts::{base, base_part, glb_of, merge, plain_truth};
use super::truth::{Piece, VariantTruth};
use likeness::avatar::glb::MeshLook;
use likeness::avatar::{Avatar, AvatarPart};

/// Reorders `part`'s vertices by x (ties by index); triangles and
/// targets follow.
fn sort_by_x(part: &mut AvatarPart) {
    let mut order: Vec<usize> = (0..part.positions.len()).collect();
    order.sort_by(|&a, &b| {
        part.positions[a]
            .x
            .total_cmp(&part.positions[b].x)
            .then(a.cmp(&b))
    });
    let mut new_index = vec![0u32; order.len()];
    for (new, &old) in order.iter().enumerate() {
        new_index[old] = new as u32;
    }
    part.positions = order.iter().map(|&o| part.positions[o]).collect();
    for t in &mut part.targets {
        *t = order.iter().map(|&o| t[o]).collect();
    }
    for tri in &mut part.triangles {
        *tri = tri.map(|i| new_index[i as usize]);
    }
}

/// The avatar (meshes `head`, `eyeLeft`, `eyeRight`, `TeethAndGums`,
/// `tongue`) and how many of the merged part's vertices the jaw moves.
fn avatar() -> (Avatar, usize) {
    let b = base();
    let rows = [b.teeth[0], b.teeth[1], b.gums[0], b.gums[1]].map(|k| base_part(k, 3, 0));
    let lower = rows[1].positions.len() + rows[3].positions.len();
    let mut mouth = merge("TeethAndGums", 3, 0, &rows);
    sort_by_x(&mut mouth);
    let mut parts: Vec<AvatarPart> = b.avatar.parts().to_vec();
    parts.retain(|p| p.mesh < 3);
    parts.push(mouth);
    parts.push(base_part(b.tongue, 4, 0));
    let mut meshes = [0, 1, 2, 3, 5]
        .map(|m| b.avatar.meshes()[m].clone())
        .to_vec();
    meshes[3].name = Some("TeethAndGums".into());
    let avatar =
        Avatar::new(meshes, parts).expect("the teeth-and-gums variant's parts make an avatar");
    (avatar, lower)
}

/// The GLB and its truth.
pub fn teeth_gums_one_mesh() -> (Vec<u8>, VariantTruth) {
    let (avatar, lower) = avatar();
    let mut truth = plain_truth(&avatar, 0, base().true_correspondence.len());
    truth.teeth_share_mesh_with_gums = true;
    // The parts of meshes 0–2 (head, eyes), then the merged teeth.
    let teeth = avatar.parts().iter().filter(|p| p.mesh < 3).count();
    truth.teeth = Some(Piece::whole(&avatar, teeth));
    truth.jaw_moved_vertices = lower;
    let looks = vec![
        MeshLook::SKIN,
        MeshLook::EYE_WHITE,
        MeshLook::EYE_WHITE,
        MeshLook::TOOTH,
        MeshLook::GUM,
    ];
    (glb_of(&avatar, Some(looks)), truth)
}
