//! The report's page: a self-contained HTML file (styles inline, no
//! scripts, no network) that links the images beside it. Numbers shown in
//! tables carry their full value in a `data-value` attribute, so that a
//! program reading the page gets exactly what the core computed.

use super::output::GENERATOR;
use std::fmt::Write;

/// `text` with `&`, `<`, `>` and `"` escaped.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(c),
        }
    }
    out
}

/// A table cell showing `value` with `decimals` decimals, its full value in
/// `data-value` and its meaning in `data-key`; `–` when there is none.
pub fn number_cell(key: &str, value: Option<f64>, decimals: usize) -> String {
    match value {
        Some(v) if v.is_finite() => format!(
            r#"<td class="num" data-key="{}" data-value="{v}">{v:.decimals$}</td>"#,
            escape(key)
        ),
        _ => format!(r#"<td class="num" data-key="{}">–</td>"#, escape(key)),
    }
}

/// An image of `width × height` pixels at `src` (relative to the page)
/// with a caption.
pub fn figure(src: &str, width: u32, height: u32, alt: &str, caption: &str) -> String {
    format!(
        r#"<figure><img src="{}" width="{width}" height="{height}" alt="{}"><figcaption>{caption}</figcaption></figure>"#,
        escape(src),
        escape(alt)
    )
}

/// A table with a header row; `rows` are already-built `<tr>` rows.
pub fn table(id: &str, header: &[&str], rows: &[String]) -> String {
    let mut out = format!(r#"<table id="{}"><thead><tr>"#, escape(id));
    for h in header {
        let _ = write!(out, "<th>{h}</th>");
    }
    out.push_str("</tr></thead><tbody>");
    for r in rows {
        out.push_str(r);
    }
    out.push_str("</tbody></table>");
    out
}

/// One section of the page: its anchor, title and body.
pub struct Section {
    /// The anchor (`#id`).
    pub id: &'static str,
    /// The heading.
    pub title: String,
    /// Its HTML.
    pub body: String,
}

/// The whole page: `title`, a short `intro`, a table of contents and the
/// sections, and `data` (a JSON text) embedded for programs to read.
pub fn page(title: &str, intro: &str, sections: &[Section], data: &str) -> String {
    let mut out = String::new();
    let _ = write!(
        out,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">{GENERATOR}\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
         <title>{}</title><style>{STYLE}</style></head><body><header><h1>{}</h1>{intro}<nav><ol>",
        escape(title),
        escape(title)
    );
    for s in sections {
        let _ = write!(out, "<li><a href=\"#{}\">{}</a></li>", s.id, s.title);
    }
    out.push_str("</ol></nav></header><main>");
    for s in sections {
        let _ = write!(
            out,
            "<section id=\"{}\"><h2>{}</h2>{}</section>",
            s.id, s.title, s.body
        );
    }
    // `</` cannot occur inside the JSON text (it is escaped below), so the
    // script element ends where it should.
    let _ = writeln!(
        out,
        "</main><script type=\"application/json\" id=\"likeness-data\">{}</script></body></html>",
        data.replace("</", "<\\/")
    );
    out
}

/// The page's styles: readable on a phone and on a desktop.
const STYLE: &str = "\
body{font-family:system-ui,-apple-system,'Segoe UI',sans-serif;margin:0;color:#222;background:#fafafa;line-height:1.45}\
header,main{max-width:1180px;margin:0 auto;padding:0 16px}\
h1{margin:24px 0 8px}h2{border-bottom:1px solid #ddd;padding-bottom:4px;margin-top:40px}\
nav ol{columns:2;padding-left:20px}\
figure{display:inline-table;margin:6px 10px 12px 0;vertical-align:top}\
figure img{max-width:100%;height:auto;border:1px solid #e4e4e4;background:#fff;display:block}\
figcaption{display:table-caption;caption-side:bottom;font-size:0.85em;color:#555;padding-top:2px}\
table{border-collapse:collapse;margin:8px 0 16px;font-size:0.9em}\
th,td{border:1px solid #ddd;padding:3px 8px;text-align:left}\
td.num{text-align:right;font-variant-numeric:tabular-nums}\
th{background:#f0f0f0}\
.row{display:flex;flex-wrap:wrap;align-items:flex-start}\
.grid{display:flex;flex-wrap:wrap}\
.grid figure{margin:4px 6px 8px 0}.grid figcaption{font-size:0.75em}\
.note{color:#555;font-size:0.9em}\
.flag{color:#b35900}.bad{color:#c0392b}";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_keep_the_full_value_and_escape_text() {
        assert_eq!(escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
        let cell = number_cell("rmse_mm", Some(0.123456789), 3);
        assert!(cell.contains(r#"data-value="0.123456789""#) && cell.contains(">0.123<"));
        assert!(number_cell("x", None, 3).contains("–"));
    }

    #[test]
    fn the_page_marks_itself_and_embeds_the_data() {
        let page = page(
            "T",
            "<p>i</p>",
            &[Section {
                id: "a",
                title: "A".into(),
                body: "<p>b</p>".into(),
            }],
            r#"{"x":"</script>"}"#,
        );
        assert!(page.contains(GENERATOR));
        assert!(page.contains(r#"<section id="a"><h2>A</h2><p>b</p></section>"#));
        assert!(page.contains(r#"{"x":"<\/script>"}"#));
    }
}
