//! What the contact sheet shows, in words: `contact-sheet.txt` maps every
//! cell of the grid (row, column, pixel rectangle) to its pose, set and
//! view; `index.html` lays out the tiles with captions (the sheet has no
//! text of its own).

use super::sheet::Layout;
use super::tiles::{Row, Set, View};
use crate::report::html::escape;
use std::fmt::Write;

/// The name of the tile of `row`, `set` and `view` in the `tiles/`
/// folder; `written` names the written set (`personalized` or
/// `retargeted`).
pub fn tile_name(row: Row, set: Set, view: View, written: &str) -> String {
    format!(
        "tiles/{}-{}-{}.png",
        row.name(),
        set_name(set, written),
        view.name()
    )
}

/// `own` or the written set's name.
pub fn set_name(set: Set, written: &str) -> &str {
    match set {
        Set::Own => "own",
        Set::Written => written,
    }
}

/// What the preview was made of, for the legend's opening lines.
pub struct About<'a> {
    /// The avatar's file (or "default avatar").
    pub avatar: &'a str,
    /// The written set's name.
    pub written: &'a str,
    /// What the written shapes are, in a sentence.
    pub written_means: &'a str,
    /// Whether the avatar has a target for a row's shape (always true for
    /// the neutral row).
    pub has_own: &'a dyn Fn(Row) -> bool,
}

/// `contact-sheet.txt`.
pub fn text(layout: &Layout, about: &About<'_>) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Contact sheet of {} ({} x {} pixels).\n\
         Rows: the avatar at rest (neutral), then each shape alone at weight one.\n\
         Columns: the avatar's own shape (own), then the written one ({}: {}); each as front, eyes, mouth.\n\
         A crossed grey tile: the avatar has no target for that shape.\n\
         Pixel rectangles are x0-x1, y0-y1 (inclusive), from the top left.\n",
        about.avatar, layout.size.0, layout.size.1, about.written, about.written_means
    );
    let _ = writeln!(out, "Columns:");
    for (c, column) in layout.columns.iter().enumerate() {
        let (w, _) = column.view.size();
        let _ = writeln!(
            out,
            "  column {}: x {}-{}: {} {}",
            c + 1,
            column.x,
            column.x + w - 1,
            set_name(column.set, about.written),
            column.view.name()
        );
    }
    let _ = writeln!(out, "Rows:");
    for (r, (row, top)) in layout.rows.iter().enumerate() {
        let missing = if (about.has_own)(*row) {
            ""
        } else {
            " (own: missing on the avatar)"
        };
        let _ = writeln!(
            out,
            "  row {}: y {}-{}: {}{missing}",
            r + 1,
            top,
            top + layout.row_height - 1,
            row.name()
        );
    }
    let _ = writeln!(out, "Cells:");
    for (r, (row, _)) in layout.rows.iter().enumerate() {
        for (c, column) in layout.columns.iter().enumerate() {
            let (x, y) = layout.corner(r, column);
            let (w, h) = column.view.size();
            let _ = writeln!(
                out,
                "  row {} column {}: x {}-{}, y {}-{}: {} {} {} -> {}",
                r + 1,
                c + 1,
                x,
                x + w - 1,
                y,
                y + h - 1,
                row.name(),
                set_name(column.set, about.written),
                column.view.name(),
                tile_name(*row, column.set, column.view, about.written)
            );
        }
    }
    out
}

/// `index.html`: one table row per pose, each tile with its caption.
pub fn html(layout: &Layout, about: &About<'_>) -> String {
    let mut out = String::new();
    let _ = write!(
        out,
        "<!doctype html><html lang=\"en\"><head><meta charset=\"utf-8\">\
         <meta name=\"generator\" content=\"likeness avatar --preview\">\
         <title>Avatar preview: {avatar}</title><style>\
         body{{font-family:system-ui,sans-serif;margin:1.5em;color:#222}}\
         table{{border-collapse:collapse}}td,th{{padding:4px;vertical-align:middle;text-align:center}}\
         th.row{{text-align:right;font-family:monospace}}figure{{margin:0}}\
         figcaption{{font-size:12px;color:#555}}img{{background:#fff;border:1px solid #bbb}}\
         td.split{{border-left:3px solid #888}}</style></head><body>\
         <h1>Avatar preview: {avatar}</h1>\
         <p>Each shape alone at weight one: left, the avatar's own shape; right, the written one \
         (<b>{written}</b>: {means}). A crossed grey tile: the avatar has no target for that shape. \
         All of it in one picture: <a href=\"contact-sheet.png\">contact-sheet.png</a> \
         (its grid in <a href=\"contact-sheet.txt\">contact-sheet.txt</a>).</p><table><tr><th></th>",
        avatar = escape(about.avatar),
        written = escape(about.written),
        means = escape(about.written_means),
    );
    for column in &layout.columns {
        let _ = write!(
            out,
            "<th>{} {}</th>",
            escape(set_name(column.set, about.written)),
            column.view.name()
        );
    }
    out.push_str("</tr>");
    for (row, _) in &layout.rows {
        let _ = write!(out, "<tr><th class=\"row\">{}</th>", row.name());
        for (c, column) in layout.columns.iter().enumerate() {
            let (w, h) = column.view.size();
            let name = tile_name(*row, column.set, column.view, about.written);
            let caption = format!(
                "{} · {} · {}",
                row.name(),
                set_name(column.set, about.written),
                column.view.name()
            );
            let split = if c > 0 && column.set != layout.columns[c - 1].set {
                " class=\"split\""
            } else {
                ""
            };
            let _ = write!(
                out,
                "<td{split}><figure><img src=\"{name}\" width=\"{w}\" height=\"{h}\" alt=\"{caption}\">\
                 <figcaption>{caption}</figcaption></figure></td>",
                caption = escape(&caption)
            );
        }
        out.push_str("</tr>");
    }
    out.push_str("</table></body></html>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use likeness::Blendshape;

    #[test]
    fn every_cell_is_named_in_the_text_and_the_page() {
        let rows = [Row::Neutral, Row::Shape(Blendshape::JawOpen)];
        let layout = Layout::new(&rows);
        let has_own = |r: Row| r == Row::Neutral;
        let about = About {
            avatar: "a <b>.glb",
            written: "personalized",
            written_means: "the person's shapes",
            has_own: &has_own,
        };
        let text = text(&layout, &about);
        let page = html(&layout, &about);
        assert!(text.contains("row 2 column 6:"), "{text}");
        assert!(text.contains("jawOpen (own: missing on the avatar)"));
        assert!(text.contains("tiles/jawOpen-personalized-mouth.png"));
        assert!(page.contains("src=\"tiles/neutral-own-eyes.png\""));
        assert!(page.contains("a &lt;b&gt;.glb"));
        assert_eq!(page.matches("<img").count(), 12);
    }
}
