//! Plain CSV tables of blendshape weights.
//!
//! The CSV dialect is the plain one: fields separated by commas, spaces
//! around a field ignored, no quoting. A UTF-8 byte-order mark and CRLF line
//! ends are accepted; blank lines are skipped. The first non-blank line is
//! the header.
//!
//! A weight table has one key column (`prompt`, `id`, `timestamp`, or Live
//! Link Face's `Timecode`) and one column per ARKit blendshape, in any order,
//! named in any spelling [`Blendshape::parse`] accepts. Each of the 52 must
//! appear exactly once. In a Live Link Face table (one with a `Timecode`
//! column) the `BlendshapeCount` column and the nine head and eye rotation
//! columns are ignored; any other unknown column is an error.
//!
//! A table is read one line at a time and each row becomes its 52 weights
//! at once, within [`CSV_LIMITS`] (64 MiB, lines of 16 KiB) and
//! [`MAX_ROWS`] rows.

use super::InterchangeError;
use crate::arkit::{BLENDSHAPE_COUNT, Blendshape, Weights};
use crate::io::{Excerpt, TextLimits, TextLines, open_text};
use crate::session::file::MAX_FRAMES;
use std::io::BufRead;
use std::path::Path;

/// The size of a CSV file and of its lines: a row of a Live Link Face take
/// is about 700 bytes (61 cells), so ten minutes at 60 fps is about 25 MB;
/// 64 MiB and lines of 16 KiB (over 20 times a row) leave room for wider
/// spellings.
pub const CSV_LIMITS: TextLimits = TextLimits {
    max_bytes: 64 << 20,
    max_line: 16 << 10,
    what: "a CSV file",
};

/// Most data rows in a table: a frame stream may have
/// [`MAX_FRAMES`] (ten minutes at 60 fps); weight tables have far fewer.
pub const MAX_ROWS: usize = MAX_FRAMES;

/// How far outside `[0, 1]` a weight may lie and still be accepted: ARKit
/// and Live Link Face occasionally report values a rounding error outside the
/// range. Accepted values are kept as they are, not clamped.
pub const WEIGHT_TOLERANCE: f32 = 1e-3;

/// Live Link Face columns that are not blendshape weights (compared
/// case-insensitively), ignored in a table with a `Timecode` column.
const LIVE_LINK_EXTRA: [&str; 10] = [
    "blendshapecount",
    "headyaw",
    "headpitch",
    "headroll",
    "lefteyeyaw",
    "lefteyepitch",
    "lefteyeroll",
    "righteyeyaw",
    "righteyepitch",
    "righteyeroll",
];

/// One data row of a weight table.
#[derive(Clone, Debug, PartialEq)]
pub struct WeightRow {
    /// 1-based line number in the file.
    pub line: usize,
    /// 1-based column number of the key cell.
    pub key_column: usize,
    /// The key cell, trimmed.
    pub key: String,
    /// The 52 weights.
    pub weights: Weights,
}

/// A parsed weight table.
#[derive(Clone, Debug, PartialEq)]
pub struct WeightTable {
    /// The key column's header, as spelled in the file (e.g. `Timecode`).
    pub key_name: String,
    /// The data rows in file order.
    pub rows: Vec<WeightRow>,
}

/// The fields of a CSV line, trimmed.
fn fields(line: &str) -> impl Iterator<Item = &str> {
    line.split(',').map(str::trim)
}

/// Reads the weight table at `path`, whose key column is one of `keys`
/// (compared case-insensitively), one line at a time.
pub fn read_weight_table(path: &Path, keys: &[&str]) -> Result<WeightTable, InterchangeError> {
    parse_lines(open_text(path, CSV_LIMITS)?, keys)
}

/// What the header says: where the key is and which shape each column holds.
///
/// Indexing: `columns` has one entry per name and `key_column` is the
/// position of one of them (both built in [`parse_header`]); [`parse_row`]
/// checks that a row has as many fields before indexing any, so column
/// indices fit the names and the fields alike.
struct Header {
    /// The header cells, trimmed.
    names: Vec<String>,
    /// 0-based column of the key.
    key_column: usize,
    /// The shape of each column (`None`: the key or an ignored column).
    columns: Vec<Option<Blendshape>>,
}

/// Parses weight-table text; `path` only names the file in errors.
pub fn parse_weight_table(
    path: &Path,
    text: &str,
    keys: &[&str],
) -> Result<WeightTable, InterchangeError> {
    parse_lines(TextLines::new(text.as_bytes(), path, CSV_LIMITS), keys)
}

/// The header first (`parse_header`), then each row against it as it is
/// read (`parse_row`); blank lines are skipped.
fn parse_lines<R: BufRead>(
    mut lines: TextLines<R>,
    keys: &[&str],
) -> Result<WeightTable, InterchangeError> {
    let path = lines.path().to_path_buf();
    let mut header = None;
    let mut rows = Vec::new();
    while let Some((line, text)) = lines.next_line()? {
        if text.trim().is_empty() {
            continue;
        }
        let Some(header) = &header else {
            let names = fields(text).map(str::to_string).collect();
            header = Some(parse_header(&path, line, names, keys)?);
            continue;
        };
        if rows.len() == MAX_ROWS {
            return Err(InterchangeError::TooManyRows {
                path,
                line,
                limit: MAX_ROWS,
            });
        }
        let cells: Vec<&str> = fields(text).collect();
        rows.push(parse_row(&path, header, line, &cells)?);
    }
    let Some(header) = header else {
        return Err(InterchangeError::MissingColumn {
            path,
            name: keys.join(" or "),
        });
    };
    Ok(WeightTable {
        key_name: header.names[header.key_column].clone(),
        rows,
    })
}

/// The header: exactly one key column (one of `keys`), each of the 52
/// shapes exactly once, Live Link Face's extra columns ignored in a table
/// with a `Timecode`, nothing else.
fn parse_header(
    path: &Path,
    header_line: usize,
    names: Vec<String>,
    keys: &[&str],
) -> Result<Header, InterchangeError> {
    let file = || path.to_path_buf();
    let live_link = names.iter().any(|h| h.eq_ignore_ascii_case("timecode"));
    let mut key_column = None;
    let mut columns: Vec<Option<Blendshape>> = Vec::with_capacity(names.len());
    // Indexed by `Blendshape::index()`, always below BLENDSHAPE_COUNT.
    let mut first_seen = [None::<usize>; BLENDSHAPE_COUNT];
    for (c, name) in names.iter().enumerate() {
        let column = c + 1;
        if keys.iter().any(|k| k.eq_ignore_ascii_case(name)) {
            if let Some(first) = key_column {
                return Err(InterchangeError::DuplicateColumn {
                    path: file(),
                    line: header_line,
                    column,
                    name: Excerpt::of(name),
                    first: first + 1,
                });
            }
            key_column = Some(c);
            columns.push(None);
            continue;
        }
        if live_link && LIVE_LINK_EXTRA.iter().any(|k| k.eq_ignore_ascii_case(name)) {
            columns.push(None);
            continue;
        }
        let shape = Blendshape::parse(name).map_err(|_| InterchangeError::UnknownColumn {
            path: file(),
            line: header_line,
            column,
            name: Excerpt::of(name),
        })?;
        if let Some(first) = first_seen[shape.index()] {
            return Err(InterchangeError::DuplicateColumn {
                path: file(),
                line: header_line,
                column,
                name: Excerpt::of(name),
                first,
            });
        }
        first_seen[shape.index()] = Some(column);
        columns.push(Some(shape));
    }
    let Some(key_column) = key_column else {
        return Err(InterchangeError::MissingColumn {
            path: file(),
            name: keys.join(" or "),
        });
    };
    if let Some(missing) = Blendshape::ALL
        .iter()
        .find(|s| first_seen[s.index()].is_none())
    {
        return Err(InterchangeError::MissingColumn {
            path: file(),
            name: missing.name().to_string(),
        });
    }
    Ok(Header {
        names,
        key_column,
        columns,
    })
}

/// One data row: as many fields as the header, every weight a finite number
/// within [`WEIGHT_TOLERANCE`] of `[0, 1]`.
fn parse_row(
    path: &Path,
    header: &Header,
    line: usize,
    fields: &[&str],
) -> Result<WeightRow, InterchangeError> {
    if fields.len() != header.names.len() {
        return Err(InterchangeError::FieldCount {
            path: path.to_path_buf(),
            line,
            expected: header.names.len(),
            found: fields.len(),
        });
    }
    let mut weights = Weights::ZERO;
    for (c, (cell, shape)) in fields.iter().zip(&header.columns).enumerate() {
        let Some(shape) = *shape else { continue };
        let value = cell
            .parse::<f32>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| InterchangeError::NotANumber {
                path: path.to_path_buf(),
                line,
                column: c + 1,
                name: header.names[c].clone(),
                value: Excerpt::of(cell),
            })?;
        if !(-WEIGHT_TOLERANCE..=1.0 + WEIGHT_TOLERANCE).contains(&value) {
            return Err(InterchangeError::WeightRange {
                path: path.to_path_buf(),
                line,
                column: c + 1,
                name: header.names[c].clone(),
                value,
            });
        }
        weights.set(shape, value);
    }
    Ok(WeightRow {
        line,
        key_column: header.key_column + 1,
        key: fields[header.key_column].to_string(),
        weights,
    })
}

/// The text of a weight table: header `key,<52 ARKit names>` and one row per
/// entry, weights printed with Rust's shortest round-tripping notation.
pub fn weight_table_text<'a>(
    key: &str,
    rows: impl IntoIterator<Item = (String, &'a Weights)>,
) -> String {
    let mut out = String::from(key);
    for shape in Blendshape::ALL {
        out.push(',');
        out.push_str(shape.name());
    }
    out.push('\n');
    for (k, weights) in rows {
        out.push_str(&k);
        for (_, w) in weights.iter() {
            out.push(',');
            out.push_str(&format!("{w:?}"));
        }
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(key: &str) -> String {
        let names: Vec<_> = Blendshape::ALL.iter().map(|s| s.name()).collect();
        format!("{key},{}", names.join(","))
    }

    fn row(key: &str, value: &str) -> String {
        format!("{key}{}", format!(",{value}").repeat(BLENDSHAPE_COUNT))
    }

    #[test]
    fn round_trips_weights_exactly_with_bom_crlf_and_spaces() {
        let mut w = Weights::ZERO;
        w.set(Blendshape::JawOpen, 0.123_456_79);
        w.set(Blendshape::TongueOut, 1.0);
        let text = weight_table_text("prompt", [("jawOpen".to_string(), &w)]);
        let messy = format!("\u{feff}{}", text.replace(',', " , ").replace('\n', "\r\n"));
        for t in [text, messy] {
            let table = parse_weight_table(Path::new("w.csv"), &t, &["prompt"]).unwrap();
            assert_eq!(table.rows.len(), 1);
            assert_eq!(table.rows[0].line, 2);
            assert_eq!(table.rows[0].key, "jawOpen");
            assert_eq!(table.rows[0].weights, w);
        }
    }

    #[test]
    fn bad_tables_name_file_line_and_column() {
        let p = Path::new("x/w.csv");
        let parse = |t: &str| {
            parse_weight_table(p, t, &["prompt"])
                .unwrap_err()
                .to_string()
        };
        let h = header("prompt");
        let mut bad_row = row("a", "0");
        bad_row = bad_row.replacen(",0,0", ",0,zero", 1);
        let bad_cell = format!("{h}\n{}\n{bad_row}", row("jawOpen", "0"));
        let m = parse(&bad_cell);
        assert!(
            m.starts_with("x/w.csv:3: column 3 (eyeLookDownLeft)"),
            "{m}"
        );
        let m = parse(&format!("{h}\n{}", row("a", "NaN")));
        assert!(m.starts_with("x/w.csv:2: column 2 (eyeBlinkLeft)"), "{m}");
        let m = parse(&format!("{h}\n{}", row("a", "1.002")));
        assert!(
            m.contains("x/w.csv:2: column 2") && m.contains("outside"),
            "{m}"
        );
        assert!(
            parse_weight_table(p, &format!("{h}\n{}", row("a", "1.0009")), &["prompt"]).is_ok()
        );
        let m = parse(&format!("{h},EyeBlinkLeft\n"));
        assert!(m.starts_with("x/w.csv:1: column 54"), "{m}");
        assert!(m.contains("duplicate"), "{m}");
        let m = parse(&format!("{h},HeadYaw\n"));
        assert!(
            m.starts_with("x/w.csv:1: column 54") && m.contains("unknown"),
            "{m}"
        );
        let m = parse(&h.replace(",tongueOut", ""));
        assert!(m.starts_with("x/w.csv: ") && m.contains("tongueOut"), "{m}");
        let m = parse(&h.replace("prompt,", "name,"));
        assert!(
            m.contains("x/w.csv:1: column 1") && m.contains("unknown"),
            "{m}"
        );
        let m = parse(&h.replace("prompt,", ""));
        assert!(m.starts_with("x/w.csv: ") && m.contains("prompt"), "{m}");
        let m = parse(&format!("{h}\njawOpen,0\n"));
        assert!(
            m.starts_with("x/w.csv:2: ") && m.contains("2 fields"),
            "{m}"
        );
    }

    #[test]
    fn rows_with_missing_or_extra_fields_are_errors() {
        let p = Path::new("w.csv");
        let h = header("prompt");
        let full = row("jawOpen", "0");
        let short = full.rsplit_once(',').unwrap().0.to_string();
        for (text, fields) in [
            (format!("{h}\n{short}"), 52),
            (format!("{h}\n{full},0"), 54),
            (format!("{h}\njawOpen"), 1),
            (format!("{h}\n,"), 2),
            (format!("{h}\n{full}\n{short}"), 52),
        ] {
            let err = parse_weight_table(p, &text, &["prompt"]).unwrap_err();
            assert!(
                matches!(err, InterchangeError::FieldCount { found, .. } if found == fields),
                "{err}"
            );
        }
        // An empty file or a key column alone have no header to speak of.
        for text in ["", "\n\n", "prompt\n"] {
            assert!(matches!(
                parse_weight_table(p, text, &["prompt"]),
                Err(InterchangeError::MissingColumn { .. })
            ));
        }
        assert!(
            parse_weight_table(p, &h, &["prompt"])
                .unwrap()
                .rows
                .is_empty()
        );
    }
}
