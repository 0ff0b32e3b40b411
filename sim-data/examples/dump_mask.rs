//! Writes the template neutral, or one template shape, as OBJ to stdout:
//! `cargo run -p likeness-sim --example dump_mask [shapeName]`.
fn main() {
    let m = likeness_sim::face_mask::face_mask();
    let model = likeness_sim::template::generic_model();
    let points = match std::env::args().nth(1) {
        Some(name) => model.shape(likeness::Blendshape::parse(&name).expect("an ARKit name")),
        None => model.neutral.clone(),
    };
    for p in &points {
        println!("v {} {} {}", p.x, p.y, p.z);
    }
    for t in m.topology.triangles() {
        println!("f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
}
