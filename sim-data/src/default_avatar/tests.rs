use super::*;

#[test]
fn default_avatar_builds() {
    let a = default_avatar();
    for p in &a.avatar.parts {
        eprintln!(
            "{}: {} vertices, {} triangles",
            p.name,
            p.positions.len(),
            p.triangles.len()
        );
    }
    eprintln!("total {}", a.avatar.vertex_count());
}
