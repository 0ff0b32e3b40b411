//! Where a glTF document refers to accessors and buffer views by index, so
//! that dropping some and renumbering the rest keeps every reference right.
//!
//! Accessors are referred to by primitives (`attributes`, `indices`,
//! `targets`), skins (`inverseBindMatrices`), animation samplers (`input`,
//! `output`) and `EXT_mesh_gpu_instancing`; buffer views by accessors
//! (`bufferView`, both parts of `sparse`), images and
//! `KHR_draco_mesh_compression`. An extension not listed here that refers
//! to either by index would not be renumbered.

use serde_json::Value;

const ACCESSOR_REFS: &[&[&str]] = &[
    &["meshes", "*", "primitives", "*", "attributes", "*"],
    &["meshes", "*", "primitives", "*", "indices"],
    &["meshes", "*", "primitives", "*", "targets", "*", "*"],
    &["skins", "*", "inverseBindMatrices"],
    &["animations", "*", "samplers", "*", "input"],
    &["animations", "*", "samplers", "*", "output"],
    &[
        "nodes",
        "*",
        "extensions",
        "EXT_mesh_gpu_instancing",
        "attributes",
        "*",
    ],
];

const VIEW_REFS: &[&[&str]] = &[
    &["accessors", "*", "bufferView"],
    &["accessors", "*", "sparse", "indices", "bufferView"],
    &["accessors", "*", "sparse", "values", "bufferView"],
    &["images", "*", "bufferView"],
    &[
        "meshes",
        "*",
        "primitives",
        "*",
        "extensions",
        "KHR_draco_mesh_compression",
        "bufferView",
    ],
];

/// What is referred to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Accessor,
    View,
}

fn paths(kind: Kind) -> &'static [&'static [&'static str]] {
    match kind {
        Kind::Accessor => ACCESSOR_REFS,
        Kind::View => VIEW_REFS,
    }
}

fn visit(v: &mut Value, path: &[&str], f: &mut dyn FnMut(&mut Value)) {
    let Some((&first, rest)) = path.split_first() else {
        f(v);
        return;
    };
    match (first, v) {
        ("*", Value::Array(items)) => items.iter_mut().for_each(|x| visit(x, rest, f)),
        ("*", Value::Object(map)) => map.values_mut().for_each(|x| visit(x, rest, f)),
        (key, Value::Object(map)) => {
            if let Some(x) = map.get_mut(key) {
                visit(x, rest, f);
            }
        }
        _ => {}
    }
}

/// Calls `f` on every value at `path` in `v`, read only ([`visit`]).
fn look(v: &Value, path: &[&str], f: &mut dyn FnMut(&Value)) {
    let Some((&first, rest)) = path.split_first() else {
        f(v);
        return;
    };
    match (first, v) {
        ("*", Value::Array(items)) => items.iter().for_each(|x| look(x, rest, f)),
        ("*", Value::Object(map)) => map.values().for_each(|x| look(x, rest, f)),
        (key, Value::Object(map)) => {
            if let Some(x) = map.get(key) {
                look(x, rest, f);
            }
        }
        _ => {}
    }
}

/// Which of `len` objects of `kind` the document refers to.
pub(crate) fn used(doc: &Value, kind: Kind, len: usize) -> Vec<bool> {
    let mut out = vec![false; len];
    for path in paths(kind) {
        look(doc, path, &mut |v| {
            if let Some(slot) = v.as_u64().and_then(|i| out.get_mut(i as usize)) {
                *slot = true;
            }
        });
    }
    out
}

/// Rewrites every reference of `kind`: index `i` becomes `map[i]`.
pub(crate) fn renumber(doc: &mut Value, kind: Kind, map: &[Option<usize>]) {
    for path in paths(kind) {
        visit(doc, path, &mut |v| {
            if let Some(Some(new)) = v.as_u64().and_then(|i| map.get(i as usize)) {
                *v = Value::from(*new);
            }
        });
    }
}

/// The renumbering that drops the objects where `drop` is true and moves
/// as few of the rest as it can: every object keeps its index unless that
/// index is past the new end, and such objects fill the gaps, those from
/// `first_new` on (the ones just added) first.
pub(crate) fn filling(drop: &[bool], first_new: usize) -> Vec<Option<usize>> {
    let len = drop.iter().filter(|&&d| !d).count();
    let mut map: Vec<Option<usize>> = (0..drop.len())
        .map(|i| (!drop[i] && i < len).then_some(i))
        .collect();
    let holes = (0..len).filter(|&i| drop[i]);
    let movers = (first_new.max(len)..drop.len())
        .chain(len..first_new.max(len))
        .filter(|&i| !drop[i]);
    for (hole, mover) in holes.zip(movers) {
        map[mover] = Some(hole);
    }
    map
}

/// `items` placed by `map` (from [`filling`]): item `i` at `map[i]`,
/// dropped items gone.
pub(crate) fn place<T>(items: Vec<T>, map: &[Option<usize>]) -> Vec<T> {
    let mut slots: Vec<Option<T>> = Vec::new();
    slots.resize_with(map.iter().flatten().count(), || None);
    for (item, at) in items.into_iter().zip(map) {
        if let Some(slot) = at.and_then(|j| slots.get_mut(j)) {
            *slot = Some(item);
        }
    }
    slots.into_iter().flatten().collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn renumbers_every_listed_reference() {
        let mut doc = json!({
            "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 3,
                "targets": [{ "POSITION": 2 }] }] }],
            "skins": [{ "inverseBindMatrices": 3 }],
        });
        assert_eq!(used(&doc, Kind::Accessor, 4), [true, false, true, true]);
        let map = filling(&[false, true, false, false], 4);
        assert_eq!(map, [Some(0), None, Some(2), Some(1)]);
        renumber(&mut doc, Kind::Accessor, &map);
        assert_eq!(doc["meshes"][0]["primitives"][0]["indices"], json!(1));
        assert_eq!(
            doc["meshes"][0]["primitives"][0]["targets"][0]["POSITION"],
            json!(2)
        );
        assert_eq!(doc["skins"][0]["inverseBindMatrices"], json!(1));
        assert_eq!(place(vec!['a', 'b', 'c', 'd'], &map), ['a', 'd', 'c']);
    }

    #[test]
    fn new_objects_fill_the_gaps_first() {
        // Old 0..4 with 1 and 2 dropped; 4 and 5 new.
        let map = filling(&[false, true, true, false, false, false], 4);
        assert_eq!(map, [Some(0), None, None, Some(3), Some(1), Some(2)]);
        // More gaps than new objects: an old one past the end moves.
        let map = filling(&[true, true, false, false, false], 4);
        assert_eq!(map, [None, None, Some(2), Some(1), Some(0)]);
    }
}
