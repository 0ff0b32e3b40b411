//! The contact sheet: every tile in one picture, a row per pose and a
//! column per set and view (the avatar's own front, eyes, mouth, then the
//! written ones), on a grey ground so each tile's white edge shows.

use super::tiles::{Row, Set, View};
use crate::report::image::Image;

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
        let mut x = GAP;
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
            .map(|(i, r)| (*r, GAP + i as u32 * (row_height + GAP)))
            .collect();
        let height = GAP + rows.len() as u32 * (row_height + GAP);
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

/// The sheet: `tile(row, column)` for every cell of `layout`.
pub fn contact_sheet(layout: &Layout, tile: &dyn Fn(usize, &Column) -> Image) -> Image {
    let mut sheet = Image::filled(layout.size.0, layout.size.1, GROUND);
    for row in 0..layout.rows.len() {
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
    }
}
