//! The one colour scale of the report's error maps: blue at 0 mm, through
//! cyan, green and yellow, to red at [`SCALE_MAX_MM`] and beyond (the
//! paper's Fig. 6: "Blue = 0mm, Red > 5mm").

/// The error (mm) at which, and beyond which, the scale is red.
pub const SCALE_MAX_MM: f64 = 5.0;

/// The scale's colours (sRGB), evenly spaced from 0 to [`SCALE_MAX_MM`]:
/// blue, cyan, green, yellow, red.
const STOPS: [[u8; 3]; 5] = [
    [0, 40, 255],
    [0, 200, 255],
    [40, 210, 60],
    [255, 220, 0],
    [255, 0, 0],
];

/// The colour of a surface with no error to show (the reference faces,
/// and avatar vertices outside the face region): a light skin tone.
pub const SKIN: [u8; 3] = [222, 196, 180];

/// The colour of parts drawn for orientation only (eyeballs, teeth).
pub const PALE: [u8; 3] = [236, 236, 232];

/// The colour of an error of `mm` millimetres: [`STOPS`] interpolated
/// linearly, red from [`SCALE_MAX_MM`] on, blue at or below zero; a value
/// that is not a number is drawn grey.
pub fn error_colour(mm: f64) -> [u8; 3] {
    if mm.is_nan() {
        return [128, 128, 128];
    }
    let segments = (STOPS.len() - 1) as f64;
    let at = (mm / SCALE_MAX_MM).clamp(0.0, 1.0) * segments;
    let i = (at.floor() as usize).min(STOPS.len() - 2);
    let t = at - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    [0, 1, 2].map(|c| (f64::from(a[c]) + (f64::from(b[c]) - f64::from(a[c])) * t).round() as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scale_runs_from_blue_to_red() {
        assert_eq!(error_colour(0.0), STOPS[0]);
        assert_eq!(error_colour(-1.0), STOPS[0]);
        assert_eq!(error_colour(SCALE_MAX_MM), [255, 0, 0]);
        assert_eq!(error_colour(40.0), [255, 0, 0]);
        assert_eq!(error_colour(2.5), STOPS[2]);
        assert_eq!(error_colour(f64::NAN), [128, 128, 128]);
    }
}
