//! The contact sheet: every tile in one picture, a row per pose and a
//! column per set and view (the avatar's own front, eyes, mouth, then the
//! written ones), on a grey ground so each tile's white edge shows; each
//! row's pose written on its left, each column's set and view above it.

use super::font::{GLYPH, draw_text, text_size};
use super::tiles::{Row, Set, View};
use crate::report::image::Image;

/// Text is drawn with each font pixel this many pixels wide.
pub const TEXT_SCALE: u32 = 2;

/// The text's colour.
pub const INK: [u8; 3] = [20, 20, 20];

/// The width of the rows' labels (the longest pose name fits).
pub const LABEL_WIDTH: u32 = 220;

/// The height of one line of text with room above and below.
pub const LINE: u32 = GLYPH.1 * TEXT_SCALE + 8;

/// The headings' height: the set, then the view.
pub const HEADER: u32 = 2 * LINE;

/// Pixels between tiles and around the sheet.
pub const GAP: u32 = 4;

/// Extra pixels between the own and the written half of the sheet.
pub const HALF_GAP: u32 = 12;

/// The sheet's ground.
pub const GROUND: [u8; 3] = [160, 160, 160];

/// The sets, in the sheet's order.
pub const SETS: [Set; 2] = [Set::Own, Set::Written];

/// One column: whose shapes, which view, where it starts and how wide.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Column {
    /// Whose shapes.
    pub set: Set,
    /// Which view.
    pub view: View,
    /// Its left edge in pixels.
    pub x: u32,
}

/// Where every tile goes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// The columns, left to right.
    pub columns: Vec<Column>,
    /// The rows, top to bottom, each with its top edge.
    pub rows: Vec<(Row, u32)>,
    /// The height of every row (the tallest view).
    pub row_height: u32,
    /// The sheet's size.
    pub size: (u32, u32),
}

impl Layout {
    /// The layout of `rows`.
    pub fn new(rows: &[Row]) -> Layout {
        let mut columns = Vec::new();
        let mut x = GAP + LABEL_WIDTH + GAP;
        for (i, set) in SETS.into_iter().enumerate() {
            if i > 0 {
                x += HALF_GAP;
            }
            for view in View::ALL {
                columns.push(Column { set, view, x });
                x += view.size().0 + GAP;
            }
        }
        let row_height = View::ALL.iter().map(|v| v.size().1).max().unwrap_or(0);
        let rows: Vec<(Row, u32)> = rows
            .iter()
            .enumerate()
            .map(|(i, r)| (*r, HEADER + GAP + i as u32 * (row_height + GAP)))
            .collect();
        let height = HEADER + GAP + rows.len() as u32 * (row_height + GAP);
        Layout {
            columns,
            rows,
            row_height,
            size: (x, height),
        }
    }

    /// The top left corner of the tile of `column` in row `row` (an index
    /// into `rows`): tiles shorter than the row sit in its middle.
    pub fn corner(&self, row: usize, column: &Column) -> (u32, u32) {
        let top = self.rows[row].1 + (self.row_height - column.view.size().1) / 2;
        (column.x, top)
    }
}

/// The sheet: `tile(row, column)` for every cell of `layout`, the rows
/// and columns labelled; `set_name` names a set.
pub fn contact_sheet(
    layout: &Layout,
    set_name: &dyn Fn(Set) -> String,
    tile: &dyn Fn(usize, &Column) -> Image,
) -> Image {
    let mut sheet = Image::filled(layout.size.0, layout.size.1, GROUND);
    let text_top = |line: u32| line * LINE + (LINE - GLYPH.1 * TEXT_SCALE) / 2;
    for set in SETS {
        let columns: Vec<&Column> = layout.columns.iter().filter(|c| c.set == set).collect();
        if let (Some(first), Some(last)) = (columns.first(), columns.last()) {
            let right = last.x + last.view.size().0;
            let name = set_name(set);
            let (w, _) = text_size(&name, TEXT_SCALE);
            let left = (first.x + right).saturating_sub(w) / 2;
            draw_text(&mut sheet, &name, left, text_top(0), TEXT_SCALE, INK);
        }
    }
    for column in &layout.columns {
        let name = column.view.name();
        let (w, _) = text_size(name, TEXT_SCALE);
        let left = column.x + column.view.size().0.saturating_sub(w) / 2;
        draw_text(&mut sheet, name, left, text_top(1), TEXT_SCALE, INK);
    }
    for (row, (pose, top)) in layout.rows.iter().enumerate() {
        let (_, h) = text_size(&pose.name(), TEXT_SCALE);
        let y = top + (layout.row_height - h) / 2;
        draw_text(&mut sheet, &pose.name(), GAP, y, TEXT_SCALE, INK);
        for column in &layout.columns {
            let (x, y) = layout.corner(row, column);
            sheet.place(&tile(row, column), x, y);
        }
    }
    sheet
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_do_not_overlap_and_fit_the_sheet() {
        let layout = Layout::new(&Row::all());
        assert_eq!(layout.columns.len(), 6);
        for pair in layout.columns.windows(2) {
            assert!(pair[0].x + pair[0].view.size().0 < pair[1].x);
        }
        let last = layout.columns.last().unwrap();
        assert!(last.x + last.view.size().0 < layout.size.0);
        let (_, top) = *layout.rows.last().unwrap();
        assert!(top + layout.row_height < layout.size.1);
        assert!(layout.columns[0].x > LABEL_WIDTH && layout.rows[0].1 >= HEADER);
    }

    #[test]
    fn the_labels_fit_their_room() {
        for row in Row::all() {
            assert!(
                text_size(&row.name(), TEXT_SCALE).0 <= LABEL_WIDTH,
                "{row:?}"
            );
        }
        for view in View::ALL {
            assert!(text_size(view.name(), TEXT_SCALE).0 <= view.size().0);
        }
    }

    #[test]
    fn the_sheet_has_its_tiles_and_its_labels() {
        let rows = [Row::Neutral];
        let layout = Layout::new(&rows);
        let tile = |_: usize, c: &Column| {
            let (w, h) = c.view.size();
            Image::filled(w, h, [255, 0, 0])
        };
        let sheet = contact_sheet(&layout, &|_| "own".to_string(), &tile);
        assert_eq!((sheet.width, sheet.height), layout.size);
        let (x, y) = layout.corner(0, &layout.columns[0]);
        assert_eq!(sheet.pixels[(y * sheet.width + x) as usize], [255, 0, 0]);
        let label_room = (0..layout.rows[0].1 * sheet.width)
            .map(|i| sheet.pixels[i as usize])
            .filter(|p| *p == INK)
            .count();
        assert!(label_room > 0, "headings drawn");
    }
}
