//! The OBJ reader: `read_obj` on the bytes as a file and `parse_obj` on
//! them as text (when they are UTF-8), within the folder's limits and
//! within a small vertex limit that short inputs can pass; the two readers
//! agree on what they accept.
#![no_main]

use libfuzzer_sys::fuzz_target;
use likeness::Topology;
use likeness::io::obj_reader::{ObjLimits, parse_obj, read_obj};
use likeness::session::interchange::OBJ_LIMITS;
use likeness_fuzz::{check_message, scratch_file};

fuzz_target!(|data: &[u8]| {
    let path = scratch_file("mesh.obj", data);
    let from_file = read_obj(&path, OBJ_LIMITS);
    if let Err(e) = &from_file {
        check_message(e);
    }
    if let Ok(text) = std::str::from_utf8(data) {
        let parsed = parse_obj(&path, text, OBJ_LIMITS);
        match (&from_file, &parsed) {
            (Ok(a), Ok(b)) => assert!(a == b, "read_obj and parse_obj differ"),
            (Err(_), Err(e)) => {
                check_message(e);
            }
            _ => panic!("read_obj and parse_obj disagree"),
        }
        let small = ObjLimits { max_vertices: 16 };
        if let Err(e) = parse_obj(&path, text, small) {
            check_message(&e);
        }
    }
    if let Ok(mesh) = from_file {
        let n = mesh.positions.len();
        assert_eq!(mesh.vertex_lines.len(), n);
        assert_eq!(mesh.triangles.len(), mesh.triangle_lines.len());
        assert!(mesh.positions.iter().all(|p| p.is_finite()));
        if let Err(e) = Topology::new(n, mesh.triangles) {
            let _ = e.to_string();
        }
    }
});
