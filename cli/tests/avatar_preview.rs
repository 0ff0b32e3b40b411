//! `likeness avatar … --preview DIR` as a person uses it: the contact
//! sheet, its tiles, its legend and page written beside the GLB, the
//! tiles showing what the shapes do, and a clear error for a path that is
//! not a folder.

use std::path::{Path, PathBuf};

mod common;
use common::{likeness, s, text};

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    common::scratch("cli-avatar-preview", name)
}

/// A PNG file decoded: width, height and RGB pixels.
struct Picture {
    width: u32,
    height: u32,
    pixels: Vec<u8>,
}

fn decode(path: &Path) -> Picture {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let decoder = png::Decoder::new(std::io::BufReader::new(file));
    let mut reader = decoder.read_info().expect("a PNG header");
    let mut pixels = vec![0; reader.output_buffer_size().expect("a size")];
    let info = reader.next_frame(&mut pixels).expect("PNG pixels");
    assert_eq!(info.color_type, png::ColorType::Rgb, "{}", path.display());
    pixels.truncate(info.buffer_size());
    Picture {
        width: info.width,
        height: info.height,
        pixels,
    }
}

/// The share of pixels of two pictures of one size that differ by more
/// than 24 in some channel.
fn share_changed(a: &Picture, b: &Picture) -> f64 {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let changed = a
        .pixels
        .chunks(3)
        .zip(b.pixels.chunks(3))
        .filter(|(p, q)| p.iter().zip(*q).any(|(x, y)| x.abs_diff(*y) > 24))
        .count();
    changed as f64 / f64::from(a.width * a.height)
}

/// The tile sizes: front, eyes, mouth.
const SIZES: [(&str, (u32, u32)); 3] = [
    ("front", (216, 264)),
    ("eyes", (362, 150)),
    ("mouth", (240, 160)),
];

const ROWS: [&str; 12] = [
    "neutral",
    "jawOpen",
    "jawOpen+mouthClose",
    "eyeBlinkLeft",
    "eyeBlinkRight",
    "mouthSmileLeft",
    "mouthFunnel",
    "browInnerUp",
    "browDownLeft",
    "eyeSquintLeft",
    "cheekPuff",
    "eyeLookUpLeft",
];

#[test]
fn the_preview_shows_every_shape_own_and_personalized() {
    let dir = scratch("default");
    let session = likeness_tests::committed::path(1);
    let (glb, preview, cache) = (dir.join("out.glb"), dir.join("preview"), dir.join("cache"));
    let out = likeness(&[
        "avatar",
        &s(&session),
        "--out",
        &s(&glb),
        "--preview",
        &s(&preview),
        "--cache-dir",
        &s(&cache),
        "--json",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(glb.is_file());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let summary = &v["preview"];
    assert_eq!(summary["dir"], s(&preview), "{v}");
    assert_eq!(summary["files"], 12 * 6 + 3, "{v}");

    for row in ROWS {
        for set in ["own", "personalized"] {
            for (view, size) in SIZES {
                let tile = decode(&preview.join(format!("tiles/{row}-{set}-{view}.png")));
                assert_eq!((tile.width, tile.height), size, "{row} {set} {view}");
            }
        }
    }
    let sheet = decode(&preview.join("contact-sheet.png"));
    assert_eq!(
        (u64::from(sheet.width), u64::from(sheet.height)),
        (
            summary["sheet_width"].as_u64().unwrap(),
            summary["sheet_height"].as_u64().unwrap()
        )
    );
    // Twelve rows of the tallest tile, six columns of the three views.
    assert!(sheet.height >= 12 * 264 && sheet.width >= 2 * (216 + 362 + 240));

    let legend = std::fs::read_to_string(preview.join("contact-sheet.txt")).unwrap();
    let page = std::fs::read_to_string(preview.join("index.html")).unwrap();
    for row in ROWS {
        assert!(legend.contains(&format!(": {row}\n")), "{row}: {legend}");
        assert!(page.contains(&format!("src=\"tiles/{row}-own-front.png\"")));
    }
    assert!(legend.contains("row 12 column 6:"), "{legend}");
    assert!(
        !legend.contains("missing"),
        "the default avatar has every shape"
    );

    // What the shapes do shows where the views look.
    let tile = |row: &str, set: &str, view: &str| {
        decode(&preview.join(format!("tiles/{row}-{set}-{view}.png")))
    };
    for set in ["own", "personalized"] {
        let neutral_mouth = tile("neutral", set, "mouth");
        let open = share_changed(&neutral_mouth, &tile("jawOpen", set, "mouth"));
        assert!(open > 0.1, "{set}: jawOpen changes {open:.3} of the mouth");
        // mouthClose on the open jaw closes the lips some: the pair is
        // not the jaw alone.
        let closing = share_changed(
            &tile("jawOpen", set, "mouth"),
            &tile("jawOpen+mouthClose", set, "mouth"),
        );
        assert!(
            closing > 0.01,
            "{set}: mouthClose changes {closing:.3} of the open mouth"
        );
        let neutral_eyes = tile("neutral", set, "eyes");
        for blink in ["eyeBlinkLeft", "eyeBlinkRight"] {
            let closed = share_changed(&neutral_eyes, &tile(blink, set, "eyes"));
            assert!(
                closed > 0.03,
                "{set}: {blink} changes {closed:.3} of the eyes"
            );
        }
        // A blink does not move the mouth, nor jawOpen the eyes.
        let still = share_changed(&neutral_mouth, &tile("eyeBlinkLeft", set, "mouth"));
        assert!(
            still < 0.01,
            "{set}: eyeBlinkLeft changes {still:.3} of the mouth"
        );
    }
    // The tiles wear the file's own colours: each eye's pupil shows (and
    // stays, an eye being one rigid body, where the shape leaves the eyes
    // open), and the lips are red.
    let pixels = |p: &Picture, columns: std::ops::Range<u32>, of: &dyn Fn(&[u8]) -> bool| {
        (p.pixels.chunks_exact(3).enumerate())
            .filter(|(i, c)| columns.contains(&(*i as u32 % p.width)) && of(c))
            .count()
    };
    let pupil = |c: &[u8]| c.iter().all(|&x| x <= 30);
    let lip = |c: &[u8]| c[0] > 120 && c[0].saturating_sub(c[1]) >= 40;
    for set in ["own", "personalized"] {
        for row in [
            "neutral",
            "jawOpen",
            "jawOpen+mouthClose",
            "mouthSmileLeft",
            "cheekPuff",
        ] {
            let eyes = tile(row, set, "eyes");
            let half = eyes.width / 2;
            for side in [0..half, half..eyes.width] {
                let dark = pixels(&eyes, side.clone(), &pupil);
                assert!(dark >= 100, "{row} {set}: {dark} pupil pixels in {side:?}");
            }
        }
        let mouth = tile("neutral", set, "mouth");
        let red = pixels(&mouth, 0..mouth.width, &lip);
        assert!(red >= 300, "{set}: {red} lip pixels");
    }
    // The neutral pose is the avatar at rest in both sets.
    assert_eq!(
        tile("neutral", "own", "front").pixels,
        tile("neutral", "personalized", "front").pixels
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_file_for_the_preview_folder_is_refused_by_name_before_any_work() {
    let dir = scratch("bad");
    let file = dir.join("not-a-folder.txt");
    std::fs::write(&file, b"mine").unwrap();
    let glb = dir.join("out.glb");
    let session = likeness_tests::committed::path(1);
    let out = likeness(&[
        "avatar",
        &s(&session),
        "--out",
        &s(&glb),
        "--preview",
        &s(&file),
    ]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(err.contains(&s(&file)), "{err}");
    assert!(err.contains("not a folder"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(!glb.exists(), "nothing written");
    assert_eq!(std::fs::read(&file).unwrap(), b"mine");
    std::fs::remove_dir_all(&dir).unwrap();
}
