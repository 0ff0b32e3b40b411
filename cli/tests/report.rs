//! `likeness report` as a person uses it: one committed session in, a
//! folder out whose every picture exists, has the size the page states and
//! shows something, whose numbers are those of `likeness evaluate --json`,
//! and whose colour scale runs from blue at 0 mm to red at 5 mm.

use serde_json::Value;
use std::collections::HashSet;
use std::path::{Path, PathBuf};

mod common;
use common::{likeness, text};

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    common::scratch("report", name)
}

#[allow(dead_code)]
#[path = "../src/report/colour_map.rs"]
mod colour_map;

/// The value of attribute `name` in the tag text `tag`.
fn attr<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let start = tag.find(&format!(" {name}=\""))? + name.len() + 3;
    let end = tag[start..].find('"')? + start;
    Some(&tag[start..end])
}

/// Every tag of `html` that starts with `open` (e.g. `<img `), up to `>`.
fn tags<'a>(html: &'a str, open: &str) -> Vec<&'a str> {
    html.match_indices(open)
        .filter_map(|(i, _)| html[i..].find('>').map(|end| &html[i..i + end + 1]))
        .collect()
}

/// A PNG's size and pixels (RGB).
fn read_png(path: &Path) -> ((u32, u32), Vec<[u8; 3]>) {
    let file = std::io::BufReader::new(std::fs::File::open(path).expect("the PNG opens"));
    let mut reader = png::Decoder::new(file).read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size().expect("a size")];
    let info = reader.next_frame(&mut buf).expect("decodes");
    assert_eq!(info.color_type, png::ColorType::Rgb, "{path:?}");
    let pixels = buf[..info.buffer_size()]
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    ((info.width, info.height), pixels)
}

/// The pictures every report of a simulated session has (beside the 52
/// thumbnails), with the size of the PNGs among them.
fn expected_pictures() -> Vec<(String, Option<(u32, u32)>)> {
    let mut out: Vec<(String, Option<(u32, u32)>)> = [
        "capture/timeline.svg",
        "capture/brows.svg",
        "capture/eyes.svg",
        "capture/cheeks-nose.svg",
        "capture/jaw.svg",
        "capture/mouth.svg",
        "capture/tongue.svg",
        "accuracy/rmse.svg",
        "accuracy/max.svg",
        "accuracy/lambda.svg",
        "colour-scale.svg",
        "avatar/face-rmse.svg",
    ]
    .iter()
    .map(|s| (s.to_string(), None))
    .collect();
    out.push(("capture/neutral-scan.png".into(), Some((360, 440))));
    for pick in ["worst", "median", "best"] {
        for panel in ["recorded", "multi", "ebfr", "dt"] {
            out.push((format!("fig6/{pick}-{panel}.png"), Some((260, 320))));
        }
        for panel in ["person", "manual", "automatic", "personalized"] {
            out.push((format!("avatar/{pick}-{panel}.png"), Some((260, 320))));
        }
    }
    for shape in likeness::Blendshape::ALL {
        out.push((format!("fig2/{}.png", shape.name()), Some((302, 185))));
    }
    out
}

/// Checks one picture the page shows at `width × height`.
fn check_picture(dir: &Path, src: &str, width: u32, height: u32) {
    let path = dir.join(src);
    assert!(path.is_file(), "{src} is missing");
    if src.ends_with(".png") {
        let (size, pixels) = read_png(&path);
        assert_eq!(size, (width, height), "{src}: size");
        let colours: HashSet<[u8; 3]> = pixels.iter().copied().collect();
        assert!(colours.len() > 1, "{src}: one colour");
        let drawn = pixels.iter().filter(|p| **p != [255, 255, 255]).count();
        assert!(drawn * 20 > pixels.len(), "{src}: {drawn} pixels drawn");
    } else {
        let svg = std::fs::read_to_string(&path).expect("SVG text");
        let root = tags(&svg, "<svg ")[0];
        assert_eq!(
            attr(root, "width"),
            Some(width.to_string().as_str()),
            "{src}"
        );
        assert_eq!(
            attr(root, "height"),
            Some(height.to_string().as_str()),
            "{src}"
        );
        let fills: HashSet<&str> = tags(&svg, "<")
            .iter()
            .filter_map(|t| attr(t, "fill").or_else(|| attr(t, "stroke")))
            .filter(|f| *f != "#FFFFFF" && *f != "none")
            .collect();
        assert!(fills.len() > 1, "{src}: colours {fills:?}");
        let marks = ["<rect", "<path", "<polyline", "<circle", "<line"]
            .iter()
            .map(|m| svg.matches(m).count())
            .sum::<usize>();
        assert!(marks > 5, "{src}: {marks} marks");
    }
}

/// `(data-key, data-value, shown text)` of each number cell in `row`.
fn number_cells(row: &str) -> Vec<(String, f64, String)> {
    tags(row, "<td class=\"num\" data-key=")
        .into_iter()
        .filter_map(|tag| {
            let key = attr(tag, "data-key")?.to_string();
            let value: f64 = attr(tag, "data-value")?.parse().ok()?;
            let start = row.find(tag)? + tag.len();
            let shown = row[start..start + row[start..].find('<')?].to_string();
            Some((key, value, shown))
        })
        .collect()
}

/// Each `<tr` row of `html` whose `marker` attribute is set, by its value.
fn rows<'a>(html: &'a str, marker: &str) -> Vec<(String, &'a str)> {
    html.match_indices(&format!("<tr {marker}=\""))
        .filter_map(|(i, _)| {
            let end = html[i..].find("</tr>")? + i;
            let row = &html[i..end];
            Some((attr(row, marker)?.to_string(), row))
        })
        .collect()
}

/// Every number shown in `rows` equals `expected(key of row, cell key)`
/// and is shown with three decimals.
fn check_rows(rows: &[(String, &str)], expected: &dyn Fn(&str, &str) -> Option<f64>) -> usize {
    let mut checked = 0;
    for (name, row) in rows {
        for (key, value, shown) in number_cells(row) {
            let want =
                expected(name, &key).unwrap_or_else(|| panic!("{name} {key} not in evaluate"));
            assert_eq!(value, want, "{name} {key}");
            assert_eq!(shown, format!("{value:.3}"), "{name} {key} shown");
            checked += 1;
        }
    }
    checked
}

#[test]
fn a_report_of_a_committed_session() {
    let dir = scratch("subject-1");
    let out = dir.join("report");
    let session = likeness_tests::committed::path(1).display().to_string();
    let out_s = out.display().to_string();
    let (report, evaluate) = std::thread::scope(|s| {
        let report = s.spawn(|| likeness(&["report", &session, "--out", &out_s]));
        let evaluate = likeness(&["evaluate", &session, "--json"]);
        (report.join().expect("joins"), evaluate)
    });
    assert!(report.status.success(), "{}", text(&report.stderr));
    assert!(evaluate.status.success(), "{}", text(&evaluate.stderr));
    let html = std::fs::read_to_string(out.join("index.html")).expect("index.html");

    // Self-contained: nothing loaded from the network.
    for tag in tags(&html, "<img ").iter().chain(&tags(&html, "<a ")) {
        let link = attr(tag, "src").or_else(|| attr(tag, "href")).unwrap_or("");
        assert!(!link.contains("://"), "{tag}");
    }

    // Every picture: there, of the size stated, not blank.
    let shown: Vec<(String, u32, u32)> = tags(&html, "<img ")
        .iter()
        .map(|t| {
            let n = |a| attr(t, a).and_then(|v| v.parse().ok()).expect("a size");
            (
                attr(t, "src").expect("src").to_string(),
                n("width"),
                n("height"),
            )
        })
        .collect();
    for (src, size) in expected_pictures() {
        let Some((_, w, h)) = shown.iter().find(|(s, _, _)| *s == src) else {
            panic!("{src} is not on the page");
        };
        if let Some(size) = size {
            assert_eq!((*w, *h), size, "{src}: stated size");
        }
    }
    for (src, w, h) in &shown {
        check_picture(&out, src, *w, *h);
    }

    // The legend of the colour scale starts blue and ends red.
    let scale = std::fs::read_to_string(out.join("colour-scale.svg")).expect("the scale");
    let fills: Vec<[u8; 3]> = tags(&scale, "<rect ")
        .iter()
        .filter_map(|t| attr(t, "fill"))
        .filter(|f| *f != "#FFFFFF")
        .map(|f| [1, 3, 5].map(|i| u8::from_str_radix(&f[i..i + 2], 16).expect("hex")))
        .collect();
    assert_eq!(fills[0], colour_map::error_colour(0.0), "starts blue");
    assert_eq!(fills[fills.len() - 1], [255, 0, 0], "ends red");

    // The numbers are those of `evaluate --json`.
    let evaluated: Value = serde_json::from_slice(&evaluate.stdout).expect("JSON");
    let start = html.find(r#"id="likeness-data">"#).expect("embedded data") + 19;
    let end = html[start..].find("</script>").expect("its end") + start;
    let data: Value = serde_json::from_str(&html[start..end].replace("<\\/", "</")).expect("JSON");
    let embedded = &data["evaluation"];
    for key in ["methods", "ratios", "lambda_curve"] {
        assert_eq!(embedded[key], evaluated[key], "{key}");
    }
    let methods = check_rows(&rows(&html, "data-method"), &|m, k| {
        evaluated["methods"][m][k].as_f64()
    });
    let ratios = check_rows(&rows(&html, "data-ratio"), &|r, _| {
        evaluated["ratios"][r].as_f64()
    });
    let curve = check_rows(&rows(&html, "data-lambda"), &|l, k| {
        evaluated["lambda_curve"]
            .as_array()?
            .iter()
            .find(|p| p["lambda"].as_f64().map(|x| x.to_string()).as_deref() == Some(l))?[k]
            .as_f64()
    });
    assert_eq!(methods, 5 * 4, "four means of five methods");
    assert_eq!(ratios, 8);
    assert_eq!(curve, 7 * 4);
    std::fs::remove_dir_all(&dir).expect("cleans up");
}

#[test]
fn the_colour_scale_runs_from_blue_to_red() {
    let blue = colour_map::error_colour(0.0);
    assert!(blue[2] == 255 && blue[0] == 0 && blue[1] < 64, "{blue:?}");
    for mm in [colour_map::SCALE_MAX_MM, 5.0, 7.5, 100.0] {
        assert_eq!(colour_map::error_colour(mm), [255, 0, 0], "{mm} mm");
    }
    let below = colour_map::error_colour(4.9);
    assert!(
        below[0] == 255 && below[1] > 0,
        "just below 5 mm is not yet red"
    );
}

#[test]
fn a_folder_that_is_no_report_is_not_replaced() {
    let dir = scratch("other");
    std::fs::write(dir.join("notes.txt"), b"mine").expect("writes");
    let session = likeness_tests::committed::path(1).display().to_string();
    let out = likeness(&["report", &session, "--out", &dir.display().to_string()]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("not a Likeness report"),
        "{}",
        text(&out.stderr)
    );
    assert_eq!(std::fs::read(dir.join("notes.txt")).expect("kept"), b"mine");
    std::fs::remove_dir_all(&dir).expect("cleans up");
}
