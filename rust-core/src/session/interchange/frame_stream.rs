//! `frames.csv`: the weight stream, as a Live Link Face export or as
//! `timestamp,<52 names>`.

use super::*;
use crate::session::Frame;
use crate::session::file::MAX_DURATION_SECONDS;

/// Most digits in one part of a Live Link timecode: nine digits keep every
/// value exact in an `f64` and finite (a 309-digit hour is infinite).
const MAX_TIMECODE_DIGITS: usize = 9;

/// Reads a weight stream: a Live Link Face CSV export (`Timecode`,
/// `BlendshapeCount`, the 52 capitalized names; head and eye rotation
/// columns are ignored) or `timestamp,<52 names>`. Frames carry no mesh and
/// count as tracked. Live Link timecodes become seconds after the first
/// row (which is at 0 s); `timestamp` values are kept as written, in
/// seconds, and must not go back. A stream longer than
/// [`MAX_DURATION_SECONDS`] is refused at the first row past it.
pub fn read_frames(path: &Path) -> Result<Vec<Frame>, InterchangeError> {
    let table = read_weight_table(path, &["timestamp", "timecode"])?;
    let live_link = table.key_name.eq_ignore_ascii_case("timecode");
    let key_error = |row: &weights_csv::WeightRow, message: String| InterchangeError::Key {
        path: path.to_path_buf(),
        line: row.line,
        column: row.key_column,
        message,
    };
    let mut times = Vec::with_capacity(table.rows.len());
    if live_link {
        let mut parsed = Vec::with_capacity(table.rows.len());
        for row in &table.rows {
            parsed.push(parse_timecode(&row.key).ok_or_else(|| {
                let message = format!(
                    "{} is not a timecode HH:MM:SS:FF[.fff] (at most {MAX_TIMECODE_DIGITS} digits a part)",
                    Excerpt::of(&row.key)
                );
                key_error(row, message)
            })?);
        }
        let max_frame = parsed.iter().map(|t| t.1).fold(0.0, f64::max);
        let rate = [24.0, 25.0, 30.0, 48.0, 50.0, 60.0, 120.0]
            .into_iter()
            .find(|r| max_frame < *r)
            .unwrap_or(max_frame.floor() + 1.0);
        let start = parsed.first().map(|t| t.0 + t.1 / rate).unwrap_or(0.0);
        times.extend(parsed.iter().map(|t| t.0 + t.1 / rate - start));
    } else {
        for row in &table.rows {
            let t = row
                .key
                .parse::<f64>()
                .ok()
                .filter(|t| t.is_finite())
                .ok_or_else(|| {
                    let message =
                        format!("timestamp {} is not a finite number", Excerpt::of(&row.key));
                    key_error(row, message)
                })?;
            times.push(t);
        }
    }
    let mut frames = Vec::with_capacity(times.len());
    let first = times.first().copied().unwrap_or(0.0);
    for (k, (row, t)) in table.rows.iter().zip(times).enumerate() {
        if k > 0 && t < frames.last().map(|f: &Frame| f.timestamp).unwrap_or(t) {
            return Err(key_error(
                row,
                format!("time {t} s is earlier than the row before"),
            ));
        }
        if t - first > MAX_DURATION_SECONDS {
            let message = format!(
                "time {t} s is more than the limit of {MAX_DURATION_SECONDS} s (ten minutes) after the first row"
            );
            return Err(key_error(row, message));
        }
        frames.push(Frame {
            timestamp: t,
            weights: row.weights,
            tracked: true,
            vertices: None,
        });
    }
    Ok(frames)
}

/// `HH:MM:SS:FF[.fff]` → (whole seconds, frames including the fraction).
pub(super) fn parse_timecode(text: &str) -> Option<(f64, f64)> {
    let parts: Vec<&str> = text.split(':').collect();
    let [h, m, s, f] = parts.as_slice() else {
        return None;
    };
    let int = |x: &str| -> Option<f64> {
        let digits = !x.is_empty() && x.len() <= MAX_TIMECODE_DIGITS;
        (digits && x.bytes().all(|b| b.is_ascii_digit())).then(|| x.parse().ok())?
    };
    let (h, m, s) = (int(h)?, int(m)?, int(s)?);
    if m >= 60.0 || s >= 61.0 {
        return None;
    }
    let (whole, fraction) = f.split_once('.').unwrap_or((f, ""));
    let frames = int(whole)?
        + if fraction.is_empty() {
            0.0
        } else {
            int(fraction)? / 10f64.powi(fraction.len() as i32)
        };
    Some((h * 3600.0 + m * 60.0 + s, frames))
}

/// One over the median spacing of the timestamps, or [`DEFAULT_FRAME_RATE`].
pub(super) fn frame_rate(frames: &[Frame]) -> f32 {
    // Indexing: windows of two, and a median taken only of a non-empty list.
    let mut spacing: Vec<f64> = frames
        .windows(2)
        .map(|w| w[1].timestamp - w[0].timestamp)
        .filter(|d| *d > 0.0)
        .collect();
    if spacing.is_empty() {
        return DEFAULT_FRAME_RATE;
    }
    spacing.sort_by(f64::total_cmp);
    let n = spacing.len();
    let median = if n % 2 == 1 {
        spacing[n / 2]
    } else {
        0.5 * (spacing[n / 2 - 1] + spacing[n / 2])
    };
    let rate = (1.0 / median) as f32;
    if rate.is_finite() && rate > 0.0 {
        rate
    } else {
        DEFAULT_FRAME_RATE
    }
}
